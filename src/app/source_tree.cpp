#include <filesystem>

#include "commands.h"

namespace shvol::app {

std::string sourceTreePath(const std::string& relative) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (ec) return "";
    const fs::path p = exe.parent_path().parent_path() / relative;
    return fs::exists(p) ? p.string() : "";
}

}  // namespace shvol::app
