#include "shvol/io/checkpoint.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>

#include "shvol/core/atomic_file.h"
#include "shvol/core/error.h"
#include "shvol/core/hash.h"
#include "shvol/core/input_file.h"
#include "shvol/io/json_reader.h"

namespace shvol {

namespace {

constexpr char kMagic[8] = {'S', 'H', 'V', 'O', 'L', 'C', 'K', '2'};
constexpr char kMagic1[8] = {'S', 'H', 'V', 'O', 'L', 'C', 'K', '1'};  ///< format 1
constexpr uint32_t kHasSumSq = 1;  ///< flags: the film has sums of squares (--variance)
/// flags: the film has its luminances' sums of squares (from 6 Dec; without, they are unknown)
constexpr uint32_t kHasLuminanceSumSq = 2;

template <class T>
void put(std::string& out, const T& v) {
    out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

/// Adds the parts of value `v`, named `name`, at `depth` levels below the document
/// (renderIdentity). An empty object above the third level adds none: it sets nothing, as with
/// "render": {"spp": 4} once the sample count is left out.
void addParts(const Json& v, const std::string& name, int depth, Json& parts) {
    const bool ofObjects = v.is_array() && std::any_of(v.begin(), v.end(),
                                                       [](const Json& e) { return e.is_object(); });
    if (depth >= 3 || !(v.is_object() || ofObjects)) {
        // As numbers, not as written: 40.0 and 40 are one value (canonicalJson).
        const std::string text = canonicalJson(v);
        parts[name] = hexHash(fnv1a(text.data(), text.size()));
    } else if (v.is_object()) {
        for (auto it = v.begin(); it != v.end(); ++it)
            addParts(it.value(), name.empty() ? it.key() : name + "." + it.key(), depth + 1, parts);
    } else {
        for (size_t i = 0; i < v.size(); ++i)
            addParts(v[i], name + "[" + std::to_string(i) + "]", depth + 1, parts);
    }
}

/// The keys of objects `a` and `b` whose values differ, in order, with the keys only one of
/// them has unless `sharedOnly`.
std::vector<std::string> differingKeys(const Json& a, const Json& b, bool sharedOnly) {
    std::vector<std::string> keys;
    for (auto it = a.begin(); it != a.end(); ++it)
        if (b.contains(it.key()) ? b.at(it.key()) != it.value() : !sharedOnly)
            keys.push_back(it.key());
    for (auto it = b.begin(); it != b.end(); ++it)
        if (!a.contains(it.key()) && !sharedOnly) keys.push_back(it.key());
    std::sort(keys.begin(), keys.end());
    return keys;
}

/// Whether `id` has the form renderIdentity gives: {"scene": {name: hash}, "inputs": {key: hash},
/// "build": revision}, hashes and revision strings.
bool isIdentity(const Json& id) {
    const auto ofStrings = [&](const char* key) {
        if (!id.contains(key) || !id.at(key).is_object()) return false;
        return std::all_of(id.at(key).begin(), id.at(key).end(),
                           [](const Json& v) { return v.is_string(); });
    };
    return id.is_object() && ofStrings("scene") && ofStrings("inputs") && id.contains("build") &&
           id.at("build").is_string();
}

/// "a", "a and b", "a, b and c"; past 6 names, "a, …, f and N more".
std::string listed(const std::vector<std::string>& names) {
    const size_t shown = names.size() > 6 ? 6 : names.size();
    std::string text;
    for (size_t i = 0; i < shown; ++i)
        text += (i == 0 ? "" : i + 1 == names.size() ? " and " : ", ") + names[i];
    if (shown < names.size()) text += " and " + std::to_string(names.size() - shown) + " more";
    return text;
}

}  // namespace

Json renderIdentity(const Json& sceneDoc, const Json& inputFiles, const std::string& build) {
    Json scene = Json::object(), inputs = Json::object();
    Json doc = sceneDoc;
    if (doc.contains("render") && doc["render"].is_object()) doc["render"].erase("spp");
    // The files' names: their contents are the inputs' part.
    const std::function<void(Json&)> dropFileNames = [&](Json& v) {
        if (v.is_object() && v.contains("file") && v["file"].is_string()) v.erase("file");
        if (v.is_structured())
            for (Json& e : v) dropFileNames(e);
    };
    dropFileNames(doc);
    addParts(doc, "", 0, scene);
    for (const Json& f : inputFiles)
        if (f.at("key") != "(scene)") inputs[f.at("key").get<std::string>()] = f.at("fnv1a64");
    return {{"scene", scene}, {"inputs", inputs}, {"build", build}};
}

std::string identityDifference(const Json& saved, const Json& current, const std::string& sources) {
    std::vector<std::string> clauses;
    const auto part = [](const Json& id, const char* key) {
        return id.is_object() && id.contains(key) && id.at(key).is_object() ? id.at(key)
                                                                            : Json::object();
    };
    if (const auto keys = differingKeys(part(saved, "scene"), part(current, "scene"), false);
        !keys.empty())
        clauses.push_back((keys.size() > 1 ? "scene values " : "scene value ") + listed(keys) +
                          (keys.size() > 1 ? " differ" : " differs") + " (" + sources + ")");
    // (A file only one of them reads follows from a scene value, named above.)
    if (const auto keys = differingKeys(part(saved, "inputs"), part(current, "inputs"), true);
        !keys.empty())
        clauses.push_back("the file" + std::string(keys.size() > 1 ? "s" : "") + " named by " +
                          listed(keys) + (keys.size() > 1 ? " differ" : " differs") +
                          " in contents");
    const auto buildOf = [](const Json& id) {
        return id.is_object() && id.contains("build") ? id.at("build") : Json();
    };
    const Json savedBuild = buildOf(saved), build = buildOf(current);
    if (savedBuild != build)
        clauses.push_back("it was saved by shvol build " +
                          (savedBuild.is_string() ? savedBuild.get<std::string>() : "(unknown)") +
                          ", this is " +
                          (build.is_string() ? build.get<std::string>() : "(unknown)"));
    std::string text;
    for (const std::string& c : clauses) text += (text.empty() ? "" : "; ") + c;
    return text;
}

void writeCheckpoint(const std::string& path, const Film& film, const Json& identity) {
    std::string header(kMagic, sizeof kMagic);
    const std::string id = dumpJson(identity);
    put(header, uint32_t(id.size()));
    header += id;
    put(header, int32_t(film.width));
    put(header, int32_t(film.height));
    put(header, uint32_t((film.sumSq.empty() ? 0 : kHasSumSq) |
                         (film.luminanceSumSq.empty() ? 0 : kHasLuminanceSumSq)));
    // Streamed from the film, the checksum computed on the way: a copy of a 4K film with variance
    // is 498 MB more (430 MB before the luminances' squares; helper 71).
    writeAtomically(path, [&](const std::string& tmp) {
        writeStreamTo(tmp, path, "checkpoint", [&](std::ofstream& f) {
            uint64_t sum = kFnv1aOffset;
            const auto write = [&](const void* data, size_t n) {
                sum = fnv1a(data, n, sum);
                f.write(static_cast<const char*>(data), std::streamsize(n));
            };
            write(header.data(), header.size());
            write(film.count.data(), film.count.size() * sizeof(uint32_t));
            write(film.sum.data(), film.sum.size() * sizeof(double));
            write(film.sumSq.data(), film.sumSq.size() * sizeof(double));
            write(film.luminanceSumSq.data(), film.luminanceSumSq.size() * sizeof(double));
            f.write(reinterpret_cast<const char*>(&sum), sizeof sum);
        });
    });
}

Film readCheckpoint(const std::string& path, const Json& identity) {
    if (const std::string problem = inputFileProblem(path); !problem.empty())
        fail(path, "", problem);  // (a directory opens, and fails only when read)
    std::ifstream f(path, std::ios::binary);
    if (!f) fail(path, "", "cannot open checkpoint");
    f.seekg(0, std::ios::end);
    const std::streamoff end = f.tellg();
    f.seekg(0);
    if (end < 0) fail(path, "", "cannot read checkpoint");
    const size_t size = size_t(end);
    // The file is read into the film as it is checked, never whole into memory: the magic first
    // (another file given as the checkpoint, an image say, is refused before more is read; a
    // 300 MB one took 556 MB, helper 71), then the header, then the film's arrays.
    const auto read = [&](void* data, size_t n) {
        f.read(static_cast<char*>(data), std::streamsize(n));
        if (size_t(f.gcount()) != n)
            fail(path, "", "cannot read checkpoint (it changed while read)");
    };
    char magic[sizeof kMagic] = {};
    f.read(magic, sizeof magic);
    if (size_t(f.gcount()) == sizeof kMagic1 && std::memcmp(magic, kMagic1, sizeof kMagic1) == 0)
        fail(path, "",
             "a checkpoint of an earlier shvol (checkpoint format 1), which this build "
             "cannot resume: start afresh");
    if (size_t(f.gcount()) < sizeof kMagic || std::memcmp(magic, kMagic, sizeof kMagic) != 0) {
        // (an image or a stats file given as the checkpoint, or an empty file, named as such; a
        // JSON file's first brace may come after more than the magic's 8 bytes)
        const std::string other = fileOfAnotherKind(path, "a shvol checkpoint");
        fail(path, "",
             size == 0        ? std::string("empty, not a shvol checkpoint")
             : !other.empty() ? other
                              : std::string("not a shvol checkpoint"));
    }
    uint32_t n = 0;
    if (size < sizeof kMagic + 4) fail(path, "", "not a shvol checkpoint");
    read(&n, 4);
    const size_t header = sizeof kMagic + 4 + size_t(n) + 4 + 4 + 4;
    if (size < header + 8)
        fail(path, "header",
             std::to_string(size) + " bytes, too few for its header (an identity of " +
                 std::to_string(n) + " bytes): truncated or corrupt");
    std::string head(magic, sizeof magic);
    put(head, n);
    head.resize(header);
    read(head.data() + sizeof kMagic + 4, header - sizeof kMagic - 4);
    int32_t w, h;
    uint32_t flags;
    std::memcpy(&w, head.data() + header - 12, 4);
    std::memcpy(&h, head.data() + header - 8, 4);
    std::memcpy(&flags, head.data() + header - 4, 4);
    if (flags & ~(kHasSumSq | kHasLuminanceSumSq))
        fail(path, "header", "unknown flags " + std::to_string(flags));
    const bool hasSumSq = flags & kHasSumSq, hasLuminanceSumSq = flags & kHasLuminanceSumSq;
    if (w <= 0 || h <= 0 || w > (1 << 16) || h > (1 << 16))
        fail(path, "header", "invalid resolution " + std::to_string(w) + "x" + std::to_string(h));
    const size_t pixels = size_t(w) * size_t(h);
    const size_t expected =
        header + pixels * (4 + 3 * 8 * (hasSumSq ? 2 : 1) + (hasLuminanceSumSq ? 8 : 0)) + 8;
    if (size != expected)
        fail(path, "",
             std::to_string(size) + " bytes where its header (" + std::to_string(w) + "x" +
                 std::to_string(h) + (hasSumSq ? ", with variance" : "") + ") needs " +
                 std::to_string(expected) + ": truncated, padded or corrupt");
    Film film(w, h);
    if (hasSumSq) film.sumSq.resize(pixels * 3);
    if (!hasLuminanceSumSq) film.luminanceSumSq.clear();  // unknown
    uint64_t computed = fnv1a(head.data(), head.size());
    const auto readHashed = [&](void* data, size_t bytes) {
        read(data, bytes);
        computed = fnv1a(data, bytes, computed);
    };
    readHashed(film.count.data(), pixels * 4);
    readHashed(film.sum.data(), pixels * 3 * 8);
    readHashed(film.sumSq.data(), film.sumSq.size() * 8);
    readHashed(film.luminanceSumSq.data(), film.luminanceSumSq.size() * 8);
    uint64_t sum;
    read(&sum, 8);
    if (computed != sum) fail(path, "", "checksum mismatch (corrupt file)");
    const Json saved = Json::parse(head.begin() + sizeof kMagic + 4,
                                   head.begin() + sizeof kMagic + 4 + n, nullptr, false);
    if (saved.is_discarded()) fail(path, "header", "its identity is not JSON (corrupt file)");
    if (!isIdentity(saved))
        fail(path, "header", "its identity is not of the form shvol writes (corrupt file)");
    if (const std::string difference = identityDifference(saved, identity); !difference.empty())
        fail(path, "",
             "written for a different render: " + difference +
                 " (only the sample count may change)");
    // A render's sums are finite (it drops NaN and infinite samples, and the light it reads,
    // at most 10³⁰ times a float's range, is far within a double's; of either sign: an SH
    // phase function rendered exactly can be negative), and a pixel of no samples has none:
    // anything else is damage that would reach the image (a checksum made again over a pixel of
    // no samples with sums passed it; helper 170).
    for (size_t i = 0; i < 3 * pixels; ++i) {
        const bool none = film.count[i / 3] == 0;
        const char* bad = !std::isfinite(film.sum[i]) ? "a sum that is not finite"
                          : none && (film.sum[i] != 0 || (hasSumSq && film.sumSq[i] != 0) ||
                                     (hasLuminanceSumSq && film.luminanceSumSq[i / 3] != 0))
                              ? "sums in a pixel of no samples"
                          : hasSumSq && !(std::isfinite(film.sumSq[i]) && film.sumSq[i] >= 0)
                              ? "a sum of squares that is negative or not finite"
                          : hasLuminanceSumSq && !(std::isfinite(film.luminanceSumSq[i / 3]) &&
                                                   film.luminanceSumSq[i / 3] >= 0)
                              ? "a sum of squared luminances that is negative or not finite"
                              : nullptr;
        if (bad)
            fail(path,
                 "pixel (" + std::to_string(i / 3 % size_t(w)) + ", " +
                     std::to_string(i / 3 / size_t(w)) + ")",
                 std::string(bad) + " (corrupt file)");
    }
    return film;
}

}  // namespace shvol
