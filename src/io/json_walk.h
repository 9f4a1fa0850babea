#pragma once
/// \file JsonWalk: the structure of a JSON text (places, keys, depth) in one pass, for
/// json_reader.cpp's checks before a text is parsed.
#include <algorithm>
#include <cstddef>
#include <functional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "shvol/io/json_reader.h"

namespace shvol {

/// A JSON text as nlohmann's SAX parser reads it, building nothing: the place (JSON path) of each
/// open object or array and the keys each object has had, to find nesting deeper than
/// kMaxJsonDepth (tooDeep(place) must throw; the place names the first levels) and the first key
/// given twice in one object (repeated, at repeatedAt). Linear in the text: the DOM parser's
/// callback, used for this until 7 Dec, scans the enclosing array or object after every object
/// it keeps, quadratic in an array of objects (32,000 spheres: 2.8 s to read a 2 MB scene;
/// helper 127). A malformed text stops the walk (sax_parse returns false): the DOM parser then
/// names the place.
class JsonWalk final : public nlohmann::json_sax<Json> {
  public:
    JsonWalk(std::string root, std::function<void(const std::string&)> tooDeep)
        : root_(std::move(root)), tooDeep_(std::move(tooDeep)) {}
    std::string repeatedAt, repeated;

    bool null() override { return element(); }
    bool boolean(bool) override { return element(); }
    bool number_integer(number_integer_t) override { return element(); }
    bool number_unsigned(number_unsigned_t) override { return element(); }
    bool number_float(number_float_t, const string_t&) override { return element(); }
    bool string(string_t&) override { return element(); }
    bool binary(binary_t&) override { return element(); }
    bool start_object(std::size_t) override { return open(false); }
    bool start_array(std::size_t) override { return open(true); }
    bool end_object() override { return close(); }
    bool end_array() override { return close(); }
    bool key(string_t& k) override {
        Frame& f = frames_.back();
        f.key = k;
        if (!f.keys.insert(k).second && repeated.empty())
            repeatedAt = where(frames_.size() - 1), repeated = k;
        return true;
    }
    bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override {
        return false;
    }

  private:
    struct Frame {
        bool array;
        long index = -1;  ///< of the array's element being read
        std::string key;  ///< of the object's member being read
        std::set<std::string> keys;
    };
    bool element() {
        if (!frames_.empty() && frames_.back().array) ++frames_.back().index;
        return true;
    }
    bool open(bool array) {
        element();
        frames_.push_back(Frame{array, -1, {}, {}});
        if (frames_.size() > kMaxJsonDepth)  // (named by its first levels)
            tooDeep_(where(std::min<size_t>(frames_.size() - 1, 4)) + "…");
        return true;
    }
    bool close() {
        frames_.pop_back();
        return true;
    }
    /// The JSON path of the value being read at `depth` levels down.
    std::string where(size_t depth) const {
        std::string at = root_;
        for (size_t k = 0; k < depth; ++k)
            at += frames_[k].array ? "[" + std::to_string(frames_[k].index) + "]"
                                   : (at.empty() ? "" : ".") + frames_[k].key;
        return at.empty() ? std::string("(top level)") : at;
    }
    std::string root_;
    std::function<void(const std::string&)> tooDeep_;
    std::vector<Frame> frames_;
};

}  // namespace shvol
