#include "shvol/cache/hsh_brdf_table.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "shvol/core/error.h"
#include "shvol/sh/hsh.h"

namespace shvol {

Vec2 parabolicFromDirection(const Vec3& w) {
    return Vec2(w.x(), w.y()) / (1 + std::max(0.0, w.z()));
}

Vec3 directionFromParabolic(const Vec2& uv) {
    Vec2 p = uv;
    const double r2 = p.squaredNorm();
    if (r2 > 1) p /= std::sqrt(r2);  // nodes outside the disk: at its rim (the horizon)
    const double q = p.squaredNorm();
    return Vec3(2 * p.x(), 2 * p.y(), 1 - q) / (1 + q);
}

namespace {

/// The rule's nodes with what every lobe's projection needs of them: the basis H_i at each
/// node (a row per node) and the node's direction and weight. Evaluated once per table rather
/// than once per outgoing direction.
struct BasisAtNodes {
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> H;
    std::vector<Vec3> w;
    Eigen::VectorXd weight;
    BasisAtNodes(int n, const sh::SphereQuadrature& q)
        : H(q.size(), n * n), w(q.size()), weight(q.size()) {
        for (int i = 0, k = 0; i < int(q.z.size()); ++i)
            for (int j = 0; j < q.nphi; ++j, ++k) {
                w[k] = q.direction(i, j);
                weight[k] = q.weight(i);
                sh::hshEval(n, w[k], H.row(k).data());
            }
    }
};

/// What the order-n projection P g of g(ω_i) = f(ω_o, ω_i) cos θ_i misses: the fraction of ∫g²
/// (energy) and the largest |g − P g| at the rule's nodes over the largest g (peak).
struct ProjectionErrors {
    double energy = 0, peak = 0;
};

/// The coefficients c of g = f(ω_o, ·) cos θ_i (c = Σ_nodes weight·g·H) and what they miss (the
/// peak only if asked: its residual at every node cost a fifth of a Cornell render with the
/// cache, for the directions whose peak is not judged; helper 169).
ProjectionErrors project(const Bsdf& shape, const Vec3& wo, const BasisAtNodes& b, double* c,
                         bool peak = true) {
    Eigen::VectorXd g(b.w.size());
    for (size_t k = 0; k < b.w.size(); ++k) g[k] = shape.eval(wo, b.w[k])[0] * b.w[k].z();
    Eigen::Map<Eigen::VectorXd> coefficients(c, b.H.cols());
    coefficients.noalias() = b.H.transpose() * b.weight.cwiseProduct(g);
    const double g2 = b.weight.dot(g.cwiseAbs2()), gMax = g.maxCoeff();
    if (!(g2 > 0) || !(gMax > 0)) return {};
    const double energy = std::max(0.0, 1 - coefficients.squaredNorm() / g2);
    if (!peak) return {energy, 0};
    const Eigen::VectorXd residual = g - b.H * coefficients;
    return {energy, residual.cwiseAbs().maxCoeff() / gMax};
}

/// The directional albedo ∫ f(ω_o, ω_i) cos θ_i dω_i of the (single-channel) `shape`, by
/// importance sampling its own lobe on a fixed 16 × 16 stratified grid: unlike the quadrature,
/// it finds a lobe of any width.
double sampledAlbedo(const Bsdf& shape, const Vec3& wo) {
    constexpr int k = 16;
    double sum = 0;
    for (int i = 0; i < k; ++i)
        for (int j = 0; j < k; ++j)
            if (const auto s = shape.sample(wo, Vec2((i + 0.5) / k, (j + 0.5) / k));
                s && s->pdf > 0 && s->wi.z() > 0)
                sum += s->f[0] * s->wi.z() / s->pdf;
    return sum / (k * k);
}

/// The relative error of the albedo the coefficients c give, under uniform radiance 1
/// (λ = ∫ H, of which only λ_0 = 2π H_0 is not 0), against the lobe's own (sampledAlbedo).
double tableAlbedoError(const Bsdf& shape, const Vec3& wo, double H0, const double* c) {
    const double table = TwoPi * H0 * c[0], sampled = sampledAlbedo(shape, wo);
    return sampled > 0 ? std::abs(table - sampled) / sampled : table > 0 ? 1.0 : 0.0;
}

/// A specular lobe of weight 0 reflects nothing: such a BSDF's table is its diffuse part's.
bool hasSpecularLobe(const Bsdf& b) {
    return b.type != BsdfType::Lambert && b.specular.maxCoeff() > 0;
}
}  // namespace

bool HshBrdfTable::sameLobes(const Bsdf& a, const Bsdf& b) {
    if (!supports(a) || !supports(b) || hasSpecularLobe(a) != hasSpecularLobe(b)) return false;
    if (!hasSpecularLobe(a)) return true;  // (the diffuse projection is every type's)
    return a.type == b.type &&
           (a.type == BsdfType::Phong ? a.exponent == b.exponent
                                      : a.alphaX == b.alphaX && a.alphaY == b.alphaY);
}

HshBrdfTable::HshBrdfTable(const HshBrdfTable& sameLobe, const Bsdf& bsdf)
    : HshBrdfTable(sameLobe) {
    if (!sameLobes(lobes_, bsdf))
        throw Error(std::string("HSH BRDF table: the table of a ") + lobes_.name() +
                    " BSDF of other lobes cannot serve a " + bsdf.name() + " BSDF");
    lobes_ = bsdf;
}

HshBrdfTable::HshBrdfTable(const Bsdf& bsdf, int order, int resolution)
    : n_(order), res_(resolution), diffuse_(order * order, 0.0) {
    if (!supports(bsdf))
        throw Error(std::string("HSH BRDF table: a ") + bsdf.name() +
                    " BSDF is not cached (lambert, phong and ward are)");
    lobes_ = bsdf;
    // A specular lobe of weight 0 reflects nothing: it is neither tabulated nor judged (a sharp
    // one would fail the albedo check and leave a Lambertian surface path traced).
    const bool diffuseOnly = !hasSpecularLobe(bsdf);
    // At least 64 × 128 nodes: tests/cache checks Phong 22 and Ward α = 0.2/0.4 against a rule
    // of 400 × 800 to 2e-4 (HshBrdfTable.ReflectsBandLimitedRadianceExactlyAtANode).
    const BasisAtNodes nodes(n_,
                             sh::hemisphereQuadrature(std::max(64, 2 * n_), std::max(128, 4 * n_)));
    const Vec3 up(0, 0, 1);
    const ProjectionErrors errD =
        project(Bsdf::lambert(Spectrum::Ones()), up, nodes, diffuse_.data());
    if (diffuseOnly) {
        projectionError_ = errD.energy;
        peakError_ = errD.peak;
        return;
    }
    Bsdf shape = bsdf;
    shape.reflectance = Spectrum::Zero();
    shape.specular = Spectrum::Ones();
    auto specular = std::make_shared<std::vector<double>>(size_t(res_) * res_ * n_ * n_, 0.0);
    std::vector<double> err(size_t(res_) * res_), peakErr(err.size()), albedoErr(err.size());
    tbb::parallel_for(0, res_ * res_, [&](int k) {  // nodes are independent: any thread count
        const int x = k % res_, y = k / res_;
        const Vec2 uv(-1 + 2.0 * x / (res_ - 1), -1 + 2.0 * y / (res_ - 1));
        Vec3 wo = directionFromParabolic(uv);
        wo.z() = std::max(wo.z(), 1e-4);  // the rim: just above the horizon
        wo.normalize();
        const bool judged = wo.z() >= kAlbedoCheckCos;
        const ProjectionErrors e =
            project(shape, wo, nodes, &(*specular)[size_t(k) * n_ * n_], judged);
        err[k] = e.energy;
        if (judged) {
            peakErr[k] = e.peak;
            albedoErr[k] = tableAlbedoError(shape, wo, nodes.H(0, 0),  // (H_0 is constant)
                                            &(*specular)[size_t(k) * n_ * n_]);
        }
    });
    for (double e : err) projectionError_ += e / err.size();
    peakError_ = *std::max_element(peakErr.begin(), peakErr.end());
    albedoError_ = *std::max_element(albedoErr.begin(), albedoErr.end());
    specular_ = std::move(specular);
}

void HshBrdfTable::coefficients(const Vec3& wo, double* out) const {
    const int nn = n_ * n_;
    for (int k = 0; k < 3; ++k)
        for (int i = 0; i < nn; ++i) out[k * nn + i] = lobes_.reflectance[k] * diffuse_[i];
    if (!specular_) return;
    const std::vector<double>& specular = *specular_;
    const Vec2 uv = parabolicFromDirection(wo);
    const double fx = std::clamp((uv.x() + 1) * 0.5 * (res_ - 1), 0.0, res_ - 1.0);
    const double fy = std::clamp((uv.y() + 1) * 0.5 * (res_ - 1), 0.0, res_ - 1.0);
    const int x0 = std::min(int(fx), res_ - 2), y0 = std::min(int(fy), res_ - 2);
    const double tx = fx - x0, ty = fy - y0;
    const double w[4] = {(1 - tx) * (1 - ty), tx * (1 - ty), (1 - tx) * ty, tx * ty};
    const double* c[4] = {&specular[(size_t(y0) * res_ + x0) * nn],
                          &specular[(size_t(y0) * res_ + x0 + 1) * nn],
                          &specular[(size_t(y0 + 1) * res_ + x0) * nn],
                          &specular[(size_t(y0 + 1) * res_ + x0 + 1) * nn]};
    for (int i = 0; i < nn; ++i) {
        const double s = w[0] * c[0][i] + w[1] * c[1][i] + w[2] * c[2][i] + w[3] * c[3][i];
        for (int k = 0; k < 3; ++k) out[k * nn + i] += lobes_.specular[k] * s;
    }
}

void HshBrdfTable::coefficients(const Frame& base, const Frame& own, const Vec3& wo,
                                double* out) const {
    // (a diffuse table needs no turning)
    if (!specular_ || !lobes_.anisotropic()) return coefficients(base.toLocal(wo), out);
    coefficients(own.toLocal(wo), out);
    const double phi = std::atan2(own.s.dot(base.t), own.s.dot(base.s));
    for (int k = 0; k < 3; ++k) sh::hshRotateZ(n_, phi, out + k * n_ * n_);
}

size_t HshBrdfTable::memoryBytes() const {
    return (diffuse_.size() + (specular_ ? specular_->size() : 0)) * sizeof(double);
}

}  // namespace shvol
