#include "shvol/core/input_file.h"

#include <filesystem>

#include "shvol/core/error.h"

namespace shvol {

uintmax_t regularFileSize(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (st.type() == fs::file_type::not_found) fail(path, "", "file not found");
    if (ec) fail(path, "", "cannot read file (" + ec.message() + ")");
    if (!fs::is_regular_file(st)) fail(path, "", "not a regular file");
    const uintmax_t bytes = fs::file_size(path, ec);
    if (ec) fail(path, "", "cannot read file (" + ec.message() + ")");
    return bytes;
}

}  // namespace shvol
