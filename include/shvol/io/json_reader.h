#pragma once
/// \file Strict, path-aware reading of JSON objects: every key is typed and checked, unknown keys
/// are errors, and every message names the file and the JSON path (e.g. media[0].phase.g).
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>

#include "shvol/core/error.h"
#include "shvol/core/math.h"

namespace shvol {

using Json = nlohmann::json;

/// j as JSON text; invalid UTF-8 in strings (e.g. a file name) is replaced by U+FFFD instead of
/// throwing. indent < 0: one line.
inline std::string dumpJson(const Json& j, int indent = -1) {
    return j.dump(indent, ' ', false, Json::error_handler_t::replace);
}

/// j as one line of JSON text in which equal values read the same: a number with an integral
/// value is written as an integer (1.0 and -0.0 as 1 and 0; nlohmann already sorts object keys).
/// Where a sweep asks whether two values are the same (a finished run's, an axis given a value
/// twice) it compares these texts, so that 1 and 1.0 are one value, as they are one render.
std::string canonicalJson(const Json& j);

/// Objects and arrays inside each other deeper than any scene, sweep or phase specification needs
/// (the deepest value of a scene or a sweep, a tabulated phase function's [angle, value] pair in
/// an axis's value, is under 12 levels down): the recursive copies and walks of a value 10⁵ levels
/// deep overflow the stack (helper 96: 100 000 nested arrays under "media", a 200 kB file, crashed
/// `render`).
inline constexpr size_t kMaxJsonDepth = 256;
/// Json::parse(text), after a walk of the text that calls tooDeep(), which must throw, where the
/// nesting passes kMaxJsonDepth, counted as parseJsonText counts (kMaxJsonDepth objects and arrays
/// inside each other pass), before anything is built: for texts read without parseJsonText's
/// messages. Throws Json::exception where the text is malformed.
Json parseWithinDepth(const std::string& text, const std::function<void()>& tooDeep);
/// The refusal's words: "objects and arrays nested more than 256 levels deep".
std::string tooDeepMessage();

/// text as a message quotes it: whole up to `limit` characters, else its first limit − 3 and
/// "..." (a --set value or a phase specification of 200 kB was quoted whole: helper 96).
std::string briefText(const std::string& text, size_t limit = 40);
/// What a value of the wrong type is, for "expected …, got " + typeAndValue(j): its type and
/// its text, `string "x"`, `array [1]`; a null is only `null` (it printed "null null").
std::string typeAndValue(const Json& j);

/// A file shvol wrote itself (a render's stats), read where it is only consulted: its JSON, or a
/// discarded value (is_discarded()) if it is malformed or nested deeper than kMaxJsonDepth.
Json parseOwnJsonFile(const std::string& path);

/// Parses a whole file; errors name the file and the line/column.
Json parseJsonFile(const std::string& path);
/// Parses JSON text from `file` (a file name, or what names the text in errors): a malformed text
/// or a NUL byte is refused at its line and column, a key given twice in one object (which the
/// parser would keep silently, the last value winning) at the object's JSON path, which starts
/// at `root` (the text's place in a larger document; empty: the top level). Nesting deeper than
/// kMaxJsonDepth is refused where it passes that depth, before the value is built.
Json parseJsonText(const std::string& text, const std::string& file, const std::string& root = "");

/// Applies an override "a.b.0.c=value" (or "a.b[0].c=value") to a document, creating objects
/// along the path. The value is parsed as JSON when it is valid JSON, else taken as a string.
/// `key=null` deletes the key, so its default applies again. Setting `type` to a different value
/// replaces the object by {"type": value}, so no key of the old type survives; later overrides
/// add the new type's keys. A relative path assigned to a key named `file` is made absolute
/// against the current directory. Errors where the scene cannot take the assignment (an index
/// beyond an array, a key inside a number) say `source` ("--set: index 3 out of range …"); an
/// empty `source` leaves it out (a sweep names its own key instead). False when it changed
/// nothing: `key=null` where the document has no such key (a typo, or a key already absent).
bool applyOverride(Json& doc, const std::string& assignment, const std::string& file,
                   const std::string& source = "--set");
/// 2^52: from it on a double holds no fraction (and from 2^53 on, not every integer), so that a
/// whole number written with a fraction or an exponent (4503599627370496.5, 9007199254740993.0)
/// may not be the number read. Whole-number keys (seeds) refuse such a number: kWrittenAsADouble.
inline constexpr double kDoubleHoldsFractionsBelow = 4503599627370496.0;
inline constexpr const char* kWrittenAsADouble =
    "written with a fraction or an exponent, and from 2^52 on a double cannot hold the fraction "
    "(nor, from 2^53 on, tell neighbouring integers apart): write it as an integer";
/// An assignment as errors name it: "--set key=value", a long value by its beginning (briefText).
std::string overridePlace(const std::string& assignment);
/// The index in `overrides` (key=value assignments as applyOverride takes them) of the one that
/// set the value an error of the document read after them is about, or −1: the error `message`
/// must be "file: place: reason", `place` present in the document `after` the overrides and
/// absent from the document `before` them or (unless the error is an unknown key) different
/// there (else it is the file's own), and inside the key an override sets (the last such); or
/// `place` missing after them from an object that an override changed (its type: a key the new
/// type asks for), the last override inside that object. placeAndReason gets "place: reason". So
/// that a misspelt or out-of-range --set, or a sweep's `set` or axis, is named as the culprit
/// rather than the scene file, which lacks the key or says something else (helpers 127, 133,
/// 137). A file name with control characters, which errors escape, is not matched: the error is
/// left as it is.
int overrideOfError(const std::string& message, const std::string& file, const Json& before,
                    const Json& after, const std::vector<std::string>& overrides,
                    std::string* placeAndReason = nullptr);
/// Applies `overrides` to `doc` in turn (applyOverride; `unchanged`, optional, gets those that
/// changed nothing) and returns, for each, the index of the later override that removed the value
/// it set, or −1 (kept, set again later, or a deletion): a new type of an object that holds it
/// starts the object afresh, or the object is replaced or deleted. So that `--set
/// media.0.phase.g=0.5 --set media.0.phase.type=rayleigh` does not drop the user's g without a
/// word (helpers 139, 140: the override that removed it, not the last of its object's).
std::vector<int> applyOverrides(Json& doc, const std::vector<std::string>& overrides,
                                const std::string& file,
                                std::vector<std::string>* unchanged = nullptr);
/// A key path as applyOverride walks it: media[0].albedo (the notation of error messages) is
/// media.0.albedo.
std::string canonicalKeyPath(const std::string& key);
/// Why `key` is not a key path (names joined by '.', each followed by any indices in brackets:
/// media[0].phase.g, media.0.phase.g), as applyOverride refuses it; empty if it is one. With
/// `parts`, appends its components as it reads them (media, 0, phase, g).
std::string keyPathProblem(const std::string& key, std::vector<std::string>* parts = nullptr);
/// Whether an override of `key` by `value` sets the key path `target` (components, "*" for any
/// one): the key itself, or an object or array holding it that the value gives
/// (render={"spp": 3} sets render.spp; media.0={…, "lookup": …} sets media.*.lookup).
bool overrideSets(const std::string& key, const Json& value,
                  const std::vector<std::string>& target);
/// The first of the "key=value" overrides that sets `target` (overrideSets), or null.
const std::string* overrideSetting(const std::vector<std::string>& sets,
                                   const std::vector<std::string>& target);
/// The value of an override "key=text" as applyOverride reads it: the JSON text parsed, or the
/// text itself as a string when it is not valid JSON; a number beyond a double's range (1e400)
/// is an error. Errors name `file` and `where`, the override as its source gives it ("--set
/// key=value" on the command line, "set[2]" in a sweep file), and a key repeated inside the
/// value by its JSON path under `place`, the path the value is assigned to (media[0].phase),
/// which also names an error without `where`.
Json overrideValue(const std::string& text, const std::string& place, const std::string& file = "",
                   const std::string& where = "");

class JsonReader {
  public:
    JsonReader(const Json& j, std::string file, std::string path);
    /// Checked at construction: the value must be an object.
    const std::string& path() const { return path_; }
    const std::string& file() const { return file_; }
    bool has(const std::string& key) const;

    double number(const std::string& key, std::optional<double> def = {});
    /// number in [lo, hi]
    double number(const std::string& key, double def, double lo, double hi);
    int integer(const std::string& key, int def, int lo, int hi);
    /// A whole number in [lo, hi] for 0 ≤ lo ≤ hi ≤ 2^53 (seeds, counts beyond an int):
    /// "expected a non-negative integer" for a fraction.
    double wholeNumber(const std::string& key, double def, double lo, double hi);
    /// An integer in [lo, hi], or "auto" (also when the key is absent): nullopt.
    std::optional<int> integerOrAuto(const std::string& key, int lo, int hi);
    /// A number in [lo, hi], or "auto" (also when the key is absent): nullopt.
    std::optional<double> numberOrAuto(const std::string& key, double lo, double hi);
    bool boolean(const std::string& key, bool def);
    /// true or false, or "auto" (also when the key is absent): nullopt.
    std::optional<bool> booleanOrAuto(const std::string& key);
    std::string string(const std::string& key, std::optional<std::string> def = {});
    /// The input file string `key` names: not empty, resolved against directory `dir` when
    /// relative (dir empty: as given), and an existing regular file; otherwise an error naming
    /// the key and the resolved path ("s.json: media[0].file: no such file: /data/c.vdb").
    std::string inputFile(const std::string& key, const std::string& dir);
    /// string(key, def) as the name of a file or directory (`what`: "file", "directory"): an
    /// empty name is refused, and so is one with a NUL character (JSON allows \u0000; the
    /// system's calls would read the name only up to it).
    std::string pathName(const std::string& key, const std::string& what,
                         std::optional<std::string> def = {});
    /// One of the listed strings.
    std::string choice(const std::string& key, const std::string& def,
                       std::initializer_list<const char*> choices);
    Vec3 vec3(const std::string& key, std::optional<Vec3> def = {});
    /// A number s (meaning (s, s, s)) or a 3-array.
    Vec3 vec3OrScalar(const std::string& key, std::optional<Vec3> def = {});
    JsonReader object(const std::string& key);
    /// The object at key, or an empty object (all defaults) when the key is absent.
    JsonReader objectOrEmpty(const std::string& key);
    const Json& raw(const std::string& key);
    /// Raises an error naming the first key that was never read.
    void finish() const;

    [[noreturn]] void error(const std::string& key, const std::string& msg) const;
    /// read(), the contents of the input file that this object's `key` names, with an error in
    /// the file named with the scene and the key as well as the file's own place (scene.json:
    /// media[0].file: cloud.vdb: grid 'smoke': no such grid): the file's place alone did not say
    /// which object of which scene named it (helpers 143, 181, 183).
    template <typename Read>
    auto readInput(const std::string& key, Read&& read) const {
        try {
            return read();
        } catch (const Error& e) {
            error(key, e.what());
        }
    }
    /// The error of a value x outside [lo, hi]: "<what> x out of range [lo, hi]", or "… (expected
    /// ≥ lo)" when hi ≥ kUnbounded ("… (expected at most 1e30)" for an x above it); whole
    /// numbers below 10^6 in full, others as the shortest decimal that reads back, with a plain
    /// exponent (2^53 in full, not 9.0072e+15; 10^12 as 1e12; 0.1 as 0.1).
    [[noreturn]] void rangeError(const std::string& key, const std::string& what, double x,
                                 double lo, double hi) const;
    /// The same with the value as written (an integer beyond 2^53 exactly).
    [[noreturn]] void rangeError(const std::string& key, const std::string& what,
                                 const std::string& x, double lo, double hi) const;
    /// An upper bound that only keeps a value finite (e.g. a radiance's 1e30): shown only to a
    /// value beyond it.
    static constexpr double kUnbounded = 1e30;

    /// Records every value read from now on — defaults included — into *node, as the resolved
    /// document (objects read through object() record into node[key]). node must outlive the
    /// reader and its children, and must not be reallocated meanwhile.
    void recordInto(Json* node) { resolved_ = node; }
    /// Records a value that was derived rather than read (e.g. "order": "auto").
    void note(const std::string& key, const Json& value) {
        if (resolved_) (*resolved_)[key] = value;
    }
    std::string keyPath(const std::string& key) const;

  private:
    const Json& get(const std::string& key, const char* type) const;
    /// vec3, whose errors say the value expected is `expected` ("an array of 3 numbers"), and a
    /// missing one `kind` ("array of 3 numbers").
    Vec3 threeNumbers(const std::string& key, std::optional<Vec3> def, const char* expected,
                      const char* kind);
    const Json& j_;
    std::string file_, path_;
    std::set<std::string> used_;
    /// Keys asked about with has(): known to the reader, so finish() suggests them for a typo
    /// (helper 86: a sweep's "axis" got no "did you mean", its "repeat" did), though not used.
    mutable std::set<std::string> asked_;
    Json* resolved_ = nullptr;
};

}  // namespace shvol
