#pragma once
/// \file Projection onto real SH by quadrature, zonal projection, reconstruction, energy fraction.
///
/// The quadrature is Gauss–Legendre in z = cos θ × uniform in φ. A product y_l^m y_l'^m' is a
/// polynomial of degree l+l' in z (times cos/sin of (m±m')φ), so nz Gauss points are exact for
/// l+l' ≤ 2nz−1 and nφ uniform points for |m|+|m'| < nφ: projecting a function of order nf onto
/// order n is exact with nz ≥ (nf+n)/2 and nφ ≥ nf+n−1 (Jarosz 2009 eq. 2 computed exactly).
#include <Eigen/Core>
#include <vector>

#include "shvol/core/math.h"
#include "shvol/sh/sh_basis.h"

namespace shvol::sh {

/// k Gauss–Legendre nodes and weights on [a, b] (Newton on P_k from Tricomi's initial guesses;
/// nodes and weights accurate to a few ulp for k up to several thousand).
void gaussLegendre(int k, double a, double b, std::vector<double>& x, std::vector<double>& w);

/// Product rule on a (z, φ) cylinder: nodes (z_i, φ_j = φ0 + (j+½)Δφ), weights wz_i · Δφ.
struct SphereQuadrature {
    std::vector<double> z, wz;
    int nphi = 1;
    double phi0 = 0.0, phi1 = TwoPi;
    int size() const { return static_cast<int>(z.size()) * nphi; }
    double phi(int j) const { return phi0 + (j + 0.5) * (phi1 - phi0) / nphi; }
    double weight(int i) const { return wz[i] * (phi1 - phi0) / nphi; }
    Vec3 direction(int i, int j) const { return sphericalDirection(z[i], phi(j)); }
};
/// nz Gauss–Legendre points in z ∈ [z0, z1] × nphi uniform points in φ ∈ [0, 2π).
SphereQuadrature sphereQuadrature(int nz, int nphi, double z0 = -1.0, double z1 = 1.0);
/// The rule that integrates every product y_i y_j of order n exactly (nz = n, nφ = 2n).
SphereQuadrature sphereQuadratureForOrder(int n);

/// f_i = ∫ f y_i dω by the quadrature q (exact for band-limited f as in the file comment).
/// F: double(const Vec3&).
template <class F>
Eigen::VectorXd projectSH(int n, F&& f, const SphereQuadrature& q) {
    Eigen::VectorXd c = Eigen::VectorXd::Zero(n * n);
    Eigen::VectorXd y(n * n);
    for (size_t i = 0; i < q.z.size(); ++i)
        for (int j = 0; j < q.nphi; ++j) {
            const Vec3 w = q.direction(static_cast<int>(i), j);
            shEval(n, w, y.data());
            c += (q.weight(static_cast<int>(i)) * f(w)) * y;
        }
    return c;
}

/// Zonal projection of a function g(μ) of μ = cos θ: p_l = 2π ∫_{−1}^{1} g(μ) y_l^0(μ) dμ,
/// l < n, so that g ≈ Σ p_l y_l^0 (DESIGN.md phase-function convention). nz Gauss points (exact
/// for polynomial g of degree ≤ 2nz − n). G: double(double).
template <class G>
Eigen::VectorXd projectZonal(int n, G&& g, int nz) {
    std::vector<double> x, w;
    gaussLegendre(nz, -1.0, 1.0, x, w);
    Eigen::VectorXd p = Eigen::VectorXd::Zero(n);
    Eigen::VectorXd y(n);
    for (int i = 0; i < nz; ++i) {
        shEvalZonal(n, x[i], y.data());
        p += (TwoPi * w[i] * g(x[i])) * y;
    }
    return p;
}

/// Expands zonal coefficients p_l (l < n) into the n² SH vector (m = 0 entries).
Eigen::VectorXd zonalToSH(const Eigen::VectorXd& p);

/// ∫ f(ω)² dω over the quadrature's domain (the denominator of Gautron 2004 eq. 15).
template <class F>
double squaredNorm(F&& f, const SphereQuadrature& q) {
    double s = 0.0;
    for (size_t i = 0; i < q.z.size(); ++i)
        for (int j = 0; j < q.nphi; ++j) {
            const double v = f(q.direction(static_cast<int>(i), j));
            s += q.weight(static_cast<int>(i)) * v * v;
        }
    return s;
}

/// Gautron 2004 eq. 15: fraction of the energy captured with k coefficients, for k = 1 … c.size()
/// (entry k−1 = Σ_{i<k} c_i² / totalEnergy). Per band: take entries (n²−1).
Eigen::VectorXd energyFraction(const Eigen::VectorXd& c, double totalEnergy);

}  // namespace shvol::sh
