#include "shvol/lights/sky_hierarchy.h"

#include <algorithm>
#include <cmath>

#include "shvol/core/error.h"
#include "shvol/sampling/warp.h"

namespace shvol {

namespace {

/// Adds value·|[a, b) ∩ cell| to every cell of width h on [0, n·h) overlapped by [a, b), where
/// 0 ≤ a < b ≤ n·h.
void distribute(double a, double b, double h, int n, double value, double* cells) {
    int i = std::clamp(int(a / h), 0, n - 1);
    for (; i < n; ++i) {
        const double lo = std::max(a, i * h), hi = std::min(b, (i + 1) * h);
        if (hi > lo) cells[i] += value * (hi - lo);
        if ((i + 1) * h >= b) break;
    }
}

}  // namespace

SkyHierarchy SkyHierarchy::fromLatLong(const LatLongSource& src, int levels, size_t K) {
    const Image& img = *src.image;
    const int W = img.width, H = img.height;
    if (W <= 0 || H <= 0) fail("", "environment", "the environment image is empty");
    if (levels < 0)
        levels = std::clamp(int(std::ceil(0.5 * std::log2(double(W) * H))), 1, kMaxLevels);
    if (levels > kMaxLevels) throw Error("SkyHierarchy: levels out of range");
    const int N = 1 << levels;
    const double hz = 2.0 / N, hphi = TwoPi / N;
    // Row sums S[iz][iφ] = ∫ Y over the leaf, accumulated image row by image row.
    std::vector<double> S(size_t(N) * N, 0.0), R(N);
    for (int y = 0; y < H; ++y) {
        double zLo = std::cos(Pi * (y + 1) / H), zHi = std::cos(Pi * y / H);
        if (src.lowerHemisphereBlack) zLo = std::max(zLo, 0.0);
        if (!(zHi > zLo)) continue;
        // R[iφ] = Σ_x Y(x, y)·|φ-interval of x ∩ leaf column iφ|.
        std::fill(R.begin(), R.end(), 0.0);
        for (int x = 0; x < W; ++x) {
            const double Y = src.scale * luminance(img.at(x, y));
            if (!(Y > 0)) continue;
            const double p0 = latLongPhi(src.mapping, double(x) / W);
            const double p1 = latLongPhi(src.mapping, double(x + 1) / W);
            double a = std::min(p0, p1) + src.rotation;
            a -= TwoPi * std::floor(a * Inv2Pi);
            if (a >= TwoPi) a = 0;
            const double b = a + TwoPi / W;
            distribute(a, std::min(b, TwoPi), hphi, N, Y, R.data());
            if (b > TwoPi) distribute(0, b - TwoPi, hphi, N, Y, R.data());
        }
        // Spread the row over the leaf rows its z-interval overlaps.
        const int iz0 = std::clamp(int((zLo + 1) / hz), 0, N - 1);
        for (int iz = iz0; iz < N && -1 + iz * hz < zHi; ++iz) {
            const double ov = std::min(zHi, -1 + (iz + 1) * hz) - std::max(zLo, -1 + iz * hz);
            if (!(ov > 0)) continue;
            double* row = &S[size_t(iz) * N];
            for (int i = 0; i < N; ++i) row[i] += ov * R[i];
        }
    }
    const double leafArea = hz * hphi;
    for (double& s : S) s /= leafArea;
    return fromLeaves(levels, S, K);
}

SkyHierarchy SkyHierarchy::constant(double luminance, bool lowerHemisphereBlack) {
    if (!lowerHemisphereBlack) return fromLeaves(0, {std::max(0.0, luminance)});
    // Level 1: rows iz = 0 (z < 0) black, iz = 1 lit.
    const double L = std::max(0.0, luminance);
    return fromLeaves(1, {0.0, 0.0, L, L});
}

SkyHierarchy SkyHierarchy::fromLeaves(int levels, const std::vector<double>& leaves, size_t K) {
    if (levels < 0 || levels > kMaxLevels) throw Error("SkyHierarchy: levels out of range");
    const uint32_t N = 1u << levels;
    if (leaves.size() != size_t(N) * N) throw Error("SkyHierarchy: wrong number of leaves");
    double brightest = 0;
    for (const double v : leaves) {
        if (!(v >= 0) || !std::isfinite(v))
            throw Error("SkyHierarchy: leaf values must be finite and >= 0");
        brightest = std::max(brightest, v);
    }
    SkyHierarchy h;
    h.levels_ = levels;
    h.unit_ = brightest > 0 ? brightest : 1.0;
    std::vector<double> morton(leaves.size());
    for (uint32_t iz = 0; iz < N; ++iz)
        for (uint32_t ip = 0; ip < N; ++ip)
            morton[mortonIndex(iz, ip)] = leaves[size_t(iz) * N + ip] / h.unit_;
    h.buildMipMap(std::move(morton));
    if (K > 0 && K < h.detailCount()) h.compress(K);
    return h;
}

void SkyHierarchy::buildMipMap(std::vector<double> level) {
    mip_.assign(levels_ + 1, {});
    for (int d = levels_;; --d) {
        mip_[d].assign(level.begin(), level.end());
        if (d == 0) break;
        std::vector<double> coarse(level.size() / 4);
        for (size_t i = 0; i < coarse.size(); ++i)
            coarse[i] =
                0.25 * (level[4 * i] + level[4 * i + 1] + level[4 * i + 2] + level[4 * i + 3]);
        level.swap(coarse);
    }
}

size_t SkyHierarchy::detailCount() const {
    return ((size_t(1) << (2 * levels_)) - 1);  // 3·(4^k − 1)/3 internal-node details
}

void SkyHierarchy::compress(size_t K) {
    // All details with their orthonormal magnitude 2^{−d}|D| (the mip-map is exact here; details
    // are computed in double from the stored float averages).
    struct Detail {
        float magnitude;
        uint32_t level, node;
        uint8_t which;
    };
    std::vector<Detail> all;
    all.reserve(detailCount());
    std::vector<std::array<double, 3>> D;  // per node of the level being scanned
    double total2 = sqr(double(mip_[0][0]));
    for (int d = 0; d < levels_; ++d) {
        const std::vector<float>& fine = mip_[d + 1];
        const double w = std::ldexp(1.0, -d);
        for (uint32_t i = 0; i < uint32_t(mip_[d].size()); ++i) {
            const double c00 = fine[4 * i], c01 = fine[4 * i + 1], c10 = fine[4 * i + 2],
                         c11 = fine[4 * i + 3];
            const double det[3] = {0.25 * (c00 - c01 + c10 - c11), 0.25 * (c00 + c01 - c10 - c11),
                                   0.25 * (c00 - c01 - c10 + c11)};
            for (int j = 0; j < 3; ++j) {
                total2 += sqr(w * det[j]);
                all.push_back({float(w * std::abs(det[j])), uint32_t(d), i, uint8_t(j)});
            }
        }
    }
    std::nth_element(all.begin(), all.begin() + K, all.end(),
                     [](const Detail& a, const Detail& b) { return a.magnitude > b.magnitude; });
    double dropped2 = 0;
    for (size_t i = K; i < all.size(); ++i) dropped2 += sqr(double(all[i].magnitude));
    all.resize(K);
    // Zero details among the K largest (flat regions) cost memory and change nothing.
    all.erase(
        std::remove_if(all.begin(), all.end(), [](const Detail& e) { return !(e.magnitude > 0); }),
        all.end());
    std::sort(all.begin(), all.end(), [](const Detail& a, const Detail& b) {
        return a.level != b.level ? a.level < b.level : a.node < b.node;
    });
    detailNodes_.assign(levels_, {});
    details_.assign(levels_, {});
    for (const Detail& e : all) {
        auto& nodes = detailNodes_[e.level];
        auto& dets = details_[e.level];
        if (nodes.empty() || nodes.back() != e.node) {
            nodes.push_back(e.node);
            dets.push_back({0.f, 0.f, 0.f});
        }
        // Recompute the signed value (the magnitude lost the sign).
        const std::vector<float>& fine = mip_[e.level + 1];
        const size_t i = e.node;
        const double c00 = fine[4 * i], c01 = fine[4 * i + 1], c10 = fine[4 * i + 2],
                     c11 = fine[4 * i + 3];
        const double det[3] = {0.25 * (c00 - c01 + c10 - c11), 0.25 * (c00 + c01 - c10 - c11),
                               0.25 * (c00 - c01 - c10 + c11)};
        dets.back()[e.which] = float(det[e.which]);
    }
    kept_ = all.size();
    l2Error_ = total2 > 0 ? std::sqrt(dropped2 / total2) : 0.0;
    compressed_ = true;
    // The second moment against the exact masses, on the cells of level ℓ (the mip-map is still
    // whole here): a descent by the compressed sampler's splits.
    const int level = std::min(levels_, kMomentLevel);
    const double alpha = kDefensiveFraction, cells = std::ldexp(1.0, 2 * level);
    const double root = mip_[0][0];
    secondMoment_ = 0;
    const auto descend = [&](const auto& self, int d, uint64_t node, double avg,
                             double prob) -> void {
        if (d == level) {
            const double m = double(mip_[level][node]) / (root * cells);
            if (m > 0) secondMoment_ += m * m / ((1 - alpha) * prob + alpha / cells);
            return;
        }
        double c[4];
        compressedChildren(d, node, avg, c);
        const detail::Split s(c);
        for (int k = 0; k < 4; ++k)
            self(self, d + 1, 4 * node + k, c[k],
                 s.total > 0 && s.c[k] > 0 ? prob * s.c[k] / s.total : 0.0);
    };
    if (root > 0) descend(descend, 0, 0, root, 1.0);
    mip_.resize(1);  // the sampler only reads the root and the kept details
    mip_.shrink_to_fit();
}

void SkyHierarchy::compressedChildren(int level, uint64_t morton, double a, double c[4]) const {
    const std::vector<uint32_t>& nodes = detailNodes_[level];
    const auto it = std::lower_bound(nodes.begin(), nodes.end(), uint32_t(morton));
    double Dphi = 0, Dz = 0, Dd = 0;
    if (it != nodes.end() && *it == morton) {
        const std::array<float, 3>& d = details_[level][it - nodes.begin()];
        Dphi = d[0], Dz = d[1], Dd = d[2];
    }
    c[0] = a + Dphi + Dz + Dd;
    c[1] = a - Dphi + Dz - Dd;
    c[2] = a + Dphi - Dz - Dd;
    c[3] = a - Dphi - Dz + Dd;
}

double SkyHierarchy::samplingAverage(int level, uint32_t iz, uint32_t iphi) const {
    if (!compressed_) return mip_[level][mortonIndex(iz, iphi)];  // sampler units, as the others
    double avg = mip_[0][0], c[4];
    uint64_t node = 0;
    for (int d = 0; d < level; ++d) {
        const int shift = level - 1 - d;
        const int r = (iz >> shift) & 1, k = (iphi >> shift) & 1;
        compressedChildren(d, node, avg, c);
        avg = c[2 * r + k];
        node = 4 * node + 2 * r + k;
    }
    return avg;
}

WarpSample SkyHierarchy::warpWithoutShare(Vec2 u) const {
    double avg = mip_[0][0], c[4], prob = 1;
    if (!(avg > 0)) return {};
    uint64_t node = 0;
    uint32_t iz = 0, ip = 0;
    for (int d = 0; d < levels_; ++d) {
        prefetchGrandchildren(d, node);
        childAverages(d, node, avg, c);
        const detail::Split s(c);
        if (!(s.total > 0)) return {};
        const int r = detail::choose(s.pRow0, u.x());
        const int k = detail::choose(s.pCol0[r], u.y());
        prob *= s.c[2 * r + k] / s.total;
        avg = c[2 * r + k];
        node = 4 * node + 2 * r + k;
        iz = 2 * iz + r, ip = 2 * ip + k;
    }
    const double n = resolution(), hz = 2 / n, hp = TwoPi / n;
    return {-1 + (iz + u.x()) * hz, (ip + u.y()) * hp, prob / (hz * hp)};
}

double SkyHierarchy::pdfWithoutShare(const Vec3& w) const {
    double avg = mip_[0][0], c[4], prob = 1;
    if (!(avg > 0)) return 0;
    uint32_t iz, ip;
    skyCell(w, levels_, &iz, &ip);
    prefetchPath(iz, ip);
    uint64_t node = 0;
    for (int d = 0; d < levels_; ++d) {
        const int shift = levels_ - 1 - d;
        const int r = (iz >> shift) & 1, k = (ip >> shift) & 1;
        childAverages(d, node, avg, c);
        const detail::Split s(c);
        if (!(s.c[2 * r + k] > 0)) return 0;
        prob *= s.c[2 * r + k] / s.total;
        avg = c[2 * r + k];
        node = 4 * node + 2 * r + k;
    }
    const double n = resolution();
    return prob / ((2 / n) * (TwoPi / n));
}

WarpSample SkyHierarchy::warp(Vec2 u) const {
    const double alpha = defensiveFraction();
    if (alpha == 0) return warpWithoutShare(u);
    WarpSample s;
    if (u.x() < alpha) {
        const Vec3 w = sampleUniformSphere(Vec2(u.x() / alpha, u.y()));
        s.z = w.z(), s.phi = sphericalPhi(w);
    } else {
        // A descent into a node whose children all reconstruct ≤ 0 fails (pdf 0): that lost
        // mass is exactly what pdfWithoutShare() leaves out, so returning no sample keeps it
        // unbiased.
        s = warpWithoutShare(Vec2((u.x() - alpha) / (1 - alpha), u.y()));
        if (s.pdf <= 0) return {};  // (a NaN goes on, for the path tracer to count)
    }
    s.pdf = pdf(s.direction());
    return s;
}

double SkyHierarchy::pdf(const Vec3& w) const {
    const double alpha = defensiveFraction();
    if (alpha == 0) return pdfWithoutShare(w);
    return (1 - alpha) * pdfWithoutShare(w) + alpha * Inv4Pi;
}

void SkyHierarchy::warp(const std::vector<Vec2>& u, std::vector<WarpSample>& out) const {
    out.resize(u.size());
    if (compressed_) {  // the defensive share is decided per point
        for (size_t i = 0; i < u.size(); ++i) out[i] = warp(u[i]);
        return;
    }
    hierarchicalWarpPoints(
        [this](const WarpNode& nd, double c[4]) {
            childAverages(nd.level, mortonIndex(nd.iz, nd.iphi), 0.0, c);
        },
        levels_, u.data(), int(u.size()), out.data());
}

double SkyHierarchy::value(const Vec3& w) const {
    uint32_t iz, ip;
    skyCell(w, levels_, &iz, &ip);
    return average(levels_, iz, ip);
}

SphereSample SkyHierarchy::sample(Vec2 u) const {
    return withValue(warp(u), [this](const Vec3& w) { return value(w); });
}

size_t SkyHierarchy::mipMapBytes() const {
    return sizeof(float) * ((size_t(1) << (2 * levels_)) * 4 - 1) / 3;
}

size_t SkyHierarchy::memoryBytes() const {
    if (!compressed_) return mipMapBytes();
    size_t b = sizeof(float);
    for (size_t d = 0; d < details_.size(); ++d)
        b += detailNodes_[d].size() * (sizeof(uint32_t) + sizeof(std::array<float, 3>));
    return b;
}

}  // namespace shvol
