#include "shvol/io/checkpoint.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>

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

std::string identityDifference(const Json& saved, const Json& current) {
    std::vector<std::string> clauses;
    const auto part = [](const Json& id, const char* key) {
        return id.is_object() && id.contains(key) && id.at(key).is_object() ? id.at(key)
                                                                            : Json::object();
    };
    if (const auto keys = differingKeys(part(saved, "scene"), part(current, "scene"), false);
        !keys.empty())
        clauses.push_back((keys.size() > 1 ? "scene values " : "scene value ") + listed(keys) +
                          (keys.size() > 1 ? " differ" : " differs") +
                          " (scene file, --set or --seed)");
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
    std::string bytes(kMagic, sizeof kMagic);
    const std::string id = dumpJson(identity);
    put(bytes, uint32_t(id.size()));
    bytes += id;
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

Film readCheckpoint(const std::string& path, const Json& identity) {
    if (const std::string problem = inputFileProblem(path); !problem.empty())
        fail(path, "", problem);  // (a directory opens, and fails only when read)
    std::ifstream f(path, std::ios::binary);
    if (!f) fail(path, "", "cannot open checkpoint");
    // The magic first: another file given as the checkpoint (an image, say) is refused before it
    // is read whole (a 300 MB one took 556 MB; helper 71).
    char start[sizeof kMagic] = {};
    f.read(start, sizeof start);
    if (size_t(f.gcount()) < sizeof kMagic || (std::memcmp(start, kMagic, sizeof kMagic) != 0 &&
                                               std::memcmp(start, kMagic1, sizeof kMagic1) != 0))
        fail(path, "", "not a shvol checkpoint");
    f.clear();
    f.seekg(0);
    const std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    if (bytes.size() >= sizeof kMagic1 && std::memcmp(bytes.data(), kMagic1, sizeof kMagic1) == 0)
        fail(path, "",
             "a checkpoint of an earlier shvol (checkpoint format 1), which this build "
             "cannot resume: start afresh");
    uint32_t n = 0;
    if (bytes.size() >= sizeof kMagic + 4) std::memcpy(&n, bytes.data() + sizeof kMagic, 4);
    const size_t header = sizeof kMagic + 4 + size_t(n) + 4 + 4 + 4;
    if (bytes.size() < sizeof kMagic + 4 || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
        fail(path, "", "not a shvol checkpoint");
    if (bytes.size() < header + 8)
        fail(path, "header",
             std::to_string(bytes.size()) + " bytes, too few for its header (an identity of " +
                 std::to_string(n) + " bytes): truncated or corrupt");
    uint64_t sum;
    int32_t w, h;
    uint32_t flags;
    std::memcpy(&w, bytes.data() + header - 12, 4);
    std::memcpy(&h, bytes.data() + header - 8, 4);
    std::memcpy(&flags, bytes.data() + header - 4, 4);
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
    const Json saved = Json::parse(bytes.begin() + sizeof kMagic + 4,
                                   bytes.begin() + sizeof kMagic + 4 + n, nullptr, false);
    if (saved.is_discarded()) fail(path, "header", "its identity is not JSON (corrupt file)");
    if (!isIdentity(saved))
        fail(path, "header", "its identity is not of the form shvol writes (corrupt file)");
    if (const std::string difference = identityDifference(saved, identity); !difference.empty())
        fail(path, "",
             "written for a different render: " + difference +
                 " (only the sample count may change)");
    Film film(w, h);
    const char* data = bytes.data() + header;
    std::memcpy(film.count.data(), data, pixels * 4);
    std::memcpy(film.sum.data(), data + pixels * 4, pixels * 3 * 8);
    if (hasSumSq) {
        film.sumSq.resize(pixels * 3);
        std::memcpy(film.sumSq.data(), data + pixels * 28, pixels * 3 * 8);
    }
    // A render's sums are finite (it drops NaN and infinite samples, and the light it reads,
    // at most 10³⁰ times a float's range, is far within a double's), so a sum that is not is
    // damage that would reach the image.
    for (size_t i = 0; i < 3 * pixels; ++i) {
        const char* bad = !std::isfinite(film.sum[i]) ? "a sum that is not finite"
                          : hasSumSq && !(std::isfinite(film.sumSq[i]) && film.sumSq[i] >= 0)
                              ? "a sum of squares that is negative or not finite"
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
