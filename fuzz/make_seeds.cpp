// Writes the binary seed files of the EXR, VDB and checkpoint fuzz targets (tests/fuzz/exr/,
// tests/fuzz/vdb/, tests/fuzz/checkpoint/):
// tiny valid files in the formats' main variants (compressions, pixel types, tiles, luminance
// only, offset data window; VDB codecs, tiles, several grids) and a few slightly broken ones (a
// truncated file, a NaN or negative value, a wrong grid type). Every file is well under 20 KB.
//   build-fuzz/fuzz_seeds tests/fuzz
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <ImfTiledOutputFile.h>

#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz_checkpoint.h"
#include "shvol/core/error.h"
#include "shvol/io/exr.h"
#include "shvol/io/procedural.h"
#include "shvol/io/vdb.h"

namespace fs = std::filesystem;

namespace {

constexpr int W = 8, H = 4;

float pixel(int x, int y, int c) {
    return 0.1f * float(x) + 0.25f * float(y) + 0.5f * float(c);
}

/// An 8×4 EXR with the named channels (each a ramp), written scanline or tiled.
void writeExrVariant(const std::string& path, const std::vector<std::string>& channels,
                     Imf::PixelType type, Imf::Compression compression, bool tiled = false,
                     Imath::V2i origin = {0, 0}) {
    const Imath::Box2i dw(origin, origin + Imath::V2i(W - 1, H - 1));
    Imf::Header header(dw, dw);
    header.compression() = compression;
    for (const std::string& c : channels) header.channels().insert(c, Imf::Channel(type));
    std::vector<std::vector<float>> f(channels.size(), std::vector<float>(W * H));
    std::vector<std::vector<half>> h(channels.size(), std::vector<half>(W * H));
    Imf::FrameBuffer fb;
    for (size_t c = 0; c < channels.size(); ++c) {
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) f[c][y * W + x] = h[c][y * W + x] = pixel(x, y, int(c));
        char* base = type == Imf::HALF ? reinterpret_cast<char*>(h[c].data())
                                       : reinterpret_cast<char*>(f[c].data());
        const size_t xs = type == Imf::HALF ? sizeof(half) : sizeof(float);
        base -= (origin.x + origin.y * W) * xs;
        fb.insert(channels[c], Imf::Slice(type, base, xs, xs * W));
    }
    if (tiled) {
        header.setTileDescription(Imf::TileDescription(4, 4, Imf::ONE_LEVEL));
        Imf::TiledOutputFile file(path.c_str(), header);
        file.setFrameBuffer(fb);
        file.writeTiles(0, file.numXTiles() - 1, 0, file.numYTiles() - 1);
    } else {
        Imf::OutputFile file(path.c_str(), header);
        file.setFrameBuffer(fb);
        file.writePixels(H);
    }
}

/// A checkpoint seed (fuzz_checkpoint.h): the file writeCheckpoint writes, without its checksum.
void writeCheckpointSeed(const std::string& path, const shvol::Film& film,
                         const shvol::Json& identity) {
    shvol::writeCheckpoint(path, film, identity);
    fs::resize_file(path, fs::file_size(path) - sizeof(uint64_t));
}

void truncateCopy(const std::string& from, const std::string& to, double fraction) {
    std::ifstream in(from, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), {});
    std::ofstream(to, std::ios::binary) << bytes.substr(0, size_t(bytes.size() * fraction));
}

openvdb::FloatGrid::Ptr sphereGrid(int res, const std::string& name) {
    auto grid = openvdb::FloatGrid::create(0.f);
    const double h = 1.0 / res;
    auto acc = grid->getAccessor();
    for (int k = 0; k < res; ++k)
        for (int j = 0; j < res; ++j)
            for (int i = 0; i < res; ++i) {
                const shvol::Vec3 p((i + 0.5) * h - 0.5, (j + 0.5) * h - 0.5, (k + 0.5) * h - 0.5);
                const float v = float(shvol::sphereDensity(p, 0.35, h));
                if (v > 0) acc.setValue(openvdb::Coord(i, j, k), v);
            }
    auto xform = openvdb::math::Transform::createLinearTransform(h);
    xform->postTranslate(openvdb::Vec3d(-0.5 + 0.5 * h));
    grid->setTransform(xform);
    grid->setName(name);
    grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    return grid;
}

void writeVdbVariant(const std::string& path, const openvdb::GridPtrVec& grids,
                     uint32_t compression) {
    openvdb::io::File file(path);
    file.setCompression(compression);
    file.write(grids);
    file.close();
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: fuzz_seeds tests/fuzz\n");
        return 2;
    }
    const fs::path root = argv[1];
    const std::string exr = (root / "exr").string() + "/", vdb = (root / "vdb").string() + "/",
                      ckpt = (root / "checkpoint").string() + "/";
    for (const std::string& dir : {exr, vdb, ckpt}) fs::create_directories(dir);
    try {
        // EXR: what shvol writes (float RGB, ZIP), then the other layouts readExr accepts.
        shvol::Image img(W, H);
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x)
                img.set(x, y, shvol::Spectrum(pixel(x, y, 0), pixel(x, y, 1), pixel(x, y, 2)));
        shvol::writeExr(exr + "rgb_float.exr", img);
        const std::vector<std::string> rgb = {"R", "G", "B"};
        writeExrVariant(exr + "rgb_half_none.exr", rgb, Imf::HALF, Imf::NO_COMPRESSION);
        writeExrVariant(exr + "rgb_half_rle.exr", rgb, Imf::HALF, Imf::RLE_COMPRESSION);
        writeExrVariant(exr + "rgb_half_piz.exr", rgb, Imf::HALF, Imf::PIZ_COMPRESSION);
        writeExrVariant(exr + "rgb_float_pxr24.exr", rgb, Imf::FLOAT, Imf::PXR24_COMPRESSION);
        writeExrVariant(exr + "rgba_half_b44a.exr", {"R", "G", "B", "A"}, Imf::HALF,
                        Imf::B44A_COMPRESSION);
        writeExrVariant(exr + "rgb_half_dwaa.exr", rgb, Imf::HALF, Imf::DWAA_COMPRESSION);
        writeExrVariant(exr + "y_float_zips.exr", {"Y"}, Imf::FLOAT, Imf::ZIPS_COMPRESSION);
        writeExrVariant(exr + "rgb_uint_tiled.exr", rgb, Imf::UINT, Imf::ZIP_COMPRESSION, true);
        writeExrVariant(exr + "rgb_half_offset_window.exr", rgb, Imf::HALF, Imf::ZIP_COMPRESSION,
                        false, {-3, 5});
        // Slightly broken: no colour channel, a negative and a NaN pixel, a truncated file.
        writeExrVariant(exr + "bad_z_only.exr", {"Z"}, Imf::FLOAT, Imf::NO_COMPRESSION);
        img.set(3, 2, shvol::Spectrum(0, -1, 0));
        shvol::writeExr(exr + "bad_negative.exr", img);
        img.set(3, 2, shvol::Spectrum(NAN, 0, 0));
        shvol::writeExr(exr + "bad_nan.exr", img);
        truncateCopy(exr + "rgb_half_piz.exr", exr + "bad_truncated.exr", 0.7);

        // VDB: an 8³ sphere with each codec (COMPRESS_NONE is left out: it stores every tile
        // value of the 32³ top node, 160 KB), a tile, two grids; then broken variants.
        openvdb::initialize();
        writeVdbVariant(vdb + "sphere8.vdb", {sphereGrid(8, "density")},
                        openvdb::io::COMPRESS_ACTIVE_MASK);
        writeVdbVariant(vdb + "sphere8_zip.vdb", {sphereGrid(8, "density")},
                        openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_ACTIVE_MASK);
        writeVdbVariant(vdb + "sphere8_blosc.vdb", {sphereGrid(8, "density")},
                        openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ACTIVE_MASK);
        {
            auto g = sphereGrid(4, "density");
            g->tree().addTile(1, openvdb::Coord(64, 0, 0), 0.5f, true);  // one 8³ tile
            writeVdbVariant(vdb + "tile.vdb", {g}, openvdb::io::COMPRESS_ACTIVE_MASK);
        }
        {
            auto empty = openvdb::FloatGrid::create(0.f);  // an empty tree is a few bytes
            empty->setName("smoke");
            writeVdbVariant(vdb + "two_grids.vdb", {empty, sphereGrid(4, "density")},
                            openvdb::io::COMPRESS_ACTIVE_MASK);
        }
        {
            // One root tile covers 4096³ voxels: 4 KB of file, 6.9·10¹⁰ voxels of density.
            auto g = openvdb::FloatGrid::create(0.f);
            g->tree().addTile(3, openvdb::Coord(0, 0, 0), 0.5f, true);
            g->setTransform(openvdb::math::Transform::createLinearTransform(1.0 / 4096));
            g->setName("density");
            writeVdbVariant(vdb + "root_tile.vdb", {g}, openvdb::io::COMPRESS_ACTIVE_MASK);
        }
        {
            // Values at every level: 32 × 32 root tiles in a slab (OpenVDB's tree iterator took
            // time quadratic in their number), a 128³ and an 8³ tile, and a sphere's voxels;
            // tile (i, j) holds 1 + ((i + 3j) mod 7)/4.
            auto g = sphereGrid(4, "density");
            for (int i = 0; i < 32; ++i)
                for (int j = 0; j < 32; ++j)
                    g->tree().addTile(3, openvdb::Coord(4096 * (i + 1), 4096 * j, 0),
                                      1 + float((i + 3 * j) % 7) / 4, true);
            g->tree().addTile(2, openvdb::Coord(0, 0, 128), 0.75f, true);
            g->tree().addTile(1, openvdb::Coord(64, 0, 0), 0.5f, true);
            g->setTransform(openvdb::math::Transform::createLinearTransform(1.0));
            writeVdbVariant(vdb + "every_level.vdb", {g}, openvdb::io::COMPRESS_ACTIVE_MASK);
        }
        writeVdbVariant(vdb + "bad_named_smoke.vdb", {sphereGrid(4, "smoke")},
                        openvdb::io::COMPRESS_ACTIVE_MASK);
        {
            auto g = openvdb::Vec3SGrid::create();
            g->tree().setValue(openvdb::Coord(1, 2, 3), openvdb::Vec3s(1, 0, 0));
            g->setName("density");
            writeVdbVariant(vdb + "bad_vec3.vdb", {g}, openvdb::io::COMPRESS_ACTIVE_MASK);
        }
        {
            auto g = sphereGrid(4, "density");
            g->tree().setValue(openvdb::Coord(1, 1, 1), -0.5f);
            writeVdbVariant(vdb + "bad_negative.vdb", {g}, openvdb::io::COMPRESS_ACTIVE_MASK);
        }
        {
            auto g = openvdb::FloatGrid::create(1.f);  // background must be 0
            g->tree().setValue(openvdb::Coord(0, 0, 0), 2.f);
            g->setName("density");
            writeVdbVariant(vdb + "bad_background.vdb", {g}, openvdb::io::COMPRESS_ACTIVE_MASK);
        }
        truncateCopy(vdb + "sphere8.vdb", vdb + "bad_truncated.vdb", 0.6);

        // Checkpoints of the fuzzer's render (4x3), without and with sums of squares, with the
        // luminances' squares unknown (flags bit 1 clear, as before 6 Dec); one of another render
        // (the seed and a file's contents differ).
        const shvol::Json identity = shvol::fuzz::checkpointIdentity();
        shvol::Film film(4, 3);
        for (size_t i = 0; i < film.pixels(); ++i) {
            film.count[i] = uint32_t(i % 5);
            for (int c = 0; c < 3; ++c) film.sum[3 * i + c] = 0.25 * double(i + c);
            film.luminanceSumSq[i] = 0.0625 * double(i);
        }
        writeCheckpointSeed(ckpt + "film.ckpt", film, identity);
        shvol::Film unknown = film;
        unknown.luminanceSumSq.clear();
        writeCheckpointSeed(ckpt + "unknown_squares.ckpt", unknown, identity);
        film.sumSq = film.sum;
        writeCheckpointSeed(ckpt + "variance.ckpt", film, identity);
        shvol::Json other = identity;
        other["scene"]["render.seed"] = "0";
        other["inputs"]["media[0].file"] = "0";
        writeCheckpointSeed(ckpt + "other_render.ckpt", film, other);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "fuzz_seeds: %s\n", e.what());
        return 1;
    }
    return 0;
}
