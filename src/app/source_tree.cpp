#include <filesystem>

#include "commands.h"

namespace shvol::app {

std::string sourceTreePath(const std::string& relative) {
    namespace fs = std::filesystem;
    std::error_code ec;
    // The program's own tree first (build/shvol → ./), then the tree it was built from (a copy
    // of the program elsewhere).
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec && fs::exists(exe.parent_path().parent_path() / relative, ec))
        return (exe.parent_path().parent_path() / relative).string();
    const fs::path built = fs::path(SHVOL_SOURCE_DIR) / relative;
    return fs::exists(built, ec) ? built.string() : "";
}

}  // namespace shvol::app
