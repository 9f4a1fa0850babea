#include "shvol/sh/sh_projection.h"

#include <cmath>

namespace shvol::sh {

void gaussLegendre(int k, double a, double b, std::vector<double>& x, std::vector<double>& w) {
    x.assign(k, 0.0);
    w.assign(k, 0.0);
    const double half = 0.5 * (b - a), mid = 0.5 * (a + b);
    for (int i = 0; i < (k + 1) / 2; ++i) {
        // Tricomi's approximation of the i-th largest root, then Newton.
        const double th = Pi * (i + 0.75) / (k + 0.5);
        double t = (1.0 - (k - 1.0) / (8.0 * k * k * k)) * std::cos(th);
        double dp = 0.0;
        for (int it = 0; it < 100; ++it) {
            double p0 = 1.0, p1 = t;
            for (int j = 2; j <= k; ++j) {
                const double p2 = ((2.0 * j - 1.0) * t * p1 - (j - 1.0) * p0) / j;
                p0 = p1;
                p1 = p2;
            }
            if (k == 1) p0 = 1.0, p1 = t;
            dp = k * (t * p1 - p0) / (t * t - 1.0);
            const double dt = p1 / dp;
            t -= dt;
            if (std::fabs(dt) < 1e-16) {
                // one more evaluation of the derivative at the converged root
                p0 = 1.0;
                p1 = t;
                for (int j = 2; j <= k; ++j) {
                    const double p2 = ((2.0 * j - 1.0) * t * p1 - (j - 1.0) * p0) / j;
                    p0 = p1;
                    p1 = p2;
                }
                dp = k * (t * p1 - p0) / (t * t - 1.0);
                break;
            }
        }
        if (k % 2 == 1 && i == k / 2) t = 0.0;
        const double wt = 2.0 / ((1.0 - t * t) * dp * dp);
        x[i] = mid + half * t;  // descending t = cos θ; stored ascending below
        x[k - 1 - i] = mid - half * t;
        w[i] = w[k - 1 - i] = half * wt;
    }
    // ascending order
    for (int i = 0; i < k / 2; ++i) std::swap(x[i], x[k - 1 - i]);
}

SphereQuadrature sphereQuadrature(int nz, int nphi, double z0, double z1) {
    SphereQuadrature q;
    gaussLegendre(nz, z0, z1, q.z, q.wz);
    q.nphi = nphi;
    return q;
}

SphereQuadrature sphereQuadratureForOrder(int n) {
    return sphereQuadrature(n, 2 * n);
}

Eigen::VectorXd zonalToSH(const Eigen::VectorXd& p) {
    const int n = static_cast<int>(p.size());
    Eigen::VectorXd c = Eigen::VectorXd::Zero(n * n);
    for (int l = 0; l < n; ++l) c[shIndex(l, 0)] = p[l];
    return c;
}

Eigen::VectorXd energyFraction(const Eigen::VectorXd& c, double totalEnergy) {
    Eigen::VectorXd e(c.size());
    double s = 0.0;
    for (Eigen::Index i = 0; i < c.size(); ++i) {
        s += c[i] * c[i];
        e[i] = s / totalEnergy;
    }
    return e;
}

}  // namespace shvol::sh
