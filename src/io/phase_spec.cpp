#include "shvol/io/phase_spec.h"

#include <filesystem>
#include <sstream>

#include "shvol/core/error.h"
#include "shvol/phase/phase_table_csv.h"

namespace shvol {

namespace fs = std::filesystem;

namespace {

constexpr double kMaxG = 0.999999;  // |g| and |k| bound: the lobes stay representable

/// A required number in [lo, hi] (JsonReader::number(key, def, lo, hi) has a default).
double requiredNumber(JsonReader& r, const std::string& key, double lo, double hi) {
    const double x = r.number(key);
    if (x < lo || x > hi) r.rangeError(key, "value", x, lo, hi);
    return x;
}

/// The analytic or tabulated phase function named by "type".
PhaseFunction readBasePhase(JsonReader& r, const std::string& baseDir) {
    const std::string type = r.choice(
        "type", "isotropic",
        {"isotropic", "hg", "two_term_hg", "rayleigh", "schlick", "cornette_shanks", "tabulated"});
    PhaseFunction phase;
    if (type == "isotropic") {
        phase = IsotropicPhase();
    } else if (type == "hg") {
        phase = HenyeyGreensteinPhase(r.number("g", 0, -kMaxG, kMaxG));
    } else if (type == "two_term_hg") {
        const double g1 = requiredNumber(r, "g1", -kMaxG, kMaxG);
        const double g2 = requiredNumber(r, "g2", -kMaxG, kMaxG);
        const double w = requiredNumber(r, "w", 0, 1);
        phase = TwoTermHenyeyGreensteinPhase(g1, g2, w);
    } else if (type == "rayleigh") {
        phase = RayleighPhase();
    } else if (type == "schlick") {
        phase = SchlickPhase(requiredNumber(r, "k", -kMaxG, kMaxG));
    } else if (type == "cornette_shanks") {
        phase = CornetteShanksPhase(requiredNumber(r, "g", -kMaxG, kMaxG));
    } else {  // tabulated
        r.string("file");
        r.finish();  // report unknown keys before touching the file system
        const std::string file = r.inputFile("file", baseDir);
        return r.readInput("file", [&] { return readPhaseTableCsv(file); });
    }
    r.finish();
    return phase;
}

/// The parser behind both entry points; relative files are resolved against baseDir. The SH keys
/// wrap the phase function in an SHSampledPhase; they are errors without "sampling": "sh".
PhaseFunction readPhase(JsonReader& r, const std::string& baseDir) {
    const bool sh = r.choice("sampling", "analytic", {"analytic", "sh"}) == "sh";
    if (!sh)
        for (const char* key : {"order", "tolerance", "window", "evaluate", "sh_depth"})
            if (r.has(key)) r.error(key, "only valid with \"sampling\": \"sh\"");
    const SHPhaseKeys keys = sh ? readSHPhaseKeys(r) : SHPhaseKeys{};
    const PhaseFunction base = readBasePhase(r, baseDir);
    if (!sh) return base;
    try {
        return SHSampledPhase(base, keys.fit, keys.evaluate, keys.depth);
    } catch (const Error& e) {
        r.error("order", e.what());
    }
}

}  // namespace

std::string specName(const std::string& spec) {
    return "phase spec \"" + briefText(spec, 80) + "\"";
}

SHPhaseKeys readSHPhaseKeys(JsonReader& r) {
    SHPhaseKeys k;
    const std::optional<int> order = r.integerOrAuto("order", 1, 256);
    k.fit.order = order.value_or(0);  // 0: "auto", the default
    if (!order)
        k.fit.tolerance = r.number("tolerance", k.fit.tolerance, 1e-9, 1);
    else if (r.has("tolerance"))
        r.error("tolerance", "only valid with \"order\": \"auto\"");
    const std::string window = r.choice("window", "auto", {"auto", "none", "hann", "lanczos"});
    if (window != "auto") k.fit.window = shWindowFromName(window);
    k.evaluate = r.choice("evaluate", "sh", {"sh", "exact"}) == "exact"
                     ? SHSampledPhase::Evaluate::Exact
                     : SHSampledPhase::Evaluate::Reconstruction;
    k.depth = r.integer("sh_depth", k.depth, SHSampledPhase::kMinDepth, SHSampledPhase::kMaxDepth);
    return k;
}

PhaseFunction readPhaseFunction(JsonReader r) {
    return readPhase(r, fs::path(r.file()).parent_path().string());
}

Json phaseSpecToJson(const std::string& spec) {
    const std::string where = specName(spec);
    const auto b = spec.find_first_not_of(" \t\r\n");
    if (b == std::string::npos) fail(where, "", "empty phase specification");
    if (spec[b] == '{') return parseJsonText(spec, where);
    const auto colon = spec.find(':');
    const std::string name = spec.substr(0, colon);
    if (name.empty()) fail(where, "", "missing phase function name before ':'");
    // A file's name, a scene's say, was read as a type name (helper 122). (With a '.' or '/',
    // which no type name has: a file named like a type in the working directory is no error.)
    std::error_code ec;
    if (colon == std::string::npos && spec.find_first_of("./") != std::string::npos &&
        fs::is_regular_file(spec, ec))
        fail(where, "",
             "a file, where a phase function is JSON or a short form such as hg:g=0.9 (a table "
             "file is named by tabulated:file=NAME.csv)");
    Json j = Json::object();
    j["type"] = name;
    if (colon == std::string::npos) return j;
    std::stringstream ss(spec.substr(colon + 1));
    for (std::string item; std::getline(ss, item, ',');) {
        const auto eq = item.find('=');
        if (eq == std::string::npos || eq == 0)
            fail(where, "", "expected key=value, got \"" + item + "\"");
        const std::string key = item.substr(0, eq), text = item.substr(eq + 1);
        if (key == "type") fail(where, "", "the type is the name before ':', not a key");
        if (j.contains(key)) fail(where, "", "key \"" + key + "\" given twice");
        Json value = text;  // a number if the whole value is one, else the string
        try {
            const Json parsed = Json::parse(text);
            if (parsed.is_number()) value = parsed;
        } catch (const Json::out_of_range&) {  // a number beyond a double (1e999)
            fail(where, key, "number beyond the range of a double (±1.8e308)");
        } catch (const Json::exception&) {  // not a number: keep the string
        }
        j[key] = value;
    }
    if (spec.back() == ',' || spec.back() == ':')
        fail(where, "", "expected key=value after '" + std::string(1, spec.back()) + "'");
    return j;
}

PhaseFunction readPhaseFunction(const Json& j, const std::string& where,
                                const std::string& baseDir) {
    JsonReader r(j, where, "");
    return readPhase(r, baseDir);
}

PhaseFunction parsePhaseSpec(const std::string& spec, const std::string& baseDir) {
    return readPhaseFunction(phaseSpecToJson(spec), specName(spec), baseDir);
}

}  // namespace shvol
