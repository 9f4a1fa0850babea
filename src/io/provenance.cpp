#include "shvol/io/provenance.h"

#include <sys/utsname.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <thread>

#include "shvol/core/error.h"
#include "shvol/core/hash.h"

namespace shvol {

namespace fs = std::filesystem;

namespace {

/// fileFingerprint(path) with its "key" and absolute "path", read through `memo` when given.
Json namedFingerprint(const fs::path& p, const std::string& key,
                      std::map<std::string, Json>* memo) {
    const std::string path = p.lexically_normal().string();
    Json e;
    try {
        if (!memo) {
            e = fileFingerprint(path);
        } else {
            auto it = memo->find(path);
            if (it == memo->end()) it = memo->emplace(path, fileFingerprint(path)).first;
            e = it->second;
        }
    } catch (const Error& err) {  // the file's own line, and which key named it
        throw Error(std::string(err.what()) + " (named by " + key + ")");
    }
    e["key"] = key;
    e["path"] = fs::absolute(p).lexically_normal().string();
    return e;
}

void collectFiles(const Json& j, const std::string& path, const fs::path& dir, Json& out,
                  std::map<std::string, Json>* memo) {
    if (j.is_object()) {
        for (auto it = j.begin(); it != j.end(); ++it) {
            const std::string key = path.empty() ? it.key() : path + "." + it.key();
            if (it.key() == "file" && it.value().is_string()) {
                fs::path p(it.value().get<std::string>());
                if (p.is_relative()) p = dir / p;
                out.push_back(namedFingerprint(p, key, memo));
            } else {
                collectFiles(it.value(), key, dir, out, memo);
            }
        }
    } else if (j.is_array()) {
        for (size_t i = 0; i < j.size(); ++i)
            collectFiles(j[i], path + "[" + std::to_string(i) + "]", dir, out, memo);
    }
}

}  // namespace

Json fileFingerprint(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) fail(path, "", "cannot open file");
    uint64_t h = kFnv1aOffset, bytes = 0;
    char buf[1 << 16];
    while (f.read(buf, sizeof buf) || f.gcount() > 0) {
        h = fnv1a(buf, size_t(f.gcount()), h);
        bytes += uint64_t(f.gcount());
    }
    return {{"bytes", bytes}, {"fnv1a64", hexHash(h)}};
}

Json inputFiles(const Json& doc, const std::string& scenePath, std::map<std::string, Json>* memo) {
    Json out = Json::array();
    out.push_back(namedFingerprint(scenePath, "(scene)", memo));
    collectFiles(doc, "", fs::path(scenePath).parent_path(), out, memo);
    return out;
}

std::string namedFileContents(const Json& inputs) {
    std::string text;
    for (const Json& f : inputs)
        if (f.at("key") != "(scene)")
            text +=
                f.at("key").get<std::string>() + " " + f.at("fnv1a64").get<std::string>() + "\n";
    return text;
}

std::string commandLine() {
    std::ifstream f("/proc/self/cmdline", std::ios::binary);
    std::string all((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>()), line;
    size_t start = 0;
    while (start < all.size()) {
        const size_t end = all.find('\0', start);
        const std::string arg = all.substr(start, end - start);
        if (!line.empty()) line += ' ';
        const bool plain =
            !arg.empty() && arg.find_first_not_of(
                                "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                "0123456789_./=:,+-@%") == std::string::npos;
        if (plain) {
            line += arg;
        } else {  // single-quote it, each ' as '\''
            line += '\'';
            for (char c : arg) line += c == '\'' ? std::string("'\\''") : std::string(1, c);
            line += '\'';
        }
        if (end == std::string::npos) break;
        start = end + 1;
    }
    return line;
}

Json machineDescription() {
    Json m;
    std::ifstream cpu("/proc/cpuinfo");
    for (std::string line; std::getline(cpu, line);)
        if (line.rfind("model name", 0) == 0) {
            const auto colon = line.find(':');
            m["cpu"] = colon == std::string::npos ? line : line.substr(colon + 2);
            break;
        }
    m["hardware_threads"] = std::thread::hardware_concurrency();
    utsname u{};
    if (uname(&u) == 0) {
        m["os"] = std::string(u.sysname) + " " + u.release + " " + u.machine;
        m["host"] = u.nodename;
    }
    return m;
}

}  // namespace shvol
