#include "shvol/io/json_reader.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "json_walk.h"
#include "shvol/core/error.h"
#include "shvol/core/input_file.h"
#include "shvol/core/spelling.h"

namespace shvol {

namespace {
std::string typeName(const Json& j) {
    if (j.is_number()) return "number";
    return j.type_name();
}
/// Appends j as compact JSON until out is longer than `limit`. Never throws on strings that are
/// not valid UTF-8 (a --set value that is not JSON is taken as a string as it is; its bad bytes
/// print as U+FFFD), and recurses no deeper than the text it prints, so that a value nested
/// thousands of levels deep cannot overflow the stack (Json::dump recurses through all of it).
void briefInto(const Json& j, std::string& out, size_t limit) {
    if (out.size() > limit) return;
    if (!j.is_structured()) {
        out += j.dump(-1, ' ', false, Json::error_handler_t::replace);
        return;
    }
    out += j.is_array() ? '[' : '{';
    for (auto it = j.begin(); it != j.end() && out.size() <= limit; ++it) {
        if (it != j.begin()) out += ',';
        if (j.is_object())
            out += Json(it.key()).dump(-1, ' ', false, Json::error_handler_t::replace) + ':';
        briefInto(*it, out, limit);
    }
    out += j.is_array() ? ']' : '}';
}
std::string brief(const Json& j) {
    std::string s;
    briefInto(j, s, 40);
    return briefText(s);
}
}  // namespace

std::string typeAndValue(const Json& j) {
    return j.is_null() ? "null" : typeName(j) + " " + brief(j);
}

namespace {

/// The offset of the first JSON number in `text` spelled `token`: outside strings, and not part
/// of a longer number; npos if there is none.
size_t findNumberToken(const std::string& text, const std::string& token) {
    auto inNumber = [](char c) {
        return std::isdigit((unsigned char)c) || std::strchr("+-.eE", c);
    };
    bool inString = false;
    for (size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (inString) {
            if (c == '\\')
                ++i;  // an escaped character
            else if (c == '"')
                inString = false;
        } else if (c == '"') {
            inString = true;
        } else if (text.compare(i, token.size(), token) == 0 &&
                   (i == 0 || !inNumber(text[i - 1])) &&
                   (i + token.size() == text.size() || !inNumber(text[i + token.size()]))) {
            return i;
        }
    }
    return std::string::npos;
}

/// j with every number of integral value below 2^63 in magnitude stored as an integer
/// (canonicalJson); larger ones stay doubles, as no int64 holds them.
Json integralAsInteger(const Json& j) {
    if (j.is_number_float()) {
        const double x = j.get<double>();
        return std::trunc(x) == x && std::abs(x) < 9223372036854775808.0
                   ? Json(static_cast<std::int64_t>(x))
                   : j;
    }
    if (!j.is_structured()) return j;
    Json out = j;
    for (auto& v : out) v = integralAsInteger(v);
    return out;
}

}  // namespace

Json parseWithinDepth(const std::string& text, const std::function<void()>& tooDeep) {
    JsonWalk walk("", [&](const std::string&) { tooDeep(); });
    Json::sax_parse(text, &walk);
    return Json::parse(text);
}

std::string canonicalJson(const Json& j) {
    return dumpJson(integralAsInteger(j));
}

std::string tooDeepMessage() {
    return "objects and arrays nested more than " + std::to_string(kMaxJsonDepth) + " levels deep";
}

std::string briefText(const std::string& text, size_t limit) {
    return text.size() > limit ? text.substr(0, limit - 3) + "..." : text;
}

Json parseOwnJsonFile(const std::string& path) {
    std::ifstream f(path);
    std::stringstream text;
    text << f.rdbuf();
    struct TooDeep {};
    try {
        return parseWithinDepth(text.str(), [] { throw TooDeep{}; });
    } catch (const TooDeep&) {
    } catch (const Json::exception&) {
    }
    return Json(Json::value_t::discarded);
}

Json parseJsonFile(const std::string& path) {
    if (const std::string problem = inputFileProblem(path); !problem.empty())
        fail(path, "", problem);  // (a directory opens, and reads as empty)
    std::ifstream f(path);
    if (!f) fail(path, "", "cannot open file");
    std::stringstream ss;
    ss << f.rdbuf();
    return parseJsonText(ss.str(), path);
}

Json parseJsonText(const std::string& text, const std::string& path, const std::string& root) {
    // "line L, column C" of the byte at offset `byte` (0-based).
    auto lineColumn = [&](size_t byte) {
        size_t line = 1, col = 1;
        for (size_t i = 0; i < byte && i < text.size(); ++i) {
            if (text[i] == '\n')
                ++line, col = 1;
            else
                ++col;
        }
        return "line " + std::to_string(line) + ", column " + std::to_string(col);
    };
    // A file of another kind given where JSON is read (a grid or an image for a scene): named by
    // its kind, where the parser's "a NUL byte" said nothing of it (helper 122).
    if (const char* kind = fileKindByMagic(text))
        fail(path, "",
             std::string("the file is ") + kind +
                 ", not JSON: a scene or a sweep names such files by their keys");
    // The parser reads a NUL byte as the end of the text, and would ignore what follows.
    if (const size_t nul = text.find('\0'); nul != std::string::npos)
        fail(path, lineColumn(nul), "malformed JSON: a NUL byte");
    // A key given twice in one object: the parser keeps the last silently, so a scene's first
    // value would be ignored without a word. The place is the object's JSON path. Said once the
    // whole text has parsed: the walk sees a key before the parser checks the ':' after it, and a
    // syntax error there ("fov" 40) is the mistake to name.
    JsonWalk walk(root, [&](const std::string& place) { fail(path, place, tooDeepMessage()); });
    const bool wellFormed = Json::sax_parse(text, &walk);
    try {
        Json parsed = Json::parse(text);  // (malformed: throws, naming the place)
        if (wellFormed && !walk.repeated.empty())
            fail(path, walk.repeatedAt,
                 "key \"" + walk.repeated + "\" appears twice (the last would replace the first)");
        return parsed;
    } catch (const Json::out_of_range& e) {  // e.g. a number such as 1e999
        // e.what() is "[json.exception…] number overflow parsing '1e999'", without a position:
        // the place is where that number first occurs.
        std::string msg = e.what();
        msg = msg.substr(msg.find("] ") == std::string::npos ? 0 : msg.find("] ") + 2);
        const size_t q0 = msg.find('\''), q1 = msg.rfind('\'');
        const size_t at =
            q0 < q1 ? findNumberToken(text, msg.substr(q0 + 1, q1 - q0 - 1)) : std::string::npos;
        fail(path, at == std::string::npos ? "" : lineColumn(at), "malformed JSON: " + msg);
    } catch (const Json::parse_error& e) {
        // e.what() is "[json.exception…] parse error at line L, column C: <reason>"; keep the
        // reason. e.byte is 1-based.
        std::string msg = e.what();
        const auto at = msg.find("column ");
        const auto colon = at == std::string::npos ? at : msg.find(": ", at);
        if (colon != std::string::npos) msg = msg.substr(colon + 2);
        fail(path, lineColumn(e.byte > 0 ? e.byte - 1 : 0), "malformed JSON: " + msg);
    }
}

bool overrideSets(const std::string& key, const Json& value,
                  const std::vector<std::string>& target) {
    std::vector<std::string> parts;
    if (!keyPathProblem(key, &parts).empty()) return false;
    size_t i = 0;
    for (; i < parts.size() && i < target.size(); ++i)
        if (target[i] != "*" && parts[i] != target[i]) return false;
    // The key itself (a key inside it fails as the scene is read: the targets hold numbers and
    // names).
    if (i == target.size()) return parts.size() == target.size();
    // The rest of the target inside the value.
    const std::function<bool(const Json&, size_t)> holds = [&](const Json& v, size_t k) {
        if (k == target.size()) return true;
        if (v.is_object()) {
            if (target[k] != "*") return v.contains(target[k]) && holds(v.at(target[k]), k + 1);
            for (const auto& member : v)
                if (holds(member, k + 1)) return true;
        } else if (v.is_array()) {
            for (size_t e = 0; e < v.size(); ++e)
                if ((target[k] == "*" || target[k] == std::to_string(e)) && holds(v[e], k + 1))
                    return true;
        }
        return false;
    };
    return holds(value, i);
}

const std::string* overrideSetting(const std::vector<std::string>& sets,
                                   const std::vector<std::string>& target) {
    for (const std::string& set : sets)
        if (const size_t eq = set.find('=');  // (one without '=' is refused as the scene is read)
            eq != std::string::npos) {
            Json value;
            try {
                value = overrideValue(set.substr(eq + 1), set.substr(0, eq));
            } catch (const Error&) {  // (refused as the scene is read, with the scene's name)
                continue;
            }
            if (overrideSets(set.substr(0, eq), value, target)) return &set;
        }
    return nullptr;
}

Json overrideValue(const std::string& text, const std::string& place, const std::string& file,
                   const std::string& where) {
    const std::string named = file.empty() || where.empty() ? file + where : file + ": " + where;
    Json value;
    try {
        value = Json::parse(text);
    } catch (const Json::out_of_range&) {  // a number beyond a double (1e400)
        fail(named, where.empty() ? place : "", "number beyond the range of a double (±1.8e308)");
    } catch (const Json::exception&) {  // not JSON: a string
        return text;
    }
    // JSON, so refused as a file's would be if it repeats a key, named at its place.
    return value.is_structured() ? parseJsonText(text, named, place) : value;
}

std::string canonicalKeyPath(const std::string& key) {
    std::string path;
    for (char ch : key) {
        if (ch == '[')
            path += '.';
        else if (ch != ']')
            path += ch;
    }
    return path;
}

std::string keyPathProblem(const std::string& key, std::vector<std::string>* parts) {
    // (no scene key has one; a NUL would cut short every message that names the key)
    for (const char c : key)
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
            return "a control character in key path";
    size_t i = 0;
    // Reads the run of characters `allowed` accepts from i (into parts); false if it is empty.
    const auto run = [&](auto&& allowed) {
        const size_t start = i;
        while (i < key.size() && allowed(key[i])) ++i;
        if (i > start && parts) parts->push_back(key.substr(start, i - start));
        return i > start;
    };
    const auto name = [&] { return run([](char c) { return c != '.' && c != '[' && c != ']'; }); };
    if (!name())
        return key.empty() || key[0] == '.' ? "empty component in key path"
                                            : "a key path starts with a name";
    while (i < key.size()) {
        const char c = key[i++];
        if (c == '.') {
            if (!name()) return "empty component in key path";
        } else if (c == '[') {
            if (!run([](char d) { return d >= '0' && d <= '9'; }) || i == key.size() ||
                key[i] != ']')
                return "expected an index in brackets, as in media[0]";
            ++i;
        } else if (c == ']') {
            return "']' without '[' in key path";
        } else {
            return "expected '.' or '[' after ']' in key path";
        }
    }
    return "";
}

namespace {
/// The path of a scene object with its indices left out: media[].phase for media[0].phase.
std::string genericPath(const std::string& path) {
    std::string generic;
    for (size_t i = 0; i < path.size(); ++i) {
        generic += path[i];
        if (path[i] == '[') i = std::min(path.find(']', i), path.size()) - 1;
    }
    return generic;
}

/// The keys of the scene object at `path` that every type of it reads, which a new type keeps: a
/// camera's position, target, up and resolution, a sky's lower_hemisphere_black and
/// wavelet_coefficients, a medium's albedo, phase and boundary, a phase function's SH sampling
/// keys, a surface's name, BSDF, emission and transform. Started afresh whole, they were lost
/// without a word (helper 73: --set camera.type=orthographic rendered at 320 × 240; helper 183:
/// a sky's black lower hemisphere, a phase function's SH sampling). A BSDF's and a shape's keys
/// are their type's.
const std::vector<std::string>& keysOfEveryType(const std::string& path) {
    static const std::vector<std::string> none,
        camera = {"position", "target", "up", "resolution"},
        environment = {"lower_hemisphere_black", "wavelet_coefficients"},
        medium = {"albedo", "phase", "boundary"},
        phase = {"sampling", "order", "tolerance", "window", "evaluate", "sh_depth"},
        surface = {"name", "bsdf", "emission", "emission_two_sided", "transform"};
    const std::string generic = genericPath(path);
    return generic == "camera"          ? camera
           : generic == "environment"   ? environment
           : generic == "media[]"       ? medium
           : generic == "media[].phase" ? phase
           : generic == "surfaces[]"    ? surface
                                        : none;
}

/// The type of the object at `path` (media[0].phase) when it names none: the defaults of the
/// loader's `choice("type", …)` (scene_loader.cpp, phase_spec.cpp), or null where an object has
/// no type. A --set of another type starts such an object afresh too (helper 181: a BSDF of
/// reflectance 0.3 and no type, set to a mirror, kept 0.3 where the mirror's default is 1).
Json defaultType(const std::string& path) {
    static const std::pair<const char*, const char*> defaults[] = {
        {"camera", "perspective"},      {"environment", "constant"}, {"media[]", "vdb"},
        {"media[].phase", "isotropic"}, {"media[].shape", "box"},    {"surfaces[]", "mesh"},
        {"surfaces[].bsdf", "lambert"}};
    const std::string generic = genericPath(path);
    for (const auto& [p, type] : defaults)
        if (generic == p) return type;
    return nullptr;
}
}  // namespace

namespace {
/// "unknown key", with `nearest`, the nearest known key (nearestSpelling), when there is one
/// (helper 77: `camra: unknown key` said nothing of `camera`).
std::string unknownKey(const std::string& nearest) {
    return nearest.empty() ? "unknown key" : "unknown key (did you mean \"" + nearest + "\"?)";
}
}  // namespace

std::string overridePlace(const std::string& assignment) {
    const auto eq = assignment.find('=');
    return "--set " + (eq == std::string::npos ? briefText(assignment, 80)
                                               : assignment.substr(0, eq + 1) +
                                                     briefText(assignment.substr(eq + 1), 80));
}

namespace {
/// The value at a key path (components, as keyPathProblem gives them) of `doc`, or nullptr.
const Json* valueAt(const Json& doc, const std::vector<std::string>& path) {
    const Json* node = &doc;
    for (const std::string& part : path) {
        const bool index = part.find_first_not_of("0123456789") == std::string::npos;
        if (node->is_object() && node->contains(part))
            node = &(*node)[part];
        else if (node->is_array() && index && part.size() < 10 && std::stoul(part) < node->size())
            node = &(*node)[std::stoul(part)];
        else
            return nullptr;
    }
    return node;
}
}  // namespace

std::vector<int> applyOverrides(Json& doc, const std::vector<std::string>& overrides,
                                const std::string& file, std::vector<std::string>* unchanged) {
    std::vector<int> by(overrides.size(), -1);
    std::vector<std::vector<std::string>> paths(overrides.size());
    for (size_t j = 0; j < overrides.size(); ++j) {
        if (!applyOverride(doc, overrides[j], file) && unchanged)
            unchanged->push_back(overrides[j]);
        for (size_t i = 0; i < j; ++i)  // (those of i still there before j)
            if (!paths[i].empty() && by[i] < 0 && !valueAt(doc, paths[i])) by[i] = int(j);
        const std::string& o = overrides[j];
        const size_t eq = o.find('=');
        if (eq == std::string::npos || o.compare(eq + 1, std::string::npos, "null") == 0 ||
            !keyPathProblem(o.substr(0, eq), &paths[j]).empty() || !valueAt(doc, paths[j]))
            paths[j].clear();  // (a deletion, or nothing set)
    }
    for (size_t i = 0; i < overrides.size(); ++i)  // (set again later: there after all)
        if (by[i] >= 0 && valueAt(doc, paths[i])) by[i] = -1;
    return by;
}

int overrideOfError(const std::string& message, const std::string& file, const Json& before,
                    const Json& after, const std::vector<std::string>& overrides,
                    std::string* placeAndReason) {
    const std::string prefix = file + ": ";
    if (message.rfind(prefix, 0) != 0) return -1;
    const std::string rest = message.substr(prefix.size());
    const size_t colon = rest.find(": ");
    if (colon == std::string::npos) return -1;
    const std::string place = rest.substr(0, colon);
    std::vector<std::string> parts;
    if (!keyPathProblem(place, &parts).empty()) return -1;
    // The value must be one the overrides brought in or changed (an unknown key one they brought
    // in): the file's own, where an override set something beside it, is the file's to answer
    // for. And it must be in the document after them (a key whose name holds a dot, "fov.x",
    // reads as the path camera.fov.x, which the file's camera.fov=30 does not hold; helper 131).
    std::string at = canonicalKeyPath(place);
    bool missing = false, typeChanged = false, broughtIn = false;
    if (const Json* now = valueAt(after, parts)) {
        // (A key the overrides brought in is theirs also where the error names an object above
        // the key they set: `--set calera.fov=40`, "calera: unknown key", blamed the scene file;
        // helper 170.)
        broughtIn = !valueAt(before, parts);
        // A key the file has is unknown for the file's reasons, unless an override changed the
        // type of its object, whatever the key's value (helpers 139, 140: `--set
        // media.0.phase.type=rayleigh --set media.0.phase.g=0.5`, or `phase.type=null`, blamed
        // the file's HG phase for its g).
        const std::vector<std::string> object(parts.begin(), parts.end() - 1);
        const auto typeOf = [&](const Json& doc) {
            const Json* o = valueAt(doc, object);
            return o && o->is_object() && o->contains("type") ? (*o)["type"] : Json();
        };
        const bool unknownKey = rest.compare(colon + 2, 11, "unknown key") == 0;
        typeChanged = unknownKey && typeOf(before) != typeOf(after);
        if (const Json* was = valueAt(before, parts);
            was && (unknownKey ? !typeChanged : *was == *now))
            return -1;
    } else {
        // A key missing after the overrides (one that a new type of its object asks for, or one
        // of the file's that setting the type removed): the override that changed its object
        // (helper 137: --set media.0.phase.type=tabulated, without a file, blamed the scene).
        const std::vector<std::string> object(parts.begin(), parts.end() - 1);
        const Json *objectNow = valueAt(after, object), *objectWas = valueAt(before, object);
        if (object.empty() || !objectNow || !objectNow->is_object() ||
            (objectWas && *objectWas == *objectNow))
            return -1;
        at = at.substr(0, at.rfind('.'));
        missing = true;
    }
    // (the type's override, where nothing else set the key: `phase.type=null`)
    const std::string type = at.substr(0, at.rfind('.') + 1) + "type";
    for (int i = int(overrides.size()) - 1; i >= 0; --i) {  // (a later one replaces an earlier)
        const std::string key =
            canonicalKeyPath(overrides[size_t(i)].substr(0, overrides[size_t(i)].find('=')));
        if (at == key || at.rfind(key + ".", 0) == 0 ||
            ((missing || broughtIn) && key.rfind(at + ".", 0) == 0) ||
            (typeChanged && key == type)) {
            if (placeAndReason) *placeAndReason = rest;
            return i;
        }
    }
    return -1;
}

bool applyOverride(Json& doc, const std::string& assignment, const std::string& file,
                   const std::string& source) {
    const std::string by = source.empty() ? "" : source + ": ";
    const auto eq = assignment.find('=');
    const std::string given = overridePlace(assignment);
    if (eq == std::string::npos || eq == 0) fail(file, given, "expected key.path=value");
    std::vector<std::string> parts;
    if (const std::string problem = keyPathProblem(assignment.substr(0, eq), &parts);
        !problem.empty())
        fail(file, given, problem);
    // The document itself must be an object (a scene or a sweep), overrides or not.
    if (!doc.is_object()) fail(file, "(top level)", "expected an object, got " + typeName(doc));
    Json* node = &doc;
    std::string walked;
    const auto cannotDescend = [&] {
        fail(file, walked,
             by + "cannot descend into " + std::string(node->is_array() ? "an " : "a ") +
                 typeName(*node));
    };
    // The element of the array *node that `part` names.
    const auto element = [&](const std::string& part) {
        const std::string size =
            std::to_string(node->size()) + (node->size() == 1 ? " element" : " elements");
        if (part.find_first_not_of("0123456789") != std::string::npos)
            fail(file, walked, by + "\"" + part + "\" is not an index of the array (" + size + ")");
        const size_t i = part.size() > 9 ? node->size() : std::stoul(part);
        if (i >= node->size())
            fail(file, walked, by + "index " + part + " out of range (" + size + ")");
        return i;
    };
    // An index into a value the document lacks (media[0] of a scene without media): the walk
    // would make an object {"0": …} of it, which the loader then refused as "expected an array of
    // objects" (helper 77). No scene key is a number. Checked before the walk adds the key.
    const auto indexIntoMissing = [&](size_t k) {
        const std::string& next = parts[k + 1];
        if (!(node->is_null() || (node->is_object() && !node->contains(parts[k]))) ||
            next.find_first_not_of("0123456789") != std::string::npos)
            return;
        const std::string array = walked + (walked.empty() ? "" : ".") + parts[k];
        // A misspelt key is more likely than a missing array: its object's keys (and the
        // scene's arrays) are the candidates (helper 81: `medai[0]` was told to give the whole
        // array).
        std::vector<std::string> known;
        if (node->is_object())
            for (auto it = node->begin(); it != node->end(); ++it) known.push_back(it.key());
        if (walked.empty()) known.insert(known.end(), {"media", "surfaces"});
        if (const std::string nearest = nearestSpelling(parts[k], known); !nearest.empty())
            fail(file, array, by + unknownKey(nearest));
        fail(file, array,
             by + "index " + next + " of an array the scene does not have: give the whole array " +
                 "(--set '" + array + "=[…]')");
    };
    // A deletion under a key the document lacks deletes nothing, and adds nothing either (the
    // walk would make each missing key null on its way, which the loader then refused).
    // (`bsdf.type=null` is no deletion: it names the null BSDF, below.)
    const bool bsdfType =
        parts.size() >= 2 && parts.back() == "type" && parts[parts.size() - 2] == "bsdf";
    const bool deleting = assignment.compare(eq + 1, std::string::npos, "null") == 0 && !bsdfType;
    for (size_t k = 0; k + 1 < parts.size(); ++k) {
        const std::string& part = parts[k];
        if (deleting && !(node->is_object() && node->contains(part)) && !node->is_array())
            return false;
        if (node->is_array()) {
            node = &(*node)[element(part)];
            walked += "[" + part + "]";
        } else if (node->is_object() || node->is_null()) {
            if (!deleting) indexIntoMissing(k);
            node = &(*node)[part];
            walked += (walked.empty() ? "" : ".") + part;
        } else {
            cannotDescend();
        }
    }
    const std::string& last = parts.back();
    // (read once the path is walked: errors in the value are named at its place, media[0].phase)
    // (a sweep, without `source`, names the assignment itself: the value is the sweep file's)
    Json value = overrideValue(
        assignment.substr(eq + 1),
        node->is_array() ? walked + "[" + last + "]" : (walked.empty() ? "" : walked + ".") + last,
        source.empty() ? "" : file, source.empty() ? "" : given);
    if (node->is_array()) {
        if (value.is_null()) fail(file, walked, by + "array elements cannot be deleted");
        (*node)[element(last)] = std::move(value);
        return true;
    }
    if (!node->is_object() && !node->is_null()) cannotDescend();
    // A BSDF's type=null names the null BSDF, which is what `--set surfaces.0.bsdf.type=null`
    // means (deleting the object, bsdf=null, restores its default); other types are deleted.
    if (value.is_null() && bsdfType) value = "null";
    if (value.is_null())  // key=null deletes the key (its default applies again)
        return node->is_object() && node->erase(last) > 0;
    // A new type starts a fresh object: keys of the old type would be unknown to the new one
    // (but for those every type reads). The old type is the default where the object names none.
    if (last == "type" && node->is_object()) {
        const Json old = node->contains("type") ? (*node)["type"] : defaultType(walked);
        if (!old.is_null() && old != value) {
            Json kept = Json::object();
            for (const std::string& key : keysOfEveryType(walked))
                if (node->contains(key)) kept[key] = std::move((*node)[key]);
            *node = std::move(kept);
        }
    }
    // A file named on the command line is relative to the current directory, as a shell user
    // expects (file names inside the scene stay relative to the scene's folder).
    if (last == "file" && value.is_string() && !value.get<std::string>().empty() &&
        !std::filesystem::path(value.get<std::string>()).is_absolute()) {
        std::error_code ec;  // (the current directory may have been removed)
        const auto abs = std::filesystem::absolute(value.get<std::string>(), ec);
        if (ec) fail(file, "--set " + assignment, "cannot resolve the file name: " + ec.message());
        value = abs.lexically_normal().string();
    }
    (*node)[last] = std::move(value);
    return true;
}

JsonReader::JsonReader(const Json& j, std::string file, std::string path)
    : j_(j), file_(std::move(file)), path_(std::move(path)) {
    if (!j_.is_object())
        fail(file_, path_.empty() ? "(top level)" : path_,
             "expected an object, got " + typeName(j_));
}

std::string JsonReader::keyPath(const std::string& key) const {
    return path_.empty() ? key : path_ + "." + key;
}

void JsonReader::error(const std::string& key, const std::string& msg) const {
    fail(file_, key.empty() ? path_ : keyPath(key), msg);
}

namespace {
/// A bound or value as a reader would write it: whole numbers below 10^6 in full (20, not 2e1),
/// else the shortest decimal that reads back as v, with a plain exponent: 2^53 in full
/// (9007199254740992, not 9.0072e+15), 10^12 as 1e12, 0.1 as 0.1.
std::string numberText(double v) {
    if (std::abs(v) < 1e6 && v == std::floor(v)) return std::to_string((long long)v);
    char b[32];
    for (int digits = 1; digits <= 17; ++digits) {
        std::snprintf(b, sizeof b, "%.*g", digits, v);
        if (std::strtod(b, nullptr) == v) break;
    }
    std::string s = b;
    const size_t e = s.find('e');  // e+12 → e12, e-05 → e-5
    if (e == std::string::npos) return s;
    std::string mantissa = s.substr(0, e), exponent = s.substr(e + 1);
    const bool negative = exponent[0] == '-';
    exponent = exponent.substr(exponent[0] == '+' || negative ? 1 : 0);
    exponent.erase(0, std::min(exponent.find_first_not_of('0'), exponent.size() - 1));
    return mantissa + "e" + (negative ? "-" : "") + exponent;
}
}  // namespace

void JsonReader::rangeError(const std::string& key, const std::string& what, double x, double lo,
                            double hi) const {
    rangeError(key, what, numberText(x), lo, hi);
}

void JsonReader::rangeError(const std::string& key, const std::string& what, const std::string& x,
                            double lo, double hi) const {
    // An unbounded range keeps its number finite: the cap is said only to a value beyond it.
    const std::string range = hi < kUnbounded ? "[" + numberText(lo) + ", " + numberText(hi) + "]"
                              : std::strtod(x.c_str(), nullptr) > hi
                                  ? "(expected at most " + numberText(hi) + ")"
                                  : "(expected ≥ " + numberText(lo) + ")";
    error(key, what + " " + x + " out of range " + range);
}

bool JsonReader::has(const std::string& key) const {
    asked_.insert(key);
    return j_.contains(key);
}

const Json& JsonReader::get(const std::string& key, const char* type) const {
    if (!j_.contains(key)) error(key, std::string("missing required ") + type);
    return j_.at(key);
}

namespace {
/// A default as a reader would write it: an integral number as an integer.
Json writtenDefault(double v) {
    const bool integral = std::abs(v) < 0x1p53 && v == std::floor(v);
    return integral ? Json((long long)v) : Json(v);
}
}  // namespace

double JsonReader::number(const std::string& key, std::optional<double> def) {
    used_.insert(key);
    if (!j_.contains(key) && def) {
        note(key, writtenDefault(*def));
        return *def;
    }
    const Json& v = get(key, "number");
    if (!v.is_number()) error(key, "expected a number, got " + typeAndValue(v));
    const double x = v.get<double>();
    if (!std::isfinite(x)) error(key, "expected a finite number");
    note(key, v);  // as written (an integer stays one)
    return x;
}

double JsonReader::number(const std::string& key, double def, double lo, double hi) {
    const double x = number(key, std::optional<double>(def));
    // An integer is compared exactly: 2^53 + 1 rounds to 2^53 as a double, and would pass.
    if (has(key) && j_.at(key).is_number_integer()) {
        const Json& v = j_.at(key);
        const long double e = v.is_number_unsigned() ? (long double)v.get<unsigned long long>()
                                                     : (long double)v.get<long long>();
        if (e < lo || e > hi) rangeError(key, "value", dumpJson(v), lo, hi);
    }
    if (x < lo || x > hi) rangeError(key, "value", x, lo, hi);
    return x;
}

double JsonReader::wholeNumber(const std::string& key, double def, double lo, double hi) {
    const double x = number(key, def, lo, hi);
    if (x != std::floor(x)) error(key, "expected a non-negative integer");
    // From 2^52 on a double holds no fraction, and from 2^53 on doubles are 2 apart:
    // 9007199254740993.0 was read as 2^53 and rendered as that seed (helper 127), where the same
    // digits without ".0" are refused as out of range, and 4503599627370496.5 as ...496 (helper
    // 129).
    if (std::abs(x) >= kDoubleHoldsFractionsBelow && j_.contains(key) &&
        j_.at(key).is_number_float())
        error(key, std::string(kWrittenAsADouble) + " (it reads as " + dumpJson(j_.at(key)) + ")");
    return x;
}

int JsonReader::integer(const std::string& key, int def, int lo, int hi) {
    used_.insert(key);
    if (!j_.contains(key)) {
        note(key, def);
        return def;
    }
    const Json& v = j_.at(key);
    // An integral number written with a fraction or an exponent (4.0, 4e0) is that integer: JSON
    // numbers have no kind, and a sweep's values compare as numbers (canonicalJson).
    const double d = v.is_number_float() ? v.get<double>() : 0;
    if (!v.is_number_integer() && !(v.is_number_float() && std::isfinite(d) && d == std::floor(d)))
        error(key, "expected an integer, got " + typeAndValue(v));
    // (Out of range before the conversion to an integer: 1e300 or 2^64 would not fit.)
    if ((v.is_number_float() && !(d >= lo && d <= hi)) ||
        (v.is_number_unsigned() && v.get<unsigned long long>() > (unsigned long long)hi))
        rangeError(key, "value", dumpJson(v), lo, hi);
    const long long x = v.is_number_float() ? (long long)d : v.get<long long>();
    if (x < lo || x > hi) rangeError(key, "value", dumpJson(v), lo, hi);
    note(key, x);
    return int(x);
}

std::optional<int> JsonReader::integerOrAuto(const std::string& key, int lo, int hi) {
    if (has(key) && !raw(key).is_string()) return integer(key, lo, lo, hi);
    if (string(key, "auto") != "auto")
        error(key, "expected an integer " + std::to_string(lo) + " … " + std::to_string(hi) +
                       " or \"auto\"");
    return std::nullopt;
}

std::optional<double> JsonReader::numberOrAuto(const std::string& key, double lo, double hi) {
    if (has(key) && !raw(key).is_string()) return number(key, lo, lo, hi);
    if (string(key, "auto") != "auto") {
        std::ostringstream m;
        m << "expected a number in [" << lo << ", " << hi << "] or \"auto\"";
        error(key, m.str());
    }
    return std::nullopt;
}

std::optional<bool> JsonReader::booleanOrAuto(const std::string& key) {
    if (has(key) && !raw(key).is_string()) return boolean(key, true);
    if (string(key, "auto") != "auto") error(key, "expected true, false or \"auto\"");
    return std::nullopt;
}

bool JsonReader::boolean(const std::string& key, bool def) {
    used_.insert(key);
    bool b = def;
    if (j_.contains(key)) {
        const Json& v = j_.at(key);
        if (!v.is_boolean()) error(key, "expected true or false, got " + typeAndValue(v));
        b = v.get<bool>();
    }
    note(key, b);
    return b;
}

std::string JsonReader::string(const std::string& key, std::optional<std::string> def) {
    used_.insert(key);
    if (!j_.contains(key) && def) {
        note(key, *def);
        return *def;
    }
    const Json& v = get(key, "string");
    if (!v.is_string()) error(key, "expected a string, got " + typeAndValue(v));
    note(key, v);
    return v.get<std::string>();
}

std::string JsonReader::choice(const std::string& key, const std::string& def,
                               std::initializer_list<const char*> choices) {
    const std::string s = string(key, def);
    std::string list;
    for (const char* c : choices) {
        if (s == c) return s;
        list += (list.empty() ? "" : ", ") + std::string("\"") + c + "\"";
    }
    error(key, "unknown value \"" + s + "\"; expected one of " + list);
}

Vec3 JsonReader::vec3(const std::string& key, std::optional<Vec3> def) {
    return threeNumbers(key, def, "an array of 3 numbers", "array of 3 numbers");
}

Vec3 JsonReader::threeNumbers(const std::string& key, std::optional<Vec3> def, const char* expected,
                              const char* kind) {
    used_.insert(key);
    if (!j_.contains(key) && def) {
        note(key,
             {writtenDefault((*def)[0]), writtenDefault((*def)[1]), writtenDefault((*def)[2])});
        return *def;
    }
    const Json& v = get(key, kind);
    if (!v.is_array() || v.size() != 3)
        error(key, std::string("expected ") + expected + ", got " + typeAndValue(v));
    Vec3 r;
    for (int i = 0; i < 3; ++i) {
        if (!v[i].is_number())
            fail(file_, keyPath(key) + "[" + std::to_string(i) + "]",
                 "expected a number, got " + typeAndValue(v[i]));
        r[i] = v[i].get<double>();
    }
    note(key, v);
    return r;
}

Vec3 JsonReader::vec3OrScalar(const std::string& key, std::optional<Vec3> def) {
    if (j_.contains(key) && j_.at(key).is_number()) {
        const double x = number(key);
        return Vec3(x, x, x);
    }
    // (The error said "an array of 3 numbers" to a scale, which takes a number too; helper 161.)
    return threeNumbers(key, def, "a number or an array of 3 numbers",
                        "number or array of 3 numbers");
}

JsonReader JsonReader::object(const std::string& key) {
    used_.insert(key);
    JsonReader child(get(key, "object"), file_, keyPath(key));
    if (resolved_) child.recordInto(&((*resolved_)[key] = Json::object()));
    return child;
}

JsonReader JsonReader::objectOrEmpty(const std::string& key) {
    static const Json empty = Json::object();
    if (j_.contains(key)) return object(key);
    used_.insert(key);
    JsonReader child(empty, file_, keyPath(key));
    if (resolved_) child.recordInto(&((*resolved_)[key] = Json::object()));
    return child;
}

const Json& JsonReader::raw(const std::string& key) {
    used_.insert(key);
    const Json& v = get(key, "value");
    note(key, v);
    return v;
}

std::string JsonReader::pathName(const std::string& key, const std::string& what,
                                 std::optional<std::string> def) {
    const std::string name = string(key, std::move(def));
    if (name.empty()) error(key, "expected a " + what + " name, got an empty string");
    if (name.find('\0') != std::string::npos)
        error(key, "the " + what + " name contains a NUL character (\\u0000)");
    return name;
}

std::string JsonReader::inputFile(const std::string& key, const std::string& dir) {
    namespace fs = std::filesystem;
    const std::string name = pathName(key, "file");
    const std::string path = fs::path(name).is_absolute() || dir.empty()
                                 ? name
                                 : (fs::path(dir) / name).lexically_normal().string();
    const std::string problem = inputFileProblem(path);
    if (!problem.empty()) error(key, problem + ": " + path);
    return path;
}

void JsonReader::finish() const {
    for (auto it = j_.begin(); it != j_.end(); ++it)
        if (!used_.count(it.key())) {
            std::vector<std::string> known(used_.begin(), used_.end());
            known.insert(known.end(), asked_.begin(), asked_.end());
            error(it.key(), unknownKey(nearestSpelling(it.key(), known)));
        }
}

}  // namespace shvol
