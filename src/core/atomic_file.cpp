#include "shvol/core/atomic_file.h"

#include <unistd.h>

#include <cstdio>
#include <fstream>

#include "shvol/core/error.h"

namespace shvol {

void writeAtomically(const std::string& path,
                     const std::function<void(const std::string&)>& write) {
    const std::string tmp = path + ".tmp" + std::to_string(::getpid());
    try {
        write(tmp);
    } catch (...) {
        std::remove(tmp.c_str());
        throw;
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        std::remove(tmp.c_str());
        fail(path, "", "cannot write file");
    }
}

void writeTextAtomically(const std::string& path, const std::string& text) {
    writeAtomically(path, [&](const std::string& tmp) {
        std::ofstream f(tmp, std::ios::binary);
        f << text;
        f.close();
        if (!f) fail(path, "", "cannot write file");
    });
}

}  // namespace shvol
