#include "shvol/sampling/sh_sampler.h"

#include <map>
#include <mutex>

#include "shvol/core/error.h"
#include "shvol/sampling/sh_cell_mass.h"
#include "shvol/sh/legendre.h"
#include "shvol/sh/sh_basis.h"
#include "shvol/sh/sh_integrals.h"

namespace shvol {

namespace {

/// The function-independent 1D integral tables at the finest level D (Jarosz §5.1): for each of
/// the 2^D z-intervals the triangular array J_l^m, and for each φ-interval C[m] and S[m].
struct SHIntegralTables {
    int n, cells;
    std::vector<double> J;     // cells × triSize(n)
    std::vector<double> C, S;  // cells × n

    SHIntegralTables(int n_, int depth) : n(n_), cells(1 << depth) {
        J.resize(size_t(cells) * sh::triSize(n));
        C.resize(size_t(cells) * n);
        S.resize(size_t(cells) * n);
        for (int i = 0; i < cells; ++i) {
            const double z0 = -1 + 2.0 * i / cells, z1 = -1 + 2.0 * (i + 1) / cells;
            sh::legendreIntegrals(n, z0, z1, &J[size_t(i) * sh::triSize(n)]);
            const double p0 = TwoPi * i / cells, p1 = TwoPi * (i + 1) / cells;
            sh::phiIntegrals(n, p0, p1, &C[size_t(i) * n], &S[size_t(i) * n]);
        }
    }

    /// Shared per (n, depth): built once, reused by every sampler.
    static std::shared_ptr<const SHIntegralTables> get(int n, int depth) {
        static std::mutex mutex;
        static std::map<std::pair<int, int>, std::shared_ptr<const SHIntegralTables>> cache;
        std::lock_guard<std::mutex> lock(mutex);
        auto& t = cache[{n, depth}];
        if (!t) t = std::make_shared<SHIntegralTables>(n, depth);
        return t;
    }
};

}  // namespace

namespace {
int checkedOrder(int n) {  // before n² coefficients are copied
    if (n < 1 || n > 128) throw Error("SHSampler: order must be in [1, 128]");
    return n;
}
}  // namespace

SHSampler::SHSampler(int n, const double* coeffs, Mode mode, int depth)
    : n_(checkedOrder(n)),
      depth_(depth > 0 ? depth : (mode == Mode::Tables ? 7 : 16)),
      mode_(mode),
      coeffs_(coeffs, coeffs + size_t(n_) * n_) {
    if (mode == Mode::Tables && depth_ > 12) throw Error("SHSampler: table depth must be ≤ 12");
    if (depth_ > 40) throw Error("SHSampler: depth must be ≤ 40");
    if (mode == Mode::Tables) buildTables();
}

void SHSampler::buildTables() {
    const auto t = SHIntegralTables::get(n_, depth_);
    const int cells = t->cells;
    std::vector<double> A(n_), B(n_);
    pyramid_.assign(depth_ + 1, {});
    std::vector<double>& leaves = pyramid_[depth_];
    leaves.resize(size_t(cells) * cells);
    for (int iz = 0; iz < cells; ++iz) {
        weightByCoefficients(n_, coeffs_.data(), &t->J[size_t(iz) * sh::triSize(n_)], A.data(),
                             B.data());
        for (int ip = 0; ip < cells; ++ip) {
            const double m =
                cellMass(n_, A.data(), B.data(), &t->C[size_t(ip) * n_], &t->S[size_t(ip) * n_]);
            leaves[size_t(iz) * cells + ip] = m > 0 ? m : 0.0;
        }
    }
    for (int d = depth_ - 1; d >= 0; --d) {
        const int res = 1 << d;
        const std::vector<double>& fine = pyramid_[d + 1];
        std::vector<double>& coarse = pyramid_[d];
        coarse.resize(size_t(res) * res);
        for (int iz = 0; iz < res; ++iz)
            for (int ip = 0; ip < res; ++ip) {
                const size_t a = size_t(2 * iz) * (2 * res) + 2 * ip, b = a + 2 * res;
                coarse[size_t(iz) * res + ip] = fine[a] + fine[a + 1] + fine[b] + fine[b + 1];
            }
    }
    // Split probabilities of every internal node, and the leaves' pdf.
    auto split = [](double a, double b) {
        const double p = a + b > 0 ? a / (a + b) : 0.0;
        return Split{{0.0, p}, {p > 0 ? 1 / p : 0.0, p < 1 ? 1 / (1 - p) : 0.0}};
    };
    levelOffset_.assign(depth_ + 1, 0);
    for (int d = 0; d < depth_; ++d) levelOffset_[d + 1] = levelOffset_[d] + (size_t(1) << (2 * d));
    splits_.resize(levelOffset_[depth_]);
    double c[4];
    for (int d = 0; d < depth_; ++d) {
        const int res = 1 << d;
        for (int iz = 0; iz < res; ++iz)
            for (int ip = 0; ip < res; ++ip) {
                childMassesFromTables(WarpNode{d, iz, ip}, c);
                NodeSplits& ns = splits_[levelOffset_[d] + size_t(iz) * res + ip];
                ns.row = split(c[0] + c[1], c[2] + c[3]);
                ns.col[0] = split(c[0], c[1]);
                ns.col[1] = split(c[2], c[3]);
            }
    }
    const double root = pyramid_[0][0];
    const double leafArea = (2.0 / cells) * (TwoPi / cells);
    leafPdf_.resize(leaves.size());
    for (size_t i = 0; i < leaves.size(); ++i)
        leafPdf_[i] = root > 0 ? leaves[i] / root / leafArea : 0;
}

WarpSample SHSampler::warpTables(Vec2 u) const {
    constexpr double OneMinus = 1.0 - 0x1.0p-53;
    if (!(pyramid_[0][0] > 0)) return {};
    int iz = 0, ip = 0;
    double x = u.x(), y = u.y();
    for (int d = 0; d < depth_; ++d) {
        const NodeSplits& ns = splits_[levelOffset_[d] + (size_t(iz) << d) + ip];
        const int r = x >= ns.row.p();
        x = std::min((x - ns.row.lo[r]) * ns.row.inv[r], OneMinus);
        const Split& cs = ns.col[r];
        const int k = y >= cs.p();
        y = std::min((y - cs.lo[k]) * cs.inv[k], OneMinus);
        iz = 2 * iz + r, ip = 2 * ip + k;
    }
    const int cells = 1 << depth_;
    const double dz = 2.0 / cells, dphi = TwoPi / cells;
    return {-1 + (iz + x) * dz, (ip + y) * dphi, leafPdf_[(size_t(iz) << depth_) + ip]};
}

void SHSampler::warpTablesBlock(const Vec2* u, int count, WarpSample* out) const {
    constexpr int Block = 16;
    constexpr double OneMinus = 1.0 - 0x1.0p-53;
    if (!(pyramid_[0][0] > 0)) {
        for (int j = 0; j < count; ++j) out[j] = {};
        return;
    }
    double x[Block], y[Block];
    size_t iz[Block], ip[Block];
    for (int j = 0; j < count; ++j) x[j] = u[j].x(), y[j] = u[j].y(), iz[j] = ip[j] = 0;
    for (int d = 0; d < depth_; ++d) {
        const NodeSplits* level = &splits_[levelOffset_[d]];
        for (int j = 0; j < count; ++j) {
            const NodeSplits& ns = level[(iz[j] << d) + ip[j]];
            const int r = x[j] >= ns.row.p();
            x[j] = std::min((x[j] - ns.row.lo[r]) * ns.row.inv[r], OneMinus);
            const Split& cs = ns.col[r];
            const int k = y[j] >= cs.p();
            y[j] = std::min((y[j] - cs.lo[k]) * cs.inv[k], OneMinus);
            iz[j] = 2 * iz[j] + r, ip[j] = 2 * ip[j] + k;
        }
    }
    const int cells = 1 << depth_;
    const double dz = 2.0 / cells, dphi = TwoPi / cells;
    for (int j = 0; j < count; ++j)
        out[j] = {-1 + (iz[j] + x[j]) * dz, (ip[j] + y[j]) * dphi,
                  leafPdf_[(iz[j] << depth_) + ip[j]]};
}

void SHSampler::childMassesFromTables(const WarpNode& node, double c[4]) const {
    const std::vector<double>& fine = pyramid_[node.level + 1];
    const int res = 2 << node.level;
    const size_t a = size_t(2 * node.iz) * res + 2 * node.iphi, b = a + res;
    c[0] = fine[a], c[1] = fine[a + 1], c[2] = fine[b], c[3] = fine[b + 1];
}

void SHSampler::childMassesOnTheFly(const WarpNode& node, double c[4]) const {
    constexpr int MaxN = 128;
    double J[sh::triSize(MaxN)], C[2][MaxN], S[2][MaxN], A[MaxN], B[MaxN];
    sh::phiIntegrals(n_, node.phi0, node.phiMid(), C[0], S[0]);
    sh::phiIntegrals(n_, node.phiMid(), node.phi1, C[1], S[1]);
    for (int r = 0; r < 2; ++r) {
        sh::legendreIntegrals(n_, r ? node.zMid() : node.z0, r ? node.z1 : node.zMid(), J);
        weightByCoefficients(n_, coeffs_.data(), J, A, B);
        for (int k = 0; k < 2; ++k) c[2 * r + k] = cellMass(n_, A, B, C[k], S[k]);
    }
}

WarpSample SHSampler::warp(const Vec2& u) const {
    if (mode_ == Mode::Tables) return warpTables(u);
    return hierarchicalWarp([this](const WarpNode& nd, double* c) { childMassesOnTheFly(nd, c); },
                            depth_, u);
}

void SHSampler::warp(const std::vector<Vec2>& u, std::vector<WarpSample>& out) const {
    out.resize(u.size());
    if (mode_ == Mode::Tables) {
        // The split probabilities are stored, so nothing is left to share between points: the
        // map is applied pointwise (which is what preserves the set's stratification).
        for (size_t i = 0; i < u.size(); i += 16)
            warpTablesBlock(&u[i], int(std::min<size_t>(16, u.size() - i)), &out[i]);
    } else {
        hierarchicalWarpPoints(
            [this](const WarpNode& nd, double* c) { childMassesOnTheFly(nd, c); }, depth_, u.data(),
            int(u.size()), out.data());
    }
}

SphereSample SHSampler::sample(const Vec2& u) const {
    const WarpSample s = warp(u);
    if (!(s.pdf > 0)) return {};
    const Vec3 w = s.direction();
    return {w, eval(w), s.pdf};
}

double SHSampler::pdf(const Vec3& w) const {
    const double z = std::clamp(w.z(), -1.0, 1.0), phi = sphericalPhi(w);
    if (mode_ == Mode::Tables) {
        const int cells = 1 << depth_;
        const int iz = std::min(cells - 1, int((z + 1) * 0.5 * cells));
        const int ip = std::min(cells - 1, int(phi * Inv2Pi * cells));
        // The warp's product of split probabilities telescopes to leaf/root (to rounding).
        return leafPdf_[size_t(iz) * cells + ip];
    }
    return hierarchicalPdf([this](const WarpNode& nd, double* c) { childMassesOnTheFly(nd, c); },
                           depth_, z, phi);
}

double SHSampler::probability(double z0, double z1, double phi0, double phi1) const {
    if (mode_ == Mode::Tables)
        return hierarchicalProbability(
            [this](const WarpNode& nd, double* c) { childMassesFromTables(nd, c); }, depth_, z0, z1,
            phi0, phi1);
    return hierarchicalProbability(
        [this](const WarpNode& nd, double* c) { childMassesOnTheFly(nd, c); }, depth_, z0, z1, phi0,
        phi1);
}

double SHSampler::eval(const Vec3& w) const {
    return sh::shReconstruct(n_, coeffs_.data(), w);
}

double SHSampler::positiveMass() const {
    if (mode_ == Mode::Tables) return pyramid_[0][0];
    double c[4];
    childMassesOnTheFly(WarpNode{}, c);
    return std::max(0.0, c[0]) + std::max(0.0, c[1]) + std::max(0.0, c[2]) + std::max(0.0, c[3]);
}

}  // namespace shvol
