// The only translation unit of shvol that includes OpenVDB (on the 2-core CI machine, 31 s to
// compile in the release build and 79 s under ASan: the slowest file of every build).
#include "shvol/io/vdb.h"

#include <openvdb/io/DelayedLoadMetadata.h>
#include <openvdb/io/File.h>
#include <openvdb/io/GridDescriptor.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>
#include <vector>

#include <tbb/parallel_for.h>
#include <Eigen/SVD>

#include "shvol/core/atomic_file.h"
#include "shvol/core/error.h"
#include "shvol/core/hash.h"
#include "shvol/core/input_file.h"
#include "shvol/core/progress.h"
#include "shvol/media/density_bricks.h"
#include "shvol/media/majorant_grid.h"
#include "shvol/media/trilinear_depth.h"
#include "shvol/sampling/warp.h"

namespace shvol {

namespace {

void initOpenVdb() {
    static std::once_flag once;
    std::call_once(once, [] {
        openvdb::initialize();
        // OpenVDB's reader of the "__delayedload" metadata that io::File writes into every grid
        // trusts the counts inside it: a damaged one makes it allocate (and clear) up to 4 GB or
        // decompress past the end of a buffer. shvol never loads lazily, so that metadata is read
        // as opaque bytes instead (the size of which checkVdbStructure has checked).
        openvdb::Metadata::unregisterType(openvdb::io::DelayedLoadMetadata::staticTypeName());
    });
}

// ---- Reading a .vdb file that may be damaged or hostile ------------------------------------
//
// OpenVDB 10 reads sizes and counts from the file and believes them: a string or metadata length
// is allocated before it is read, the tile and child counts of the root node drive loops that go
// on after the stream has failed (4·10⁹ turns for a 1 KB file), a compressed chunk's size is
// allocated before it is read, and io::bloscFromStream / unzipFromStream read a chunk marked
// "uncompressed" into the node's buffer before they compare its size with the buffer's (a heap
// buffer overflow with bytes from the file). So a .vdb is read in three steps:
//  1. checkVdbStructure walks the file's outer structure with a bounded reader of its own:
//     header, file metadata, grid descriptors, and each grid's metadata and transform type,
//     checking every size and count against the bytes left in the file;
//  2. VdbGridReader reads the requested grid's metadata and transform with OpenVDB, then walks
//     the tree's topology and buffers (FloatTreeCheck) checking every count and chunk size
//     against what OpenVDB will expect;
//  3. only then OpenVDB reads the tree, from a stream whose failed reads throw.

/// Reads [pos, end) of a file, refusing (std::runtime_error) to go past `end`.
class BoundedReader {
  public:
    BoundedReader(std::istream& in, uint64_t pos, uint64_t end) : in_(in), pos_(pos), end_(end) {
        in_.seekg(std::streamoff(pos));
    }
    uint64_t pos() const { return pos_; }
    uint64_t left() const { return end_ - pos_; }
    void need(uint64_t n, const std::string& what) const {
        if (n > left())
            throw std::runtime_error(what + " (" + std::to_string(n) + " bytes at byte " +
                                     std::to_string(pos_) + ") runs past the end of " +
                                     (end_ == fileEnd_ ? "the file" : "the grid"));
    }
    std::string bytes(uint64_t n, const std::string& what) {
        need(n, what);
        std::string b(n, '\0');
        if (n) in_.read(&b[0], std::streamsize(n));
        pos_ += n;
        return b;
    }
    void skip(uint64_t n, const std::string& what) {
        need(n, what);
        pos_ += n;
        in_.seekg(std::streamoff(pos_));
    }
    template <typename T>
    T get(const std::string& what) {
        T v;
        const std::string b = bytes(sizeof(T), what);
        std::memcpy(&v, b.data(), sizeof(T));
        return v;
    }
    std::string string(const std::string& what) { return bytes(get<uint32_t>(what), what); }
    void seek(uint64_t p) {
        if (p > end_) throw std::runtime_error("offset " + std::to_string(p) + " past the end");
        pos_ = p;
        in_.seekg(std::streamoff(p));
    }
    void setFileEnd(uint64_t e) { fileEnd_ = e; }

  private:
    std::istream& in_;
    uint64_t pos_, end_, fileEnd_ = 0;
};

std::string at(uint64_t pos) {
    return " at byte " + std::to_string(pos);
}

/// A grid descriptor of the file (positions are byte offsets in the file).
struct VdbGridEntry {
    std::string uniqueName;
    bool instance = false;
    uint64_t descriptorPos = 0, endPos = 0;
};

/// The file's grids, after checking the outer structure (file format versions 222 to 224, i.e.
/// OpenVDB 2.0 and later, written with grid offsets as io::File writes them):
///   header:     int64 magic, uint32 format version, uint32 ×2 library version,
///               char has-grid-offsets, 36-character UUID
///   metadata:   uint32 count, count × (string name, string type, uint32 n, n bytes)
///   grids:      int32 count, count × descriptor (string unique name, string type, string
///               instance parent, int64 grid, block and end offsets), each followed at its grid
///               offset by uint32 compression, metadata, string transform type, … up to its
///               end offset
/// (a string is a uint32 length and that many bytes). Throws std::runtime_error saying what is
/// wrong and where.
std::vector<VdbGridEntry> checkVdbStructure(std::istream& in, uint64_t size) {
    BoundedReader r(in, 0, size);
    r.setFileEnd(size);
    auto metadata = [&](const std::string& what) {
        const uint32_t count = r.get<uint32_t>(what);
        r.need(uint64_t(count) * 12, what);  // each item has at least three uint32 sizes
        for (uint32_t i = 0; i < count; ++i) {
            r.string(what);  // name
            const std::string type = r.string(what);
            const uint64_t valuePos = r.pos();
            const uint32_t n = r.get<uint32_t>(what);
            // OpenVDB reads a registered fixed-size type (int32, vec3d, …) whatever n says.
            if (type != "string" && openvdb::Metadata::isRegisteredType(type) &&
                n != openvdb::Metadata::createMetadata(type)->size())
                throw std::runtime_error(what + ": " + std::to_string(n) + "-byte " + type +
                                         " value" + at(valuePos));
            if (type == "bool" && n == 1) {  // read into a C++ bool: must be 0 or 1
                if (const char b = r.bytes(1, what)[0]; b != 0 && b != 1)
                    throw std::runtime_error(what + ": bool value " + std::to_string(int(b)) +
                                             at(valuePos + 4));
            } else {
                r.skip(n, what);
            }
        }
    };

    if (size < 8 || r.get<int64_t>("header") != openvdb::OPENVDB_MAGIC)
        throw std::runtime_error("no VDB header");
    const uint32_t version = r.get<uint32_t>("header");
    if (version < openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION ||
        version > openvdb::OPENVDB_FILE_VERSION)
        throw std::runtime_error(
            "file format version " + std::to_string(version) + "; this build reads versions " +
            std::to_string(openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION) +
            " (OpenVDB 2.0) to " + std::to_string(openvdb::OPENVDB_FILE_VERSION));
    r.skip(8, "header");  // library version
    if (r.get<char>("header") == 0)
        throw std::runtime_error("the file has no grid offsets (a VDB stream)");
    const std::string uuid = r.bytes(36, "header");
    for (size_t i = 0; i < uuid.size(); ++i)
        if (i == 8 || i == 13 || i == 18 || i == 23 ? uuid[i] != '-'
                                                    : !std::isxdigit((unsigned char)uuid[i]))
            throw std::runtime_error("malformed UUID in the header");
    metadata("file metadata");
    const uint64_t countPos = r.pos();
    const int32_t count = r.get<int32_t>("grid count");
    if (count < 0 || uint64_t(count) > r.left() / 36)  // a descriptor has at least 36 bytes
        throw std::runtime_error("grid count " + std::to_string(count) + at(countPos) +
                                 " does not fit in the file");
    std::vector<VdbGridEntry> grids;
    for (int32_t g = 0; g < count; ++g) {
        VdbGridEntry e;
        e.descriptorPos = r.pos();
        e.uniqueName = r.string("grid descriptor");
        r.string("grid descriptor");  // type
        e.instance = !r.string("grid descriptor").empty();
        const int64_t gridPos = r.get<int64_t>("grid descriptor");
        int64_t blockPos = r.get<int64_t>("grid descriptor");
        const int64_t endPos = r.get<int64_t>("grid descriptor");
        if (e.instance) blockPos = endPos;  // an instance has no tree (and no block offset)
        const std::string grid =
            "grid '" + openvdb::io::GridDescriptor::nameAsString(e.uniqueName) + "'";
        if (gridPos == int64_t(r.pos()) && blockPos >= gridPos && endPos >= blockPos &&
            uint64_t(endPos) > size)  // (an incomplete copy or download)
            throw std::runtime_error("truncated: " + grid + " ends at byte " +
                                     std::to_string(endPos) + ", the file at byte " +
                                     std::to_string(size));
        if (gridPos != int64_t(r.pos()) || blockPos < gridPos || endPos < blockPos ||
            uint64_t(endPos) > size)
            throw std::runtime_error("inconsistent offsets in the descriptor of " + grid +
                                     at(e.descriptorPos));
        e.endPos = uint64_t(endPos);
        r.get<uint32_t>("grid compression flags");
        metadata("grid metadata");
        r.string("transform type");
        if (int64_t(r.pos()) > blockPos)
            throw std::runtime_error("grid metadata runs past the grid's data" + at(blockPos));
        r.seek(uint64_t(endPos));
        grids.push_back(std::move(e));
    }
    return grids;
}

/// Walks the topology and buffers of a FloatTree (5, 4, 3) from `in`'s position to `end` as
/// OpenVDB 10 reads them (tree/RootNode.h, InternalNode.h and LeafNode.h readTopology and
/// readBuffers, io/Compression.h readCompressedValues, readData and HalfReader, for file format
/// versions ≥ 222 and a stream that is not "seekable", so that leaves read their value mask
/// again with their buffers), allocating nothing the file asks for. Every count must fit in the
/// grid's bytes and every value chunk must have the size OpenVDB will read it into; for Blosc
/// chunks the Blosc header must agree. Throws std::runtime_error.
class FloatTreeCheck {
  public:
    FloatTreeCheck(std::istream& in, uint64_t begin, uint64_t end, uint32_t compression, bool half)
        : r_(in, begin, end), compression_(compression), valueBytes_(half ? 2 : 4), half_(half) {}

    void run() {
        r_.get<int32_t>("tree");  // buffer count
        r_.get<float>("root");    // background
        const uint32_t numTiles = r_.get<uint32_t>("root"), numChildren = r_.get<uint32_t>("root");
        if (numTiles == 0 && numChildren == 0) return;
        r_.need(uint64_t(numTiles) * 17, "root tiles");  // (int32 ×3, float, bool) each
        for (uint32_t n = 0; n < numTiles; ++n)
            if (const char active = r_.bytes(17, "root tile")[16]; active != 0 && active != 1)
                throw std::runtime_error("root tile" + at(r_.pos() - 17) + ": active flag " +
                                         std::to_string(int(active)) + " is not a bool");
        r_.need(uint64_t(numChildren) * (12 + 2 * kUpperMask), "root child nodes");
        // The root keeps its children in a map: a later child at the same key replaces an
        // earlier one, and buffers are read in key order.
        std::map<std::array<int32_t, 3>, std::vector<uint32_t>> children;
        for (uint32_t n = 0; n < numChildren; ++n) {
            std::array<int32_t, 3> key;
            for (int32_t& k : key) k = r_.get<int32_t>("root child origin");
            children[key] = upperTopology();
        }
        for (const auto& child : children)
            for (uint32_t leaves : child.second)
                for (uint32_t l = 0; l < leaves; ++l) {
                    const Mask mask = readMask(kLeafMask, "leaf value mask");
                    values(512, mask.on, kLeafMask, "leaf values");
                }
    }

  private:
    static constexpr uint64_t kUpperMask = 4096, kLowerMask = 512, kLeafMask = 64;  // bytes
    struct Mask {
        std::vector<uint64_t> words;
        uint64_t on = 0;
    };

    Mask readMask(uint64_t bytes, const char* what) {
        Mask m;
        m.words.resize(bytes / 8);
        const std::string b = r_.bytes(bytes, what);
        std::memcpy(m.words.data(), b.data(), bytes);
        for (uint64_t w : m.words) m.on += uint64_t(__builtin_popcountll(w));
        return m;
    }

    /// An upper internal node's topology; returns the leaf count of each lower child.
    std::vector<uint32_t> upperTopology() {
        const Mask child = readMask(kUpperMask, "internal node child mask");
        const Mask value = readMask(kUpperMask, "internal node value mask");
        values(32768, value.on, kUpperMask, "internal node tile values");
        r_.need(child.on * 2 * kLowerMask, "internal node children");
        std::vector<uint32_t> leaves;
        for (uint64_t i = 0; i < child.on; ++i) leaves.push_back(lowerTopology());
        return leaves;
    }
    uint32_t lowerTopology() {
        const Mask child = readMask(kLowerMask, "internal node child mask");
        const Mask value = readMask(kLowerMask, "internal node value mask");
        values(4096, value.on, kLowerMask, "internal node tile values");
        r_.skip(child.on * kLeafMask, "leaf value masks");
        return uint32_t(child.on);
    }

    /// io::readCompressedValues(destCount = count, a value mask with `active` bits on).
    void values(uint64_t count, uint64_t active, uint64_t maskBytes, const char* what) {
        const int8_t meta = r_.get<int8_t>(what);
        using namespace openvdb::io;
        if (meta == NO_MASK_AND_ONE_INACTIVE_VAL || meta == MASK_AND_ONE_INACTIVE_VAL ||
            meta == MASK_AND_TWO_INACTIVE_VALS)
            r_.skip(meta == MASK_AND_TWO_INACTIVE_VALS ? 8 : 4, what);  // float inactive values
        if (meta == MASK_AND_NO_INACTIVE_VALS || meta == MASK_AND_ONE_INACTIVE_VAL ||
            meta == MASK_AND_TWO_INACTIVE_VALS)
            r_.skip(maskBytes, what);  // selection mask
        if ((compression_ & COMPRESS_ACTIVE_MASK) && meta != NO_MASK_AND_ALL_VALS) count = active;
        if (half_ && count == 0) return;  // HalfReader reads nothing then
        const uint64_t bytes = count * valueBytes_;
        if (!(compression_ & (COMPRESS_BLOSC | COMPRESS_ZIP))) return r_.skip(bytes, what);
        const uint64_t chunkPos = r_.pos();
        const int64_t n = r_.get<int64_t>(what);
        if (n <= 0) {  // stored uncompressed: exactly the bytes expected
            if (n != -int64_t(bytes))
                throw std::runtime_error(std::string(what) + at(chunkPos) + ": " +
                                         std::to_string(n) + "-byte chunk where " +
                                         std::to_string(bytes) + " bytes are expected");
            return r_.skip(bytes, what);
        }
        r_.need(uint64_t(n), what);
        if (compression_ & COMPRESS_BLOSC) {
            // Blosc header: version, versionlz, flags, typesize, uint32 nbytes, blocksize, cbytes
            const std::string h = r_.bytes(std::min<uint64_t>(uint64_t(n), 16), what);
            uint32_t nbytes = 0, cbytes = 0;
            if (h.size() == 16) {
                std::memcpy(&nbytes, h.data() + 4, 4);
                std::memcpy(&cbytes, h.data() + 12, 4);
            }
            if (h.size() < 16 || nbytes != bytes || cbytes != uint64_t(n))
                throw std::runtime_error(std::string(what) + at(chunkPos) +
                                         ": inconsistent Blosc chunk header");
            return r_.skip(uint64_t(n) - 16, what);
        }
        r_.skip(uint64_t(n), what);
    }

    BoundedReader r_;
    uint32_t compression_;
    uint64_t valueBytes_;
    bool half_;
};

/// Reads one FloatGrid the way io::Archive::readGrid does (file format ≥ 222), from a stream
/// whose failed reads throw, checking its tree with FloatTreeCheck before OpenVDB reads it.
class VdbGridReader : public openvdb::io::Archive {
  public:
    openvdb::GridBase::Ptr read(std::istream& is, const VdbGridEntry& entry,
                                const std::function<void(const openvdb::GridBase&)>& checkType) {
        is.seekg(0);
        readHeader(is);  // (returns whether the UUID changed; a bad header throws)
        auto fileMetadata = std::make_shared<openvdb::io::StreamMetadata>();
        openvdb::io::setStreamMetadataPtr(is, fileMetadata, /*transfer=*/false);
        openvdb::io::setVersion(is, libraryVersion(), fileVersion());
        openvdb::io::setDataCompression(is, compression());
        is.seekg(std::streamoff(entry.descriptorPos));
        openvdb::io::GridDescriptor gd;
        gd.read(is);
        openvdb::GridBase::Ptr grid = openvdb::GridBase::createGrid(gd.gridType());
        checkType(*grid);  // before reading a tree of another type
        grid->setSaveFloatAsHalf(gd.saveFloatAsHalf());
        gd.seekToGrid(is);
        readGridCompression(is);
        auto gridMetadata = std::make_shared<openvdb::io::StreamMetadata>(*fileMetadata);
        gridMetadata->setHalfFloat(grid->saveFloatAsHalf());
        gridMetadata->setSeekable(false);  // leaves read their own value masks (as checked)
        openvdb::io::setStreamMetadataPtr(is, gridMetadata, /*transfer=*/false);
        openvdb::io::setGridClass(is, openvdb::GRID_UNKNOWN);
        openvdb::io::setGridBackgroundValuePtr(is, nullptr);
        grid->readMeta(is);
        gridMetadata->gridMetadata() = static_cast<openvdb::MetaMap&>(*grid);
        openvdb::io::setGridClass(is, grid->getGridClass());
        grid->readTransform(is);
        const std::streamoff tree = is.tellg();
        FloatTreeCheck(is, uint64_t(tree), entry.endPos, openvdb::io::getDataCompression(is),
                       grid->saveFloatAsHalf())
            .run();
        is.seekg(tree);
        grid->readTopology(is);
        grid->readBuffers(is);
        return grid;
    }
};

// Not registered with the tree: cheap to make per ray, private to the calling thread.
using Accessor = openvdb::tree::ValueAccessor<const openvdb::FloatTree, false>;

/// Calls f(value, box) for every tile of the tree, active or not (the root's, of 4096³ voxels,
/// and the internal nodes', of 128³ and 8³), and, with `voxels`, then for every voxel of every
/// leaf: the values tree.cbeginValueAll() visits, in another order. Each root entry is visited
/// once. (OpenVDB's tree value iterator took time quadratic in the root's tiles: 25,600 root
/// tiles, a file of 435 KB, took 25 s to load; helper 55.)
template <typename F>
void forEachValue(const openvdb::FloatTree& tree, bool voxels, F&& f) {
    using Root = openvdb::FloatTree::RootNodeType;
    using Upper = Root::ChildNodeType;
    using Lower = Upper::ChildNodeType;
    using Leaf = Lower::ChildNodeType;
    // The box of dim³ voxels from origin, its far corner clamped to INT_MAX: a damaged file can put
    // a node's origin anywhere, and origin + dim − 1 in int overflowed (CoordBBox::createCube; the
    // VDB fuzzer under UBSan, 8 Dec). Such a box reaches beyond ±2^30, where loadVdbMedium refuses
    // any density and ignores zeros.
    const auto cube = [](const openvdb::Coord& origin, int dim) {
        const auto end = [dim](int c) {
            return int(std::min<int64_t>(int64_t(c) + dim - 1, std::numeric_limits<int>::max()));
        };
        return openvdb::CoordBBox(
            origin, openvdb::Coord(end(origin.x()), end(origin.y()), end(origin.z())));
    };
    for (auto t = tree.root().cbeginValueAll(); t; ++t) f(*t, cube(t.getCoord(), Upper::DIM));
    for (auto u = tree.root().cbeginChildOn(); u; ++u) {
        for (auto t = u->cbeginValueAll(); t; ++t) f(*t, cube(t.getCoord(), Lower::DIM));
        for (auto l = u->cbeginChildOn(); l; ++l) {
            for (auto t = l->cbeginValueAll(); t; ++t) f(*t, cube(t.getCoord(), Leaf::DIM));
            if (voxels)
                for (auto leaf = l->cbeginChildOn(); leaf; ++leaf)
                    for (auto v = leaf->cbeginValueAll(); v; ++v) f(*v, cube(v.getCoord(), 1));
        }
    }
}

/// Whether the window of brick position c (voxels 8c … 8c + 8 on each axis: its leaf position
/// and the +1 neighbours' first voxels) holds `value` in every voxel: none of the 8 leaf
/// positions c + {0, 1}³ it touches is a leaf, and each lies in a tile (or the background) of
/// that value. A leaf counts as not constant, whatever its voxels.
bool windowIsConstant(Accessor& acc, const Eigen::Vector3i& c, float value) {
    for (int k = 0; k < 8; ++k) {
        const openvdb::Coord v(8 * (c.x() + (k & 1)), 8 * (c.y() + (k >> 1 & 1)),
                               8 * (c.z() + (k >> 2)));
        if (acc.probeConstLeaf(v) || acc.getValue(v) != value) return false;
    }
    return true;
}

/// The brick copy of a density grid (background 0). A brick is stored at every brick position
/// whose voxels or apron hold a non-zero value, except where they all lie in tiles of one value:
/// inside a tile, and on its shell where the neighbouring tiles have its value, the position is a
/// constant (no voxel is read or stored for it). None (std::nullopt) when the table or the bricks
/// would take too much memory.
std::optional<DensityBricks> makeBricks(const openvdb::FloatTree& tree) {
    // 64 MiB of table (and 16 MiB of `kind` below while it is built), 182 MiB of bricks and 48 M
    // voxel reads at most: a small hostile file must not cost seconds to load (a tile is cheap to
    // write and its shell needs bricks).
    constexpr double kMaxTableCells = 1 << 24, kMaxBricks = 1 << 16;
    struct Box {
        Eigen::Vector3i lo, hi;  // brick coordinates, inclusive
        float tile;              // the tile's value, or 0 for a leaf
    };
    std::vector<Box> boxes;
    Eigen::Vector3i lo = Eigen::Vector3i::Constant(INT32_MAX), hi = -lo;
    auto addBox = [&](const openvdb::CoordBBox& b, float tile) {
        // Voxel x lies in the window (brick and apron) of bricks (x − 1) >> 3 … x >> 3.
        const Eigen::Vector3i a((b.min().x() - 1) >> 3, (b.min().y() - 1) >> 3,
                                (b.min().z() - 1) >> 3),
            z(b.max().x() >> 3, b.max().y() >> 3, b.max().z() >> 3);
        boxes.push_back({a, z, tile});
        lo = lo.cwiseMin(a), hi = hi.cwiseMax(z);
    };
    for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf)
        for (auto v = leaf->cbeginValueAll(); v; ++v)
            if (*v > 0) {
                addBox(leaf->getNodeBoundingBox(), 0);
                break;
            }
    forEachValue(tree, false, [&](float v, const openvdb::CoordBBox& b) {  // tiles only
        if (v > 0) addBox(b, v);
    });
    if (boxes.empty()) return DensityBricks();
    const Eigen::Vector3i res = hi - lo + Eigen::Vector3i::Ones();
    if (res.cast<double>().prod() > kMaxTableCells) return std::nullopt;
    // Calls visit(c, tile) for each brick position c of the box b, with tile = the tile's value
    // where c is inside a tile with its apron too (lo + 1 … hi − 1 on every axis: a constant
    // rather than a brick), else 0; with shellOnly, a tile's inner positions are skipped. Stops
    // when visit returns false.
    auto forEachPosition = [&](const Box& b, bool shellOnly, auto&& visit) {
        for (int x = b.lo.x(); x <= b.hi.x(); ++x)
            for (int y = b.lo.y(); y <= b.hi.y(); ++y) {
                const bool edge = x == b.lo.x() || x == b.hi.x() || y == b.lo.y() || y == b.hi.y();
                // Inner rows of a tile: only their two ends are on the shell.
                const int step = shellOnly && b.tile > 0 && !edge ? b.hi.z() - b.lo.z() : 1;
                for (int z = b.lo.z(); z <= b.hi.z(); z += std::max(step, 1)) {
                    const bool interior = !edge && z > b.lo.z() && z < b.hi.z();
                    if (!visit(Eigen::Vector3i(x, y, z), interior ? b.tile : 0.f)) return false;
                }
            }
        return true;
    };
    // The bricks to store, each counted once: a position lies in the windows of up to 8 boxes
    // (its own and those one brick above it on each axis), so a sum over the boxes would count
    // a dense region's bricks about 8 times. Tiles' inner positions are not walked, and the
    // count stops at the cap, so a small hostile file is refused quickly.
    // A tile's shell position whose window lies in tiles of the tile's value is a constant
    // (helper 138: a 512³ fill, 64 tiles of 128³ in an 8.8 KB file, took 58,625 bricks, 165 MiB,
    // most of them on the faces between tiles). At most kMaxChecks positions are checked (8
    // probes each), so that a small file of many tiles still loads quickly; beyond, a shell
    // position takes a brick, as it did before.
    constexpr size_t kMaxChecks = size_t(1) << 20;
    enum : uint8_t { kUnseen, kBrick, kConstant };
    std::vector<uint8_t> kind(size_t(res.prod()), kUnseen);
    const auto kindOf = [&](const Eigen::Vector3i& c) -> uint8_t& {
        const Eigen::Vector3i r = c - lo;
        return kind[(size_t(r.x()) * res.y() + r.y()) * res.z() + r.z()];
    };
    DensityBricks d(lo, res, 0.f);
    Accessor acc(tree);
    size_t bricks = 0, checks = 0;
    for (const Box& b : boxes)
        if (!forEachPosition(b, true, [&](const Eigen::Vector3i& c, float tile) {
                uint8_t& k = kindOf(c);
                if (tile > 0 || k != kUnseen) return true;
                if (b.tile > 0 && ++checks <= kMaxChecks && windowIsConstant(acc, c, b.tile))
                    k = kConstant, d.fill(c, b.tile);
                else
                    k = kBrick, ++bricks;
                return double(bricks) <= kMaxBricks;
            }))
            return std::nullopt;
    d.reserve(bricks);
    auto voxel = [&](int i, int j, int l) { return acc.getValue(openvdb::Coord(i, j, l)); };
    for (const Box& b : boxes)
        forEachPosition(b, false, [&](const Eigen::Vector3i& c, float tile) {
            if (tile > 0)
                d.fill(c, tile);
            else if (kindOf(c) == kBrick)
                d.add(c, voxel);
            return true;
        });
    return d;
}

/// A lower bound of the trilinear density in every cell of the majorant grid: the smallest voxel
/// value a lookup inside the cell can reach (the voxels from ⌊lo⌋ to ⌊hi⌋ + 1, background
/// zeros included). Empty (no control part) when the windows of the cells with density hold
/// more than 2^24 voxels: loading stays fast for a small file whose tiles cover a large region.
std::vector<double> minorants(const openvdb::FloatTree& tree, const MajorantGrid& g) {
    const Eigen::Vector3i res = g.resolution();
    const Vec3 cell = g.cellUpper(0, 0, 0) - g.cellLower(0, 0, 0);
    double withDensity = 0;
    for (int z = 0; z < res.z(); ++z)
        for (int y = 0; y < res.y(); ++y)
            for (int x = 0; x < res.x(); ++x) withDensity += g.cell(x, y, z) > 0;
    if ((cell.array() + 2).prod() * withDensity > double(1 << 24)) return {};
    std::vector<double> minimum(size_t(res.prod()), 0.0);
    Accessor acc(tree);
    size_t i = 0;
    for (int z = 0; z < res.z(); ++z)
        for (int y = 0; y < res.y(); ++y)
            for (int x = 0; x < res.x(); ++x, ++i) {
                if (g.cell(x, y, z) <= 0) continue;
                const Vec3 lo = g.cellLower(x, y, z), hi = g.cellUpper(x, y, z);
                float m = INFINITY;
                for (int vz = int(std::floor(lo.z())); m > 0 && vz <= int(std::floor(hi.z())) + 1;
                     ++vz)
                    for (int vy = int(std::floor(lo.y()));
                         m > 0 && vy <= int(std::floor(hi.y())) + 1; ++vy)
                        for (int vx = int(std::floor(lo.x()));
                             m > 0 && vx <= int(std::floor(hi.x())) + 1; ++vx)
                            m = std::min(m, acc.getValue(openvdb::Coord(vx, vy, vz)));
                minimum[i] = double(m);
            }
    return minimum;
}

class VdbMedium final : public Medium {
  public:
    VdbMedium(const VdbMediumDesc& d, openvdb::FloatGrid::ConstPtr grid,
              const Eigen::Affine3d& worldToIndex, MajorantGrid majorants, int cellVoxels,
              std::optional<DensityBricks> bricks)
        : Medium(d.albedo, d.phase),
          grid_(std::move(grid)),
          worldToIndex_(worldToIndex),
          scale_(d.densityScale),
          sigmaMax_(d.densityScale * (1 + 1e-6) * majorants.maxValue()),
          // ‖A d‖₁ ≥ ‖A d‖₂ ≥ s_min(A) for a unit d: no ray of unit direction (as the integrator's
          // are) can prefer regular tracking unless σ_maj exceeds kRegularTrackingLookupsPerCell ·
          // s_min somewhere. (A shorter d could; missing it costs speed, never correctness.)
          regular_(d.regularTracking &&
                   sigmaMax_ > kRegularTrackingLookupsPerCell *
                                   Eigen::JacobiSVD<Eigen::Matrix3d>(worldToIndex.linear())
                                       .singularValues()
                                       .minCoeff()),
          majorants_(std::move(majorants)),
          bricks_(std::move(bricks)),
          desc_("vdb " + d.file + ":" + d.grid +
                (majorants_.empty() ? ", no density"
                 : cellVoxels > 0   ? ", majorant cells of " + std::to_string(cellVoxels) +
                                        (cellVoxels == 1 ? " voxel" : " voxels") +
                                        (d.majorantCellVoxels == 0 ? " (auto)" : "")
                                  : ", one global majorant") +
                (d.regularTracking ? "" : ", no regular tracking")) {}

  private:
    auto segments(const Vec3& o, const Vec3& d, double tMax) const {
        // Float rounding in the trilinear interpolation (three levels of lerps a + (b − a)·w,
        // each rounded three times, every value at most the cell's maximum m) errs by at most
        // 3·3·2⁻²⁴·m ≈ 5.4·10⁻⁷·m, also when the result is near the minimum: a lerp from 1 to
        // 0.001 can land 10⁻⁵ of 0.001 below 0.001. So the majorant is inflated, and the
        // minorant deflated, by 10⁻⁶·m: σ_min ≤ σ_t ≤ σ_maj holds for the computed σ_t, the
        // residual σ_t − σ_min is never below 0, and a collision accepted below σ_min is one σ_t
        // would accept.
        const double k = scale_ * (1 + 1e-6);
        return [this, o, d, tMax, k](auto&& visit) {
            majorants_.traverse(o, d, 0, tMax, [&](double t0, double t1, double m, double mn) {
                return visit(t0, t1, k * m, scale_ * std::max(0.0, mn - 1e-6 * m));
            });
        };
    }
    /// The density at index-space points, density(p), and the voxels around a unit cell,
    /// density.corners(x, y, z, v) (TrilinearDepth's Voxels): from the bricks or through an
    /// OpenVDB accessor.
    struct BrickDensity {
        const DensityBricks& bricks;
        __attribute__((always_inline)) float operator()(const Vec3& p) const {
            return bricks.sample(p);
        }
        void corners(int x, int y, int z, float v[8]) const { bricks.corners(x, y, z, v); }
    };
    struct AccessorDensity {
        Accessor& acc;
        float operator()(const Vec3& p) const {
            return openvdb::tools::BoxSampler::sample(acc, openvdb::Vec3R(p.x(), p.y(), p.z()));
        }
        void corners(int x, int y, int z, float v[8]) const {
            for (int i = 0; i < 8; ++i)
                v[i] = acc.getValue(openvdb::Coord(x + (i >> 2), y + ((i >> 1) & 1), z + (i & 1)));
        }
    };
    /// Calls track(density) with the bricks' density or (without them) an accessor's: two
    /// instantiations, no branch per lookup.
    template <typename Track>
    double withDensity(Track&& track) const {
        if (bricks_) return track(BrickDensity{*bricks_});
        Accessor acc(grid_->tree());
        return track(AccessorDensity{acc});
    }
    template <typename Density>
    auto sigma(const Density& density, const Vec3& o, const Vec3& d) const {
        return [ this, &density, o, d ](double t) __attribute__((always_inline)) {
            return scale_ * double(density(o + t * d));
        };
    }

    /// A free flight (Flight) or a transmittance estimate along o + t·d, with regular tracking
    /// (TrilinearDepth) or (NoRegularTracking) without.
    template <bool Flight, bool Regular>
    __attribute__((always_inline)) double track(const Vec3& o, const Vec3& d, double tMax,
                                                TransmittanceEstimator est, Rng& rng,
                                                TrackingCounters& c, const Vec2* first) const {
        return withDensity([&](const auto& density) {
            const auto exact = [&] {
                if constexpr (Regular)
                    return TrilinearDepth(o, d, scale_, density);
                else
                    return NoRegularTracking{};
            }();
            if constexpr (Flight)
                return deltaTrack(segments(o, d, tMax), sigma(density, o, d), rng, c, first, exact);
            else
                return est == TransmittanceEstimator::Ratio
                           ? ratioTrack(segments(o, d, tMax), sigma(density, o, d), rng, c, exact)
                           : deltaTrackTransmittance(segments(o, d, tMax), sigma(density, o, d),
                                                     rng, c, exact);
        });
    }
    /// track() where a segment of the ray could prefer regular tracking, out of line: media and
    /// rays it cannot serve keep the inlined loops of plain tracking, without a test per segment
    /// (with the four trackers inlined into one function, sampleCollision took 6–8% more
    /// instructions on the cloud of validation/cycles, where regular tracking is never taken:
    /// callgrind). regular_ is false already at load for a medium too thin for any ray.
    template <bool Flight>
    double trackChoosing(const Ray& ray, double tMax, TransmittanceEstimator est, Rng& rng,
                         TrackingCounters& c, const Vec2* first) const {
        const Vec3 o = worldToIndex_ * ray.o, d = worldToIndex_.linear() * ray.d;
        if (regular_ && regularTrackingPossible(sigmaMax_, d))
            return trackRegular<Flight>(o, d, tMax, est, rng, c, first);
        return track<Flight, false>(o, d, tMax, est, rng, c, first);
    }
    template <bool Flight>
    __attribute__((noinline)) double trackRegular(const Vec3& o, const Vec3& d, double tMax,
                                                  TransmittanceEstimator est, Rng& rng,
                                                  TrackingCounters& c, const Vec2* first) const {
        return track<Flight, true>(o, d, tMax, est, rng, c, first);
    }

  public:
    double sampleCollision(const Ray& ray, double tMax, Rng& rng, TrackingCounters& c,
                           const Vec2* first) const override {
        return trackChoosing<true>(ray, tMax, TransmittanceEstimator::Ratio, rng, c, first);
    }

    double transmittance(const Ray& ray, double tMax, TransmittanceEstimator est, Rng& rng,
                         TrackingCounters& c) const override {
        return trackChoosing<false>(ray, tMax, est, rng, c, nullptr);
    }

    double sigmaT(const Vec3& p) const override {
        const Vec3 q = worldToIndex_ * p;
        // Where the majorant is 0 so is the density; this also keeps the index coordinates of
        // points far outside the grid (or NaN) away from OpenVDB's integer voxel lookup.
        if (!q.allFinite() || majorants_.at(q) == 0) return 0;
        return withDensity([&](const auto& density) { return scale_ * double(density(q)); });
    }

    double sigmaMajorant(const Vec3& p) const override {
        const Vec3 q = worldToIndex_ * p;
        return q.allFinite() ? scale_ * (1 + 1e-6) * majorants_.at(q) : 0;
    }

    Bounds3 bounds() const override {
        Bounds3 b{Vec3::Constant(INFINITY), Vec3::Constant(-INFINITY)};  // empty without density
        if (majorants_.empty()) return b;
        const Eigen::Affine3d indexToWorld = worldToIndex_.inverse();
        const Vec3 lo = majorants_.lower(), hi = majorants_.upper();
        for (int k = 0; k < 8; ++k) {
            const Vec3 p = indexToWorld * Vec3(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(),
                                               k & 4 ? hi.z() : lo.z());
            b.lo = b.lo.cwiseMin(p), b.hi = b.hi.cwiseMax(p);
        }
        // Widened by a rounding margin: the medium's own clip (in index space) decides the rest.
        const Vec3 pad = 1e-9 * ((b.hi - b.lo).array() + b.lo.array().abs() + b.hi.array().abs());
        return {b.lo - pad, b.hi + pad};
    }

    std::string describe() const override {
        if (!bricks_) return desc_ + ", OpenVDB lookups";
        char b[96];
        std::snprintf(b, sizeof b, ", brick lookups (%zu bricks, %.1f MiB)", bricks_->brickCount(),
                      double(bricks_->memoryBytes()) / (1 << 20));
        return desc_ + b;
    }

  private:
    openvdb::FloatGrid::ConstPtr grid_;  ///< null where the bricks answer the lookups
    Eigen::Affine3d worldToIndex_;
    double scale_;
    double sigmaMax_;  ///< the largest majorant (as segments() inflates it)
    bool regular_;     ///< regular tracking is on and can be preferred along some ray
    MajorantGrid majorants_;
    std::optional<DensityBricks> bricks_;
    std::string desc_;
};

/// A grid's float value with the digits that tell it from its neighbours (%.9g): to_string wrote
/// a voxel of −10⁻²⁰ as -0.000000.
std::string floatText(float v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.9g", double(v));
    return text;
}

std::string ijkString(const openvdb::Coord& c) {
    std::ostringstream s;
    s << "(" << c.x() << ", " << c.y() << ", " << c.z() << ")";
    return s.str();
}

}  // namespace

std::unique_ptr<Medium> loadVdbMedium(const VdbMediumDesc& desc) {
    initOpenVdb();
    const std::string& path = desc.file;
    const std::string where = "grid '" + desc.grid + "'";
    const uintmax_t size = regularFileSize(path);

    openvdb::FloatGrid::Ptr grid;
    // Where OpenVDB's own errors are (decompression, a tree's masks): the grid being read and its
    // bytes, once known (they named no place; helper 103).
    std::string reading;
    try {
        std::ifstream in(path, std::ios::binary);
        if (!in) fail(path, "", "cannot open file");
        in.exceptions(std::ios::failbit | std::ios::badbit);
        const std::vector<VdbGridEntry> grids = checkVdbStructure(in, size);
        // As io::File finds a grid: by unique name ("density[1]" for a second "density"),
        // else the first grid of that name.
        const VdbGridEntry* entry = nullptr;
        for (const VdbGridEntry& e : grids)
            if (!entry && openvdb::io::GridDescriptor::nameAsString(e.uniqueName) == desc.grid)
                entry = &e;
        for (const VdbGridEntry& e : grids)
            if (!entry && openvdb::io::GridDescriptor::stripSuffix(e.uniqueName) == desc.grid)
                entry = &e;
        if (!entry) {
            std::string names;
            for (const VdbGridEntry& e : grids)
                names += (names.empty() ? "" : ", ") +
                         openvdb::io::GridDescriptor::nameAsString(e.uniqueName);
            fail(path, where, "no such grid; the file has: " + (names.empty() ? "(none)" : names));
        }
        if (entry->instance) fail(path, where, "instanced grids are not supported");
        reading = where + " (bytes " + std::to_string(entry->descriptorPos) + " to " +
                  std::to_string(entry->endPos) + ")";
        const openvdb::GridBase::Ptr base =
            VdbGridReader().read(in, *entry, [&](const openvdb::GridBase& g) {
                if (!g.isType<openvdb::FloatGrid>())
                    fail(path, where, "has value type " + g.valueType() + ", expected float");
            });
        grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
    } catch (const Error&) {
        throw;
    } catch (const openvdb::ArithmeticError& e) {
        // OpenVDB builds an affine (rotated, sheared) transform's map as it reads it, and refuses
        // a matrix of determinant below about 3·10⁻¹⁵: voxels under about 1.4·10⁻⁵.
        fail(path, where,
             std::string("OpenVDB cannot read its transform (") + e.what() +
                 "): singular, damaged, or an affine (rotated, sheared) map of voxels below about "
                 "1.5e-5, which OpenVDB refuses; for the last, store the grid with larger voxels "
                 "and scale it down with the medium's transform");
    } catch (const std::exception& e) {
        // A file of another kind named as such, as the EXR reader does (helper 181: a scene given
        // as a grid said "no VDB header").
        if (const std::string other = fileOfAnotherKind(path, "an OpenVDB grid"); !other.empty())
            fail(path, reading, other);
        fail(path, reading, std::string("not a readable OpenVDB file (") + e.what() + ")");
    }
    if (!grid->transform().isLinear()) fail(path, where, "non-linear transforms are not supported");
    if (grid->background() != 0.f)
        fail(path, where, "background value must be 0, is " + floatText(grid->background()));

    // Index → grid world, x ↦ J·x + t: the linear base map's Jacobian (its matrix without the
    // translation) on the unit vectors, and its image of the origin. (Through getAffineMap(), a
    // voxel smaller than about 1.5·10⁻⁵ was refused: AffineMap calls a matrix of determinant below
    // about 10⁻¹⁵ nearly singular. The scene's transform below may scale it back up.)
    Eigen::Affine3d gridToWorld = Eigen::Affine3d::Identity();
    const openvdb::math::MapBase& map = *grid->transform().baseMap();
    for (int c = 0; c < 3; ++c) {
        openvdb::Vec3d unit(0, 0, 0);
        unit[c] = 1;
        const openvdb::Vec3d col = map.applyJacobian(unit);
        gridToWorld.linear().col(c) = Vec3(col.x(), col.y(), col.z());
    }
    const openvdb::Vec3d t = map.applyMap(openvdb::Vec3d(0, 0, 0));
    gridToWorld.translation() = Vec3(t.x(), t.y(), t.z());
    const Eigen::Affine3d indexToWorld = desc.toWorld * gridToWorld;
    const Eigen::Affine3d worldToIndex = indexToWorld.inverse();
    if (!indexToWorld.matrix().allFinite() || !worldToIndex.matrix().allFinite() ||
        !(std::abs(indexToWorld.linear().determinant()) > 0))
        fail(path, where, "the transform (with the scene's) is singular or not finite");

    // Pass 1: validate every stored value and find the bounds of non-zero density. Index
    // coordinates stay within ±2^30, so that lookups one voxel further and the bounds below
    // cannot overflow an int.
    const openvdb::FloatTree& tree = grid->tree();
    constexpr int kMaxIndex = 1 << 30;
    openvdb::CoordBBox bounds;
    forEachValue(tree, true, [&](float v, const openvdb::CoordBBox& b) {
        if (!std::isfinite(v) || v < 0)
            fail(path, where,
                 std::string(std::isfinite(v) ? "negative" : "NaN or infinite") + " density " +
                     floatText(v) + " at voxel " + ijkString(b.min()));
        if (v > 0) {
            const openvdb::Coord &lo = b.min(), &hi = b.max();
            if (std::min({lo.x(), lo.y(), lo.z()}) < -kMaxIndex ||
                std::max({hi.x(), hi.y(), hi.z()}) > kMaxIndex)
                fail(path, where,
                     "density at voxel " + ijkString(b.min()) +
                         ", beyond the supported index range ±2^30");
            bounds.expand(b);
        }
    });
    MajorantGrid majorants;
    int cellVoxels = 0;  // the majorant cell edge chosen (0: one global majorant)
    if (!bounds.empty()) {
        // Trilinear lookups reach one voxel beyond a stored value.
        const Vec3 lo = Vec3(bounds.min().x(), bounds.min().y(), bounds.min().z()).array() - 1;
        const Vec3 hi = Vec3(bounds.max().x(), bounds.max().y(), bounds.max().z()).array() + 1;
        // Cells of `cell` voxels from lo, doubled while the grid would have more than
        // kMaxMajorantCells cells (one tile can cover 4096³ voxels of a file of 100 bytes).
        constexpr double kMaxMajorantCells = 1 << 22;
        const bool automatic = desc.majorantGrid && desc.majorantCellVoxels == 0;
        double cell = desc.majorantGrid ? (automatic ? 1 : desc.majorantCellVoxels) : 0;
        if (desc.majorantGrid) {
            while (((hi - lo) / cell).array().ceil().prod() > kMaxMajorantCells) cell *= 2;
            majorants = MajorantGrid::withCells(lo, hi, cell);
        } else {
            majorants = MajorantGrid(lo, hi, Eigen::Vector3i(1, 1, 1));
        }
        forEachValue(tree, true, [&](float v, const openvdb::CoordBBox& b) {
            if (v > 0)
                majorants.expand(Vec3(b.min().x(), b.min().y(), b.min().z()).array() - 1,
                                 Vec3(b.max().x(), b.max().y(), b.max().z()).array() + 1, v);
        });
        cellVoxels = int(cell);
        if (automatic) {
            // The cell edge (1 voxel, doubled up to one cell over the whole grid) that minimises
            // the expected cost of tracking along fixed random lines through the medium's box: a
            // DDA step costs about 1/7 of a tentative collision (build/bench_io, PlumeSegments and
            // PlumeFreeFlight: 10.6 ns per segment, 72 ns per tentative collision with its
            // exponential and lookup). (The index range, ±2^30, keeps the edge an int.)
            constexpr double kSegmentCost = 1.0 / 7;
            std::vector<std::pair<Vec3, Vec3>> lines;
            Rng rng(0x6d616a6f72616e74ULL, 0);
            for (int i = 0; i < 1024; ++i) {
                const Vec3 p =
                    lo + (hi - lo).cwiseProduct(Vec3(rng.uniform(), rng.uniform(), rng.uniform()));
                // t in scene units along a uniformly distributed scene direction.
                lines.emplace_back(p, worldToIndex.linear() * sampleUniformSphere(rng.uniform2()));
            }
            double best = majorants.trackingCost(lines, desc.densityScale, kSegmentCost);
            // Coarsened from the finest grid, then from the last coarsening (not from a copy
            // of the finest grid, which would be the largest allocation of the choice).
            MajorantGrid g;
            for (const MajorantGrid* from = &majorants;
                 from->resolution().maxCoeff() > 1 && cell < (1 << 30); from = &g) {
                g = from->coarsened();
                cell *= 2;
                const double cost = g.trackingCost(lines, desc.densityScale, kSegmentCost);
                if (cost <= best) best = cost, majorants = g, cellVoxels = int(cell);
            }
        }
    }
    if (desc.decomposition && !majorants.empty()) majorants.setMinimum(minorants(tree, majorants));
    std::optional<DensityBricks> bricks;
    if (desc.bricks) bricks = makeBricks(tree);
    // (The tree only where no bricks are made: lookups read one or the other. It is freed
    // before the render, though the load's peak memory still holds both; helper 168.)
    return std::make_unique<VdbMedium>(desc, bricks ? nullptr : grid, worldToIndex,
                                       std::move(majorants), cellVoxels, std::move(bricks));
}

namespace {
/// OpenVDB stamps every file with a random UUID (36 characters after the 21-byte header of
/// magic, versions and the offsets flag), so two writes of the same grids differ, and a grid
/// made again would change the fingerprints of checkpoints and batch ledgers that name it. The
/// UUID is replaced by one hashed from the rest of the file (RFC 9562 version 8, "custom"): the
/// same grids give the same bytes. A file whose header is not laid out so is left as written.
/// Read in pieces, so that a large grid is not held in memory again.
void makeUuidFromContents(const std::string& file, const std::string& name) {
    constexpr size_t kAt = 21, kLength = 36;
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    std::string head(kAt + kLength, '\0');
    if (!f.read(head.data(), std::streamsize(head.size()))) return;
    std::string uuid = head.substr(kAt, kLength);
    for (size_t i = 0; i < kLength; ++i) {
        const bool dash = i == 8 || i == 13 || i == 18 || i == 23;
        if (dash != (uuid[i] == '-') || (!dash && !std::isxdigit((unsigned char)uuid[i]))) return;
    }
    std::fill(head.begin() + kAt, head.end(), '0');
    uint64_t h[2] = {fnv1a(head.data(), head.size()),
                     fnv1a(head.data(), head.size(), 0x9e3779b97f4a7c15ULL)};
    std::vector<char> piece(1 << 20);
    while (f.read(piece.data(), std::streamsize(piece.size())) || f.gcount() > 0) {
        h[0] = fnv1a(piece.data(), size_t(f.gcount()), h[0]);
        h[1] = fnv1a(piece.data(), size_t(f.gcount()), h[1]);
    }
    char hex[33];
    std::snprintf(hex, sizeof hex, "%016llx%016llx", (unsigned long long)h[0],
                  (unsigned long long)h[1]);
    hex[12] = '8';  // version 8
    const char c = hex[16];
    hex[16] = "89ab"[(std::isdigit((unsigned char)c) ? c - '0' : c - 'a' + 10) & 3];  // 10xx
    for (size_t i = 0, k = 0; i < kLength; ++i)
        if (uuid[i] != '-') uuid[i] = hex[k++];
    f.clear();
    f.seekp(std::streamoff(kAt));
    errno = 0;
    f.write(uuid.data(), std::streamsize(kLength));
    f.close();
    if (!f) failWriting(name, errno);
}

/// io::File's writer (its header, with the grids' offsets: "seekable") into a stream of ours:
/// io::File writes through a std::ofstream of its own that it never checks, and a full disk
/// left a truncated file that was reported written, exit 0 (before 6 Dec; helper 100).
class VdbWriter : public openvdb::io::Archive {
  public:
    void operator()(std::ostream& os, const openvdb::GridPtrVec& grids) const {
        write(os, grids, /*seekable=*/true);
    }
};
}  // namespace

size_t writeVdb(const std::string& path, const std::vector<VdbGridSpec>& specs,
                const std::function<void(const std::vector<VdbGridSummary>&)>& beforeWrite,
                bool progress) {
    initOpenVdb();
    openvdb::GridPtrVec grids;
    std::vector<VdbGridSummary> summaries;
    size_t active = 0;
    long long voxels = 0;
    for (const VdbGridSpec& s : specs)
        voxels += (long long)s.resolution * s.resolution * s.resolution;
    Progress bar("voxels", voxels, progress && Progress::stderrIsTerminal());
    for (const VdbGridSpec& s : specs) {
        const double h = 1.0 / s.resolution;
        auto xform = openvdb::math::Transform::createLinearTransform(h);
        xform->postTranslate(openvdb::Vec3d(-0.5 + 0.5 * h));
        auto fill = [&](auto grid, auto make) {
            using Tree = typename decltype(grid)::element_type::TreeType;
            // Slabs one leaf deep: their leaves are disjoint, and merging moves them whole.
            const int slabs = (s.resolution + 7) / 8;
            std::vector<std::unique_ptr<Tree>> trees(slabs);
            tbb::parallel_for(0, slabs, [&](int b) {
                auto tree = std::make_unique<Tree>(grid->background());
                openvdb::tree::ValueAccessor<Tree> acc(*tree);
                const int k1 = std::min(s.resolution, 8 * (b + 1));
                for (int k = 8 * b; k < k1; ++k)
                    for (int j = 0; j < s.resolution; ++j)
                        for (int i = 0; i < s.resolution; ++i) {
                            const float v = s.density(Vec3((i + 0.5) * h - 0.5, (j + 0.5) * h - 0.5,
                                                           (k + 0.5) * h - 0.5));
                            if (v != 0.f || std::isnan(v))
                                acc.setValue(openvdb::Coord(i, j, k), make(v));
                        }
                trees[b] = std::move(tree);
                bar.advance((long long)(k1 - 8 * b) * s.resolution * s.resolution);
            });
            for (const std::unique_ptr<Tree>& tree : trees) grid->tree().merge(*tree);
            VdbGridSummary summary;
            summary.activeVoxels = grid->activeVoxelCount();
            const openvdb::CoordBBox box = grid->evalActiveVoxelBoundingBox();
            if (summary.activeVoxels > 0)
                for (int a = 0; a < 3; ++a)
                    summary.lo[a] = box.min()[a], summary.hi[a] = box.max()[a];
            summaries.push_back(summary);
            active += summary.activeVoxels;
            grid->setName(s.name);
            grid->setTransform(xform);
            grid->setGridClass(openvdb::GRID_FOG_VOLUME);
            grids.push_back(grid);
        };
        if (s.type == VdbGridSpec::Type::Float)
            fill(openvdb::FloatGrid::create(0.f), [](float v) { return v; });
        else
            fill(openvdb::Vec3SGrid::create(), [](float v) { return openvdb::Vec3s(v); });
    }
    bar.done();
    if (beforeWrite) beforeWrite(summaries);
    writeAtomically(path, [&](const std::string& tmp) {
        writeStreamTo(tmp, path, "VDB", [&](std::ofstream& os) { VdbWriter()(os, grids); });
        makeUuidFromContents(tmp, path);
    });
    return active;
}

}  // namespace shvol
