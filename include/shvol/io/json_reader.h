#pragma once
/// \file Strict, path-aware reading of JSON objects: every key is typed and checked, unknown keys
/// are errors, and every message names the file and the JSON path (e.g. media[0].phase.g).
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>

#include "shvol/core/math.h"

namespace shvol {

using Json = nlohmann::json;

/// Parses a whole file; errors name the file and the line/column.
Json parseJsonFile(const std::string& path);

/// Applies an override "a.b.0.c=value" (or "a.b[0].c=value") to a document, creating objects
/// along the path. The value is parsed as JSON when it is valid JSON, else taken as a string.
/// `key=null` deletes the key, so its default applies again. Setting `type` to a different value
/// replaces the object by {"type": value}, so no key of the old type survives; later overrides
/// add the new type's keys. A relative path assigned to a key named `file` is made absolute
/// against the current directory.
void applyOverride(Json& doc, const std::string& assignment, const std::string& file);

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
    bool boolean(const std::string& key, bool def);
    std::string string(const std::string& key, std::optional<std::string> def = {});
    /// One of the listed strings.
    std::string choice(const std::string& key, const std::string& def,
                       std::initializer_list<const char*> choices);
    Vec3 vec3(const std::string& key, std::optional<Vec3> def = {});
    /// A number s (meaning (s, s, s)) or a 3-array.
    Vec3 vec3OrScalar(const std::string& key, std::optional<Vec3> def = {});
    JsonReader object(const std::string& key);
    const Json& raw(const std::string& key);
    /// Raises an error naming the first key that was never read.
    void finish() const;

    [[noreturn]] void error(const std::string& key, const std::string& msg) const;
    std::string keyPath(const std::string& key) const;

  private:
    const Json& get(const std::string& key, const char* type) const;
    const Json& j_;
    std::string file_, path_;
    std::set<std::string> used_;
};

}  // namespace shvol
