#include "shvol/io/checkpoint.h"

#include <cstring>
#include <fstream>
#include <iterator>

#include "shvol/core/atomic_file.h"
#include "shvol/core/error.h"
#include "shvol/core/hash.h"
#include "shvol/core/input_file.h"
#include "shvol/io/json_reader.h"

namespace shvol {

namespace {

constexpr char kMagic[8] = {'S', 'H', 'V', 'O', 'L', 'C', 'K', '1'};
constexpr uint32_t kHasSumSq = 1;  ///< flags: the film has sums of squares (--variance)

template <class T>
void put(std::string& out, const T& v) {
    out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

}  // namespace

uint64_t renderIdentity(Json doc, const std::string& files, const std::string& build) {
    if (doc.contains("render") && doc["render"].is_object()) doc["render"].erase("spp");
    const std::string text = dumpJson(doc) + "\n" + files + "build " + build;
    return fnv1a(text.data(), text.size());
}

void writeCheckpoint(const std::string& path, const Film& film, uint64_t identity) {
    std::string bytes(kMagic, sizeof kMagic);
    put(bytes, identity);
    put(bytes, int32_t(film.width));
    put(bytes, int32_t(film.height));
    put(bytes, uint32_t(film.sumSq.empty() ? 0 : kHasSumSq));
    bytes.append(reinterpret_cast<const char*>(film.count.data()),
                 film.count.size() * sizeof(uint32_t));
    bytes.append(reinterpret_cast<const char*>(film.sum.data()), film.sum.size() * sizeof(double));
    bytes.append(reinterpret_cast<const char*>(film.sumSq.data()),
                 film.sumSq.size() * sizeof(double));
    put(bytes, fnv1a(bytes.data(), bytes.size()));
    writeTextAtomically(path, bytes);
}

Film readCheckpoint(const std::string& path, uint64_t identity) {
    if (const std::string problem = inputFileProblem(path); !problem.empty())
        fail(path, "", problem);  // (a directory opens, and fails only when read)
    std::ifstream f(path, std::ios::binary);
    if (!f) fail(path, "", "cannot open checkpoint");
    const std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    const size_t header = sizeof kMagic + 8 + 4 + 4 + 4;
    if (bytes.size() < header + 8 || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
        fail(path, "", "not a shvol checkpoint");
    uint64_t id, sum;
    int32_t w, h;
    uint32_t flags;
    std::memcpy(&id, bytes.data() + 8, 8);
    std::memcpy(&w, bytes.data() + 16, 4);
    std::memcpy(&h, bytes.data() + 20, 4);
    std::memcpy(&flags, bytes.data() + 24, 4);
    if (flags & ~kHasSumSq) fail(path, "header", "unknown flags " + std::to_string(flags));
    const bool hasSumSq = flags & kHasSumSq;
    if (w <= 0 || h <= 0 || w > (1 << 16) || h > (1 << 16))
        fail(path, "header", "invalid resolution " + std::to_string(w) + "x" + std::to_string(h));
    const size_t pixels = size_t(w) * size_t(h);
    const size_t expected = header + pixels * (4 + 3 * 8 * (hasSumSq ? 2 : 1)) + 8;
    if (bytes.size() != expected)
        fail(path, "",
             std::to_string(bytes.size()) + " bytes where its header (" + std::to_string(w) + "x" +
                 std::to_string(h) + (hasSumSq ? ", with variance" : "") + ") needs " +
                 std::to_string(expected) + ": truncated, padded or corrupt");
    std::memcpy(&sum, bytes.data() + expected - 8, 8);
    if (fnv1a(bytes.data(), expected - 8) != sum)
        fail(path, "", "checksum mismatch (corrupt file)");
    if (id != identity)
        fail(path, "",
             "written for a different render (scene, --set values, seed, resolution, input "
             "files or shvol build differ; only the sample count may change)");
    Film film(w, h);
    std::memcpy(film.count.data(), bytes.data() + header, pixels * 4);
    std::memcpy(film.sum.data(), bytes.data() + header + pixels * 4, pixels * 3 * 8);
    if (hasSumSq) {
        film.sumSq.resize(pixels * 3);
        std::memcpy(film.sumSq.data(), bytes.data() + header + pixels * 28, pixels * 3 * 8);
    }
    return film;
}

}  // namespace shvol
