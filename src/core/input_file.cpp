#include "shvol/core/input_file.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <utility>

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

const char* fileKindByMagic(const std::string& start) {
    static const std::pair<std::string, const char*> kinds[] = {
        {" BDV", "an OpenVDB grid"},
        {"\x76\x2f\x31\x01", "an OpenEXR image"},
        {"ply\n", "a PLY mesh"},
        {"ply\r\n", "a PLY mesh"},
        {"\x89PNG\r\n", "a PNG image"}};
    for (const auto& [magic, kind] : kinds)
        if (start.compare(0, magic.size(), magic) == 0) return kind;
    return nullptr;
}

const char* fileKindOfStart(const std::string& start) {
    if (const char* kind = fileKindByMagic(start)) return kind;
    // (after a UTF-8 byte order mark and blanks)
    const size_t first = start.find_first_not_of(" \t\r\n", utf8BomLength(start));
    return first != std::string::npos && (start[first] == '{' || start[first] == '[') ? "JSON text"
                                                                                      : nullptr;
}

const char* fileKindOfFile(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    std::string start(256, '\0');
    f.read(&start[0], std::streamsize(start.size()));
    start.resize(size_t(std::max<std::streamsize>(f.gcount(), 0)));
    return fileKindOfStart(start);
}

std::string fileOfAnotherKind(const std::string& path, const std::string& wanted) {
    const char* kind = fileKindOfFile(path);
    return kind && kind != wanted ? std::string("the file is ") + kind + ", not " + wanted : "";
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
