#include "shvol/io/mesh_file.h"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <set>
#include <unordered_map>
#include <unordered_set>

#include "shvol/core/error.h"
#include "shvol/core/input_file.h"

namespace shvol {

namespace {

/// The whole regular file at path.
std::string readWhole(const std::string& path) {
    const uintmax_t size = regularFileSize(path);
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(path, "", "cannot open file");
    std::string data(size_t(size), '\0');
    in.read(data.data(), std::streamsize(size));
    if (in.gcount() != std::streamsize(size)) fail(path, "", "read error");
    return data;
}

/// s quoted for a message: at most 40 characters, control and non-ASCII bytes shown as '?', so
/// that the error stays one readable line.
std::string quote(std::string_view s) {
    std::string q = "\"";
    for (size_t i = 0; i < s.size() && i < 40; ++i) q += (s[i] >= 0x20 && s[i] < 0x7f) ? s[i] : '?';
    return q + (s.size() > 40 ? "...\"" : "\"");
}

bool isBlank(char c) {
    return c == ' ' || c == '\t' || c == '\r';
}

/// A whole-token integer or floating-point number (a leading '+' is allowed; "nan" and "inf"
/// parse as such). false if the token is not one number or is out of range.
template <typename T>
bool parseToken(std::string_view t, T* x) {
    if (t.size() > 1 && t[0] == '+' && t[1] != '-') t.remove_prefix(1);
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), *x);
    return ec == std::errc() && end == t.data() + t.size();
}

// ---------------------------------------------------------------------------------------------
// PLY

/// Largest list a PLY record may hold (a polygon of more vertices is not a mesh face).
constexpr uint64_t kMaxPlyList = 1u << 16;

enum class Type : uint8_t { I8, U8, I16, U16, I32, U32, F32, F64 };

struct TypeName {
    const char* name;
    Type type;
};
constexpr TypeName kTypeNames[] = {
    {"char", Type::I8},   {"uchar", Type::U8},   {"short", Type::I16},   {"ushort", Type::U16},
    {"int", Type::I32},   {"uint", Type::U32},   {"float", Type::F32},   {"double", Type::F64},
    {"int8", Type::I8},   {"uint8", Type::U8},   {"int16", Type::I16},   {"uint16", Type::U16},
    {"int32", Type::I32}, {"uint32", Type::U32}, {"float32", Type::F32}, {"float64", Type::F64},
};

size_t sizeOf(Type t) {
    switch (t) {
        case Type::I8:
        case Type::U8:
            return 1;
        case Type::I16:
        case Type::U16:
            return 2;
        case Type::I32:
        case Type::U32:
        case Type::F32:
            return 4;
        case Type::F64:
            return 8;
    }
    return 0;
}

bool isInteger(Type t) {
    return t != Type::F32 && t != Type::F64;
}

/// Range of an integer type.
void integerRange(Type t, int64_t* lo, int64_t* hi) {
    const int bits = int(8 * sizeOf(t));
    const bool sign = t == Type::I8 || t == Type::I16 || t == Type::I32;
    *lo = sign ? -(int64_t(1) << (bits - 1)) : 0;
    *hi = sign ? (int64_t(1) << (bits - 1)) - 1 : (int64_t(1) << bits) - 1;
}

/// What a property becomes in the mesh.
enum Role : int8_t { kSkip = -1, kX, kY, kZ, kNX, kNY, kNZ, kU, kV, kIndices };

struct Property {
    std::string name;
    Type type = Type::F32;  ///< the value type, or the item type of a list
    bool list = false;
    Type countType = Type::U8;
    int8_t role = kSkip;
    size_t line = 0;
};

struct Element {
    std::string name;
    uint64_t count = 0;
    std::vector<Property> props;
    size_t line = 0;
};

enum class Format { Ascii, BinaryLE, BinaryBE };

struct Header {
    Format format = Format::Ascii;
    std::vector<Element> elements;
    size_t vertex = 0, face = 0;  ///< indices of the elements vertex and face
    size_t bodyOffset = 0;        ///< first byte after end_header's newline
    size_t bodyLine = 0;          ///< number of the line starting there
};

std::vector<std::string_view> splitWords(std::string_view line) {
    std::vector<std::string_view> w;
    size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && isBlank(line[i])) ++i;
        const size_t b = i;
        while (i < line.size() && !isBlank(line[i])) ++i;
        if (i > b) w.push_back(line.substr(b, i - b));
    }
    return w;
}

class HeaderParser {
  public:
    HeaderParser(std::string_view bytes, const std::string& file) : bytes_(bytes), file_(file) {}

    Header parse() {
        // A UTF-8 byte-order mark (a text editor's) is skipped, as for OBJ; the body's offsets
        // stay the file's (helper 161).
        pos_ = utf8BomLength(bytes_);
        if (bytes_.substr(pos_, 3) != "ply" || !nextLine() || line_ != "ply")
            fail(file_, "line 1", "not a PLY file (the first line must be \"ply\")");
        bool format = false;
        while (true) {
            if (!nextLine()) fail(file_, at(), "end of file before end_header");
            const std::vector<std::string_view> w = splitWords(line_);
            if (w.empty()) fail(file_, at(), "empty header line");
            const std::string_view key = w[0];
            if (key == "comment" || key == "obj_info") continue;
            if (key == "end_header") {
                if (w.size() != 1) fail(file_, at(), "end_header takes no arguments");
                break;
            }
            if (key == "format") {
                if (format) fail(file_, at(), "format given twice");
                if (!h_.elements.empty()) fail(file_, at(), "format must come before the elements");
                if (w.size() != 3) fail(file_, at(), "expected \"format TYPE 1.0\"");
                if (w[1] == "ascii") {
                    h_.format = Format::Ascii;
                } else if (w[1] == "binary_little_endian") {
                    h_.format = Format::BinaryLE;
                } else if (w[1] == "binary_big_endian") {
                    h_.format = Format::BinaryBE;
                } else {
                    fail(file_, at(),
                         "unknown format " + quote(w[1]) +
                             " (expected ascii, binary_little_endian or binary_big_endian)");
                }
                if (w[2] != "1.0") fail(file_, at(), "unsupported PLY version " + quote(w[2]));
                format = true;
            } else if (key == "element") {
                if (w.size() != 3) fail(file_, at(), "expected \"element NAME COUNT\"");
                Element e;
                e.name = std::string(w[1]);
                const auto digit = [](char c) { return c >= '0' && c <= '9'; };
                if (!std::all_of(w[2].begin(), w[2].end(), digit) || !parseToken(w[2], &e.count))
                    fail(file_, at(), "element count " + quote(w[2]) + " is not a whole number");
                e.line = lineNo_;
                if (!elementNames_.insert(w[1]).second)
                    fail(file_, at(), "element " + quote(e.name) + " twice");
                propertyNames_.clear();
                h_.elements.push_back(std::move(e));
            } else if (key == "property") {
                if (h_.elements.empty()) fail(file_, at(), "property before any element");
                Property p;
                p.line = lineNo_;
                if (w.size() >= 2 && w[1] == "list") {
                    if (w.size() != 5)
                        fail(file_, at(), "expected \"property list COUNT_TYPE ITEM_TYPE NAME\"");
                    p.list = true;
                    p.countType = type(w[2]);
                    p.type = type(w[3]);
                    if (!isInteger(p.countType))
                        fail(file_, at(), "list count type " + quote(w[2]) + " is not an integer");
                    p.name = std::string(w[4]);
                } else {
                    if (w.size() != 3) fail(file_, at(), "expected \"property TYPE NAME\"");
                    p.type = type(w[1]);
                    p.name = std::string(w[2]);
                }
                Element& e = h_.elements.back();
                if (!propertyNames_.insert(w.back()).second)
                    fail(file_, at(),
                         "property " + quote(p.name) + " twice in element " + quote(e.name));
                e.props.push_back(std::move(p));
            } else {
                const bool data = std::isdigit(static_cast<unsigned char>(key[0])) ||
                                  key[0] == '-' || key[0] == '.';
                fail(file_, at(),
                     "unknown header keyword " + quote(key) +
                         (data ? " (data before end_header: is it missing?)" : ""));
            }
        }
        if (!format) fail(file_, at(), "no format line in the header");
        h_.bodyOffset = pos_;
        h_.bodyLine = lineNo_ + 1;
        checkSizes();
        assignRoles();
        return std::move(h_);
    }

  private:
    /// The next header line (without "\n" or "\r\n") into line_; false at the end of the bytes.
    bool nextLine() {
        const size_t nl = bytes_.find('\n', pos_);
        if (nl == std::string_view::npos) return false;
        line_ = bytes_.substr(pos_, nl - pos_);
        if (!line_.empty() && line_.back() == '\r') line_.remove_suffix(1);
        pos_ = nl + 1;
        ++lineNo_;
        return true;
    }
    std::string at() const { return "line " + std::to_string(lineNo_); }
    std::string at(size_t line) const { return "line " + std::to_string(line); }

    Type type(std::string_view name) const {
        for (const TypeName& t : kTypeNames)
            if (name == t.name) return t.type;
        fail(file_, at(), "unknown type " + quote(name));
    }

    /// Marks the properties the mesh uses and checks that the ones it needs are there.
    void assignRoles() {
        const std::string endLine = at();
        bool vertex = false, face = false;
        for (size_t i = 0; i < h_.elements.size(); ++i) {
            Element& e = h_.elements[i];
            if (e.name == "vertex") {
                h_.vertex = i;
                vertex = true;
                const char* const names[][3] = {{"x", "", ""},           {"y", "", ""},
                                                {"z", "", ""},           {"nx", "", ""},
                                                {"ny", "", ""},          {"nz", "", ""},
                                                {"u", "s", "texture_u"}, {"v", "t", "texture_v"}};
                const Property* by[kIndices] = {};
                for (Property& p : e.props)
                    for (int r = 0; r < kIndices; ++r)
                        for (const char* n : names[r])
                            if (*n && p.name == n) {
                                if (p.list)
                                    fail(
                                        file_, at(p.line),
                                        "vertex property " + quote(p.name) + " must not be a list");
                                if (by[r])
                                    fail(file_, at(p.line),
                                         "vertex properties " + quote(by[r]->name) + " and " +
                                             quote(p.name) + " give the same coordinate");
                                p.role = int8_t(r);
                                by[r] = &p;
                            }
                for (int r : {kX, kY, kZ})
                    if (!by[r])
                        fail(file_, at(e.line),
                             "element vertex has no property " + std::string(names[r][0]));
                const auto allOrNone = [&](int first, int n, const char* what) {
                    for (int r = first; r < first + n; ++r)
                        if (bool(by[r]) != bool(by[first]))
                            fail(file_, at(e.line),
                                 std::string("element vertex has only some of the ") + what +
                                     " properties");
                };
                allOrNone(kNX, 3, "normal (nx, ny, nz)");
                allOrNone(kU, 2, "texture coordinate (u, v)");
                if (e.count > std::numeric_limits<uint32_t>::max())
                    fail(file_, at(e.line), "more than 2^32 - 1 vertices");
            } else if (e.name == "face") {
                h_.face = i;
                face = true;
                const Property* indices = nullptr;
                for (Property& p : e.props)
                    if (p.name == "vertex_indices" || p.name == "vertex_index") {
                        if (indices)
                            fail(file_, at(p.line),
                                 "element face has both vertex_indices and vertex_index");
                        if (!p.list || !isInteger(p.type))
                            fail(file_, at(p.line),
                                 "face property " + p.name + " must be a list of integers");
                        p.role = kIndices;
                        indices = &p;
                    }
                if (!indices)
                    fail(file_, at(e.line), "element face has no list property vertex_indices");
            }
        }
        if (!vertex) fail(file_, endLine, "the header declares no element vertex");
        if (!face) fail(file_, endLine, "the header declares no element face");
    }

    /// Rejects element counts that the bytes after the header cannot hold, before anything is
    /// allocated: a record takes at least its fixed-size values and list counts (binary), or at
    /// least two characters per value, a separator included (ascii).
    void checkSizes() const {
        uint64_t left = bytes_.size() - h_.bodyOffset;
        const bool ascii = h_.format == Format::Ascii;
        if (ascii) left = (left + 1) / 2;  // values the rest can hold at most
        for (const Element& e : h_.elements) {
            uint64_t least = 0;
            for (const Property& p : e.props)
                least += ascii ? 1 : sizeOf(p.list ? p.countType : p.type);
            if (least == 0 || e.count == 0) continue;
            if (e.count > left / least)
                fail(file_, at(e.line),
                     "element " + quote(e.name) + " claims " + std::to_string(e.count) +
                         " records, but the rest of the file holds at most " +
                         std::to_string(left / least));
            left -= e.count * least;
        }
    }

    std::string_view bytes_;
    const std::string& file_;
    Header h_;
    // Names seen so far (views into bytes_), for duplicates in linear time.
    std::unordered_set<std::string_view> elementNames_, propertyNames_;
    size_t pos_ = 0, lineNo_ = 0;
    std::string_view line_;
};

/// Names record k of element e in messages ("vertex 3", "face 7", "record 2 of element x").
std::string recordName(const Element& e, uint64_t k) {
    if (e.name == "vertex" || e.name == "face") return e.name + " " + std::to_string(k);
    return "record " + std::to_string(k) + " of element " + quote(e.name);
}

/// Binary body: values at increasing byte offsets, in the file's byte order.
class BinaryBody {
  public:
    BinaryBody(std::string_view bytes, size_t offset, bool bigEndian, const std::string& file)
        : bytes_(bytes), start_(offset), pos_(offset), mark_(offset), file_(file) {
        const uint16_t one = 1;
        unsigned char first;
        std::memcpy(&first, &one, 1);
        swap_ = bigEndian == (first == 1);
    }

    void beginRecord(const Element& e, uint64_t k) {
        e_ = &e;
        k_ = k;
    }
    void endRecord() {}

    double scalar(Type t) {
        mark_ = pos_;
        const size_t n = sizeOf(t);
        if (bytes_.size() - pos_ < n)
            fail(file_, place(), "end of file inside " + recordName(*e_, k_));
        unsigned char b[8];
        std::memcpy(b, bytes_.data() + pos_, n);
        if (swap_) std::reverse(b, b + n);
        pos_ += n;
        switch (t) {
            case Type::I8:
                return load<int8_t>(b);
            case Type::U8:
                return load<uint8_t>(b);
            case Type::I16:
                return load<int16_t>(b);
            case Type::U16:
                return load<uint16_t>(b);
            case Type::I32:
                return load<int32_t>(b);
            case Type::U32:
                return load<uint32_t>(b);
            case Type::F32:
                return load<float>(b);
            case Type::F64:
                return load<double>(b);
        }
        return 0;
    }

    /// Checks that `count` items of type t follow, so that a list is never read past the end.
    void expectItems(uint64_t count, Type t) {
        if (count > (bytes_.size() - pos_) / sizeOf(t))
            fail(file_, place(), "end of file inside " + recordName(*e_, k_));
    }

    void skipList(uint64_t count, Type t) {
        expectItems(count, t);
        pos_ += size_t(count) * sizeOf(t);
    }

    void finish() {
        mark_ = pos_;
        if (pos_ != bytes_.size())
            fail(file_, place(),
                 std::to_string(bytes_.size() - pos_) + " bytes after the last element");
    }

    std::string place() const { return "byte " + std::to_string(mark_); }
    size_t size() const { return bytes_.size() - start_; }  ///< bytes in the body

  private:
    template <typename T>
    static double load(const unsigned char* b) {
        T x;
        std::memcpy(&x, b, sizeof x);
        return double(x);
    }

    std::string_view bytes_;
    size_t start_, pos_, mark_;
    bool swap_ = false;
    const std::string& file_;
    const Element* e_ = nullptr;
    uint64_t k_ = 0;
};

/// ASCII body: one record per line, values separated by spaces or tabs; blank lines are skipped.
class AsciiBody {
  public:
    AsciiBody(std::string_view text, size_t offset, size_t line, const std::string& file)
        : text_(text), start_(offset), pos_(offset), line_(line), file_(file) {}

    void beginRecord(const Element& e, uint64_t k) {
        e_ = &e;
        k_ = k;
        skipBlankLines();
        if (pos_ == text_.size()) fail(file_, place(), "end of file: expected " + recordName(e, k));
        end_ = std::min(text_.find('\n', pos_), text_.size());
    }

    void endRecord() {
        while (pos_ < end_ && isBlank(text_[pos_])) ++pos_;
        if (pos_ < end_)
            fail(file_, place(), "more values than the header declares for " + recordName(*e_, k_));
        if (pos_ < text_.size()) {
            ++pos_;
            ++line_;
        }
    }

    double scalar(Type t) {
        const std::string_view tok = token();
        if (isInteger(t)) {
            int64_t x, lo, hi;
            integerRange(t, &lo, &hi);
            if (!parseToken(tok, &x) || x < lo || x > hi)
                fail(file_, place(),
                     quote(tok) + " in " + recordName(*e_, k_) + " is not an integer from " +
                         std::to_string(lo) + " to " + std::to_string(hi));
            return double(x);
        }
        double x;
        if (!parseToken(tok, &x))
            fail(file_, place(),
                 quote(tok) + " in " + recordName(*e_, k_) +
                     " is not a number (or is out of range)");
        // A float property holds what a float can (a binary file could not hold more): 1e39 was
        // kept as a double, and refused later by the scene's coordinate check, without the
        // file's place (helper 127). Refused where it would round to an infinite float, from
        // (2 − 2⁻²⁴)·2¹²⁷ on: the largest float as printed, 3.4028235e+38, a little above the
        // largest float, rounds down to it (helper 129).
        if (t == Type::F32 && std::isfinite(x) &&
            std::abs(x) >= std::ldexp(2.0 - std::ldexp(1.0, -24), 127))
            fail(file_, place(),
                 quote(tok) + " in " + recordName(*e_, k_) +
                     " is beyond the range of a float (±3.4e38), the property's type");
        return x;
    }

    void expectItems(uint64_t, Type) {}  // each missing value is reported where it is missing

    void skipList(uint64_t count, Type t) {
        for (uint64_t i = 0; i < count; ++i) scalar(t);
    }

    void finish() {
        skipBlankLines();
        if (pos_ < text_.size()) fail(file_, place(), "data after the last element");
    }

    std::string place() const { return "line " + std::to_string(line_); }
    size_t size() const { return text_.size() - start_; }  ///< bytes in the body

  private:
    std::string_view token() {
        while (pos_ < end_ && isBlank(text_[pos_])) ++pos_;
        if (pos_ == end_)
            fail(file_, place(),
                 "fewer values than the header declares for " + recordName(*e_, k_));
        const size_t b = pos_;
        while (pos_ < end_ && !isBlank(text_[pos_])) ++pos_;
        return text_.substr(b, pos_ - b);
    }

    void skipBlankLines() {
        for (size_t i = pos_; i < text_.size(); ++i) {
            if (text_[i] == '\n') {
                pos_ = i + 1;
                ++line_;
            } else if (!isBlank(text_[i])) {
                return;
            }
        }
        pos_ = text_.size();
    }

    std::string_view text_;
    size_t start_, pos_, line_, end_ = 0;
    const std::string& file_;
    const Element* e_ = nullptr;
    uint64_t k_ = 0;
};

/// The length of a list, checked against the limit and the bytes left.
template <typename Body>
uint64_t listLength(Body& body, const Property& p, const Element& e, uint64_t k,
                    const std::string& file) {
    const double n = body.scalar(p.countType);
    if (n < 0) fail(file, body.place(), "negative list length in " + recordName(e, k));
    if (n > double(kMaxPlyList))
        fail(file, body.place(),
             "list of " + std::to_string(uint64_t(n)) + " items in " + recordName(e, k) +
                 " (at most " + std::to_string(kMaxPlyList) + ")");
    body.expectItems(uint64_t(n), p.type);
    return uint64_t(n);
}

template <typename Body>
void readBody(Body& body, const Header& h, TriangleMesh& mesh, const std::string& file,
              std::vector<uint32_t>& faceOfTriangle) {
    const Element& vertex = h.elements[h.vertex];
    const uint64_t nv = vertex.count;
    bool normals = false, uvs = false;
    for (const Property& p : vertex.props) {
        normals |= p.role == kNX;
        uvs |= p.role == kU;
    }
    mesh.p.reserve(nv);
    if (normals) mesh.n.reserve(nv);
    if (uvs) mesh.uv.reserve(nv);
    // At most one index per byte of the body reserved: hostile counts cannot reserve much more
    // than the file's size.
    mesh.indices.reserve(std::min<uint64_t>(3 * h.elements[h.face].count, body.size()));
    std::vector<uint32_t> poly;
    for (const Element& e : h.elements) {
        if (e.props.empty()) continue;
        const bool isVertex = &e == &vertex, isFace = &e == &h.elements[h.face];
        for (uint64_t k = 0; k < e.count; ++k) {
            body.beginRecord(e, k);
            double v[kIndices] = {};
            for (const Property& p : e.props) {
                if (!p.list) {
                    const double x = body.scalar(p.type);
                    if (isVertex && p.role != kSkip) v[p.role] = x;
                    continue;
                }
                const uint64_t n = listLength(body, p, e, k, file);
                if (!isFace || p.role != kIndices) {
                    body.skipList(n, p.type);
                    continue;
                }
                if (n < 3)
                    fail(file, body.place(),
                         "face " + std::to_string(k) + " has " + std::to_string(n) +
                             " vertices (a polygon needs at least 3)");
                poly.resize(n);
                for (uint64_t i = 0; i < n; ++i) {
                    const double x = body.scalar(p.type);
                    if (x < 0 || x >= double(nv))
                        fail(file, body.place(),
                             "vertex index " + std::to_string(int64_t(x)) + " of face " +
                                 std::to_string(k) + " out of range (" + std::to_string(nv) +
                                 " vertices)");
                    poly[i] = uint32_t(x);
                }
                for (uint64_t i = 1; i + 1 < n; ++i) {  // fan (v0, v_i, v_i+1)
                    mesh.indices.insert(mesh.indices.end(), {poly[0], poly[i], poly[i + 1]});
                    faceOfTriangle.push_back(uint32_t(k));
                }
            }
            body.endRecord();
            if (isVertex) {
                mesh.p.emplace_back(v[kX], v[kY], v[kZ]);
                if (normals) mesh.n.emplace_back(v[kNX], v[kNY], v[kNZ]);
                if (uvs) mesh.uv.emplace_back(v[kU], v[kV]);
            }
        }
    }
    body.finish();
}

// ---------------------------------------------------------------------------------------------
// OBJ

/// A number as tinyobjloader reads it: [+-] digits [. digits] [e [+-] digits], or with the
/// digits before or after the point left out (not both). tinyobjloader turns anything else
/// ("nan", "inf", "1,5", "0x1p3") silently into 0, or reads only its start.
bool isObjNumber(std::string_view t) {
    size_t i = 0, digits = 0;
    if (i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
    for (; i < t.size() && std::isdigit(static_cast<unsigned char>(t[i])); ++i) ++digits;
    if (i < t.size() && t[i] == '.')
        for (++i; i < t.size() && std::isdigit(static_cast<unsigned char>(t[i])); ++i) ++digits;
    if (digits == 0) return false;
    if (i < t.size() && (t[i] == 'e' || t[i] == 'E')) {
        ++i;
        if (i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
        size_t e = 0;
        for (; i < t.size() && std::isdigit(static_cast<unsigned char>(t[i])); ++i) ++e;
        if (e == 0) return false;
    }
    return i == t.size();
}

/// Why a face corner of an f line is not one tinyobjloader reads faithfully ("" if it is): v,
/// v/vt, v//vn or v/vt/vn, each index an integer of at most 2³¹ − 1 in magnitude (beyond,
/// tinyobjloader's integer parser wraps: 4294967299 would be vertex 3). An index of 0 it
/// refuses itself.
std::string objCornerDefect(std::string_view w) {
    const std::string form = " is not a face corner (v, v/vt, v//vn or v/vt/vn with integers)";
    int parts = 0;
    for (size_t i = 0;; ++parts) {
        const size_t slash = std::min(w.find('/', i), w.size());
        std::string_view n = w.substr(i, slash - i);
        if (n.empty() && parts != 1) return quote(w) + form;  // only vt may be left out
        if (!n.empty()) {
            if (n[0] == '+' || n[0] == '-') n.remove_prefix(1);
            if (n.empty() || n.find_first_not_of("0123456789") != std::string_view::npos)
                return quote(w) + form;
            const size_t first = std::min(n.find_first_not_of('0'), n.size());
            if (n.size() - first > 10 ||
                (n.size() - first == 10 && n.substr(first) > std::string_view("2147483647")))
                return "index " + quote(w.substr(i, slash - i)) + " is beyond ±2147483647";
        }
        if (slash == w.size()) break;
        i = slash + 1;
    }
    return parts > 2 ? quote(w) + form : "";
}

/// Why a relative (negative) index of the well-formed face corner w (objCornerDefect) points
/// before the first line of its kind, given how many v, vt and vn lines come before the face;
/// empty if none does. Checked here, in the text: tinyobjloader makes an index that points just
/// before the first line −1, its mark for "no index", so `f 1//-2 2//-2 3//-2` under one vn line
/// rendered as a face without normals, without a word (helper 103).
std::string objRelativeIndexDefect(std::string_view w, const std::array<size_t, 3>& before) {
    static const char* const kind[] = {"v", "vt", "vn"};
    size_t i = 0;
    for (int part = 0; part < 3; ++part) {
        const size_t slash = std::min(w.find('/', i), w.size());
        const std::string_view n = w.substr(i, slash - i);
        // (at most 10 digits, objCornerDefect: no overflow)
        if (!n.empty() && n[0] == '-' && std::stoull(std::string(n.substr(1))) > before[part])
            return std::string("relative ") + kind[part] + " index " + std::string(n) +
                   " points before the first " + kind[part] + " line";
        if (slash == w.size()) break;
        i = slash + 1;
    }
    return "";
}

/// The line numbers of an OBJ file's f and v lines: the k-th face tinyobjloader reports is on
/// line f[k], its k-th position on line v[k].
struct ObjLines {
    std::vector<size_t> f, v, vn, vt;
};

/// Checks the numbers of the v, vn and vt lines and the corners of the f lines, which
/// tinyobjloader does not, and returns the numbers of the f, v, vn and vt lines. Lines end at "\n",
/// "\r\n" or "\r", as in tinyobjloader.
ObjLines scanObj(std::string_view text, const std::string& path) {
    ObjLines lines;
    size_t pos = 0, lineNo = 0;
    while (pos < text.size()) {
        size_t end = pos;
        while (end < text.size() && text[end] != '\n' && text[end] != '\r') ++end;
        std::string_view line = text.substr(pos, end - pos);
        pos = end + (end < text.size() && text[end] == '\r' && end + 1 < text.size() &&
                             text[end + 1] == '\n'
                         ? 2
                         : 1);
        ++lineNo;
        while (!line.empty() && (line[0] == ' ' || line[0] == '\t')) line.remove_prefix(1);
        const auto keyword = [&](std::string_view k) {
            return line.size() > k.size() && line.substr(0, k.size()) == k &&
                   (line[k.size()] == ' ' || line[k.size()] == '\t');
        };
        if (keyword("f")) {
            lines.f.push_back(lineNo);
            size_t corners = 0;
            for (std::string_view w : splitWords(line.substr(1))) {
                if (w[0] == '#')
                    fail(path, "line " + std::to_string(lineNo),
                         "a comment after a face's corners (tinyobjloader cannot read it); put "
                         "it on a line of its own");
                std::string defect = objCornerDefect(w);
                if (defect.empty())
                    defect = objRelativeIndexDefect(
                        w, {lines.v.size(), lines.vt.size(), lines.vn.size()});
                if (!defect.empty()) fail(path, "line " + std::to_string(lineNo), defect);
                ++corners;
            }
            // (tinyobjloader would drop the face with only a warning.)
            if (corners < 3)
                fail(path, "line " + std::to_string(lineNo),
                     "a face of " + std::to_string(corners) +
                         (corners == 1 ? " corner" : " corners") + "; a face needs at least 3");
            // (tinyobjloader counts corners in an unsigned char; refused below too, without
            // the line, should the count of words here ever differ from its own)
            if (corners > 255)
                fail(path, "line " + std::to_string(lineNo),
                     "a face of " + std::to_string(corners) +
                         " corners; at most 255 (tinyobjloader's limit)");
            continue;
        }
        size_t least, most;
        const char* what;
        if (keyword("v")) {
            lines.v.push_back(lineNo);
            least = 3, most = 7, what = "v (x y z [w or r g b])";
        } else if (keyword("vn")) {
            lines.vn.push_back(lineNo);
            least = 3, most = 3, what = "vn (x y z)";
        } else if (keyword("vt")) {
            lines.vt.push_back(lineNo);
            least = 1, most = 3, what = "vt (u [v [w]])";
        } else {
            // Any other statement must be one of OBJ's (groups, smoothing, materials, curves):
            // an unknown one is a damaged line, skipped without a word, and a lost v line moved
            // every later vertex (helper 73: `v1 1 0`, `F 2 4 3`, binary bytes).
            // (With the older specification's bsp, bzp, cdc, cdp, res, and tinyobjloader's vw, t
            // and vc; helper 75.)
            static const std::set<std::string_view> statements = {
                "vp",     "l",          "p",         "o",        "g",        "s",    "mg",
                "mtllib", "usemtl",     "cstype",    "deg",      "bmat",     "step", "curv",
                "curv2",  "surf",       "parm",      "trim",     "hole",     "scrv", "sp",
                "end",    "con",        "bevel",     "c_interp", "d_interp", "lod",  "maplib",
                "usemap", "shadow_obj", "trace_obj", "ctech",    "stech",    "call", "csh",
                "bsp",    "bzp",        "cdc",       "cdp",      "res",      "vw",   "t",
                "vc"};
            const std::string_view word = line.substr(0, line.find_first_of(" \t"));
            // Blank (a form feed, DOS's end-of-file byte), a comment, or one of OBJ's.
            const bool blank = std::all_of(word.begin(), word.end(),
                                           [](char c) { return (unsigned char)c < 0x20; });
            if (blank || word[0] == '#' || statements.count(word)) continue;
            fail(path, "line " + std::to_string(lineNo),
                 word == "v" || word == "vn" || word == "vt" || word == "f"
                     ? quote(word) + " without numbers"
                     : "unknown statement " + quote(word) +
                           " (a damaged line? OBJ's are v, vt, vn, f, g, o, s, usemtl, mtllib, "
                           "l, p and those of curves and surfaces)");
        }
        size_t count = 0;
        for (std::string_view w : splitWords(line.substr(line.find_first_of(" \t")))) {
            if (w[0] == '#') break;  // a trailing comment
            if (!isObjNumber(w)) {
                double x;
                const bool nonFinite = parseToken(w, &x) && !std::isfinite(x);
                fail(path, "line " + std::to_string(lineNo),
                     quote(w) + (nonFinite ? " is not a finite number" : " is not a number"));
            }
            // tinyobjloader reads floats: from 2¹²⁸ − 2¹⁰³ on, a number rounds to infinity.
            if (std::fabs(std::strtod(std::string(w).c_str(), nullptr)) >= 0x1.ffffffp127)
                fail(path, "line " + std::to_string(lineNo),
                     quote(w) +
                         " is beyond the range of a float (±3.4e38), in which OBJ "
                         "numbers are read");
            ++count;
        }
        if (count < least || count > most)
            fail(path, "line " + std::to_string(lineNo),
                 std::to_string(count) + " numbers; expected " + what);
    }
    return lines;
}

/// tinyobjloader's error text as one line, with "line N" as the place when it names one.
[[noreturn]] void failTinyObj(const std::string& path, const std::string& err) {
    std::string msg;
    for (char c : err) {
        if (c == '\n' || c == '\r') {
            if (!msg.empty() && msg.back() != ' ') msg += "; ";
        } else {
            msg += c;
        }
    }
    while (!msg.empty() && (msg.back() == ' ' || msg.back() == ';')) msg.pop_back();
    std::string place;
    const size_t l = msg.find("line ");
    if (l != std::string::npos && l + 5 < msg.size() && std::isdigit((unsigned char)msg[l + 5])) {
        size_t e = l + 5;
        while (e < msg.size() && std::isdigit((unsigned char)msg[e])) ++e;
        place = msg.substr(l, e - l);
    }
    if (msg.rfind("Failed parse `f' line", 0) == 0)
        msg = "malformed face: an index is 0 or not a number";
    else if (msg.empty())
        msg = "cannot parse the file";
    else
        msg = "tinyobjloader: " + msg;
    fail(path, place, msg);
}

/// A corner of a face: indices into tinyobjloader's positions, texture coordinates, normals.
struct Corner {
    int v, vt, vn;
    bool operator==(const Corner& o) const { return v == o.v && vt == o.vt && vn == o.vn; }
};
struct CornerHash {
    size_t operator()(const Corner& c) const {
        uint64_t h = uint64_t(uint32_t(c.v)) * 0x9E3779B97F4A7C15ull;
        h ^= (uint64_t(uint32_t(c.vt)) + 0x632BE59BD9B4E019ull + (h << 6) + (h >> 2));
        h ^= (uint64_t(uint32_t(c.vn)) + 0x8CB92BA72F3D8DD7ull + (h << 6) + (h >> 2));
        return size_t(h);
    }
};

/// validateMesh as the file has the mesh, then, given toWorld, moved by it (its normals made unit
/// length) and validated again there if that moved it (every place noted as after the
/// transform).
void validateAndPlace(TriangleMesh& mesh, const std::string& file, MeshPlaces& places,
                      const Eigen::Affine3d* toWorld) {
    validateMesh(mesh, file, places);
    if (!toWorld) return;
    transformMesh(mesh, *toWorld);
    if (toWorld->matrix() == Eigen::Matrix4d::Identity()) return;
    places.note = ", after the surface's transform";
    validateMesh(mesh, file, places);
}

}  // namespace

TriangleMesh parsePly(std::string_view bytes, const std::string& name,
                      const Eigen::Affine3d* toWorld, MeshPlaces* placesOut) {
    const Header h = HeaderParser(bytes, name).parse();
    TriangleMesh mesh;
    MeshPlaces places;  // the file's face of each triangle
    places.file = name;
    try {
        if (h.format == Format::Ascii) {
            AsciiBody body(bytes, h.bodyOffset, h.bodyLine, name);
            readBody(body, h, mesh, name, places.faceOfTriangle);
        } else {
            BinaryBody body(bytes, h.bodyOffset, h.format == Format::BinaryBE, name);
            readBody(body, h, mesh, name, places.faceOfTriangle);
        }
    } catch (const Error& e) {
        // A count in the header that does not match the body shows only where reading went out
        // of step (a face read as vertex 7: "more values than the header declares"): the counts
        // go with every body error (helper 66).
        std::string counts;
        for (const Element& el : h.elements)
            counts +=
                (counts.empty() ? "" : ", ") + std::to_string(el.count) + " " + quote(el.name);
        throw Error(std::string(e.what()) + "; the header declares " + counts);
    }
    validateAndPlace(mesh, name, places, toWorld);
    if (placesOut) *placesOut = std::move(places);
    return mesh;
}

TriangleMesh readPly(const std::string& path, const Eigen::Affine3d* toWorld, MeshPlaces* places) {
    const std::string data = readWhole(path);
    return parsePly(data, path, toWorld, places);
}

TriangleMesh readObj(const std::string& path, const Eigen::Affine3d* toWorld,
                     MeshPlaces* placesOut) {
    std::string text = readWhole(path);
    // A UTF-8 byte-order mark (editors on Windows write one) is no part of the first statement:
    // tinyobjloader would not know that statement, and a first v line was lost (helper 75).
    text.erase(0, utf8BomLength(text));
    ObjLines lines = scanObj(text, path);
    tinyobj::ObjReaderConfig config;
    config.triangulate = false;   // our own fan keeps the winding
    config.vertex_color = false;  // no default colours
    tinyobj::ObjReader reader;
    // From the text we have read: mtllib lines then read an empty material stream, never a file.
    if (!reader.ParseFromString(text, "", config) || !reader.Error().empty())
        failTinyObj(path, reader.Error());
    // (scanObj refused faces of fewer than 3 corners, which tinyobjloader drops with a warning.)
    const tinyobj::attrib_t& a = reader.GetAttrib();
    const int nv = int(a.vertices.size() / 3), nvt = int(a.texcoords.size() / 2),
              nvn = int(a.normals.size() / 3);
    // What scanObj let through and tinyobjloader still misreads ("0e999" is 0·∞ = NaN to it),
    // at its line (validateMesh knows only the vertex it became).
    const auto misread = [](const char* what) {
        return std::string("a ") + what +
               " is not finite as tinyobjloader reads it (a number it misreads, such as 0e999 "
               "for 0)";
    };
    for (int i = 0; i < nv; ++i)
        if (const Vec3 p(a.vertices[3 * i], a.vertices[3 * i + 1], a.vertices[3 * i + 2]);
            !p.allFinite())
            fail(path,
                 lines.v.size() == size_t(nv) ? "line " + std::to_string(lines.v[i])
                                              : "v line " + std::to_string(i + 1),
                 misread("coordinate"));

    // num_face_vertices is an unsigned char: the count of a face of 256 or more vertices wraps
    // around, and the corners no longer add up.
    size_t faces = 0, corners = 0, allIndices = 0;
    for (const tinyobj::shape_t& s : reader.GetShapes()) {
        faces += s.mesh.num_face_vertices.size();
        for (unsigned char n : s.mesh.num_face_vertices) corners += n;
        allIndices += s.mesh.indices.size();
    }
    if (corners != allIndices)
        fail(path, "", "a face has more than 255 vertices (tinyobjloader's limit)");
    const auto faceLine = [&](size_t f) {
        return lines.f.size() == faces ? "line " + std::to_string(lines.f[f])
                                       : "face " + std::to_string(f);
    };

    TriangleMesh mesh;
    std::unordered_map<Corner, uint32_t, CornerHash> vertexOf;
    vertexOf.reserve(corners);
    std::vector<uint32_t> poly;
    MeshPlaces places;  // faces by their f lines, vertices by the f line that first names them
    places.file = path;
    // A corner's normal and texture coordinates, checked at their own vn and vt lines when a
    // vertex first uses them (validateMesh knows only the vertex, named by its first f line):
    // tinyobjloader's misreadings (0e999), and a zero normal.
    const auto lineOr = [&](const std::vector<size_t>& lineOf, int count, int i, size_t f) {
        return lineOf.size() == size_t(count) ? "line " + std::to_string(lineOf[i]) : faceLine(f);
    };
    const auto checkCorner = [&](const tinyobj::attrib_t& a, const Corner& k, size_t f) {
        if (k.vn >= 0) {
            const Vec3 n(a.normals[3 * k.vn], a.normals[3 * k.vn + 1], a.normals[3 * k.vn + 2]);
            if (!n.allFinite())
                fail(path, lineOr(lines.vn, nvn, k.vn, f), misread("normal coordinate"));
            if (n.cwiseAbs().maxCoeff() == 0)
                fail(path, lineOr(lines.vn, nvn, k.vn, f), "normal is zero");
        }
        if (k.vt >= 0 && !Vec2(a.texcoords[2 * k.vt], a.texcoords[2 * k.vt + 1]).allFinite())
            fail(path, lineOr(lines.vt, nvt, k.vt, f), misread("texture coordinate"));
    };
    std::vector<size_t> firstFaceOf;
    places.fileIndices = false;
    bool first = true, withUV = false, withN = false;
    size_t f = 0;
    for (const tinyobj::shape_t& s : reader.GetShapes()) {
        size_t c = 0;
        for (unsigned char n : s.mesh.num_face_vertices) {
            poly.clear();
            for (size_t j = 0; j < n; ++j) {
                const tinyobj::index_t& ix = s.mesh.indices[c + j];
                const Corner k{ix.vertex_index, ix.texcoord_index, ix.normal_index};
                const auto check = [&](int i, int count, const char* what, bool optional) {
                    if (optional && i == -1) return;
                    if (i < 0)
                        fail(path, faceLine(f),
                             std::string("relative ") + what + " index points before the first " +
                                 what + " line");
                    if (i >= count)
                        fail(path, faceLine(f),
                             std::string(what) + " index " + std::to_string(i + 1) +
                                 " out of range (" + std::to_string(count) + " " + what +
                                 " lines)");
                };
                check(k.v, nv, "v", false);
                check(k.vt, nvt, "vt", true);
                check(k.vn, nvn, "vn", true);
                if (first) {
                    withUV = k.vt >= 0;
                    withN = k.vn >= 0;
                    first = false;
                }
                if ((k.vt >= 0) != withUV)
                    fail(path, faceLine(f),
                         "some face corners have texture coordinates (vt) and others do not");
                if ((k.vn >= 0) != withN)
                    fail(path, faceLine(f),
                         "some face corners have normals (vn) and others do not");
                const auto [it, added] = vertexOf.try_emplace(k, uint32_t(mesh.p.size()));
                if (added) {
                    checkCorner(a, k, f);
                    firstFaceOf.push_back(f);
                    mesh.p.emplace_back(a.vertices[3 * k.v], a.vertices[3 * k.v + 1],
                                        a.vertices[3 * k.v + 2]);
                    if (withUV)
                        mesh.uv.emplace_back(a.texcoords[2 * k.vt], a.texcoords[2 * k.vt + 1]);
                    if (withN)
                        mesh.n.emplace_back(a.normals[3 * k.vn], a.normals[3 * k.vn + 1],
                                            a.normals[3 * k.vn + 2]);
                }
                poly.push_back(it->second);
            }
            for (size_t i = 1; i + 1 < poly.size(); ++i) {  // fan (v0, v_i, v_i+1)
                mesh.indices.insert(mesh.indices.end(), {poly[0], poly[i], poly[i + 1]});
                places.faceOfTriangle.push_back(uint32_t(f));
            }
            c += n;
            ++f;
        }
    }
    // (Kept by value: the places outlive this function when the caller asks for them.)
    places.face = [lineOf = std::move(lines.f), faces](size_t face) {
        return lineOf.size() == faces ? "line " + std::to_string(lineOf[face])
                                      : "face " + std::to_string(face);
    };
    places.vertex = [face = places.face, first = std::move(firstFaceOf)](size_t k) {
        return face(first[k]);
    };
    validateAndPlace(mesh, path, places, toWorld);
    if (placesOut) *placesOut = std::move(places);
    return mesh;
}

TriangleMesh readMesh(const std::string& path, const Eigen::Affine3d* toWorld, MeshPlaces* places) {
    const size_t dot = path.find_last_of("./");
    std::string ext = dot != std::string::npos && path[dot] == '.' ? path.substr(dot) : "";
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (ext == ".obj") return readObj(path, toWorld, places);
    if (ext == ".ply") return readPly(path, toWorld, places);
    fail(path, "", "unknown mesh file extension " + quote(ext) + " (expected .obj or .ply)");
}

}  // namespace shvol
