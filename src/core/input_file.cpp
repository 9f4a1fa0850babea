#include "shvol/core/input_file.h"

#include <filesystem>

#include "shvol/core/error.h"

namespace shvol {

std::string inputFileProblem(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (st.type() == fs::file_type::not_found) return "no such file";
    if (ec) return "cannot read file (" + ec.message() + ")";
    if (!fs::is_regular_file(st)) return "not a regular file";
    return "";
}

uintmax_t regularFileSize(const std::string& path) {
    const std::string problem = inputFileProblem(path);
    if (!problem.empty()) fail(path, "", problem);
    std::error_code ec;
    const uintmax_t bytes = std::filesystem::file_size(path, ec);
    if (ec) fail(path, "", "cannot read file (" + ec.message() + ")");
    return bytes;
}

}  // namespace shvol
