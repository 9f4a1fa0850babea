// HSH against SH of equal coefficient count for what the radiance cache stores (Gautron et al.
// 2004's claim that the hemispherical basis needs fewer coefficients; §5 and §6.2).
//
// The outgoing radiance of the Phong-22 back wall of the Cornell box (ρ_s = 1, exponent 22) under
// three incoming radiance fields over the hemisphere, computed three ways for a grid of outgoing
// directions: by fine quadrature (the reference), as the dot product of the HSH projections of
// the incoming radiance and of f cos θ_i (what a record and a BRDF table of order n give), and as
// the dot product of their SH projections over the sphere with both extended by zero below the
// horizon (the same n² coefficients). Printed: the RMS relative error of L_o over ω_o per field
// and order. Fields: a smooth sky-like lobe, a hard-edged "window" (a square light seen at 40°
// from the normal, like the Cornell light from the back wall), and their sum.
#include <cstdio>
#include <functional>

#include "shvol/sh/hsh.h"
#include "shvol/sh/sh_basis.h"
#include "shvol/surfaces/bsdf.h"

using namespace shvol;

int main() {
    const Bsdf phong = Bsdf::phong(Spectrum::Zero(), Spectrum::Ones(), 22);
    const Vec3 d = Vec3(0.3, 0.2, 0.9).normalized();
    const Vec3 win = Vec3(0, std::sin(40 * Pi / 180), std::cos(40 * Pi / 180));
    const Frame wf(win);
    std::function<double(const Vec3&)> smooth = [&](const Vec3& w) {
        return std::exp(2 * w.dot(d));
    };
    std::function<double(const Vec3&)> window = [&](const Vec3& w) {
        const Vec3 l = wf.toLocal(w);  // a square of half-width tan 15° around `win`
        return l.z() > 0 && std::abs(l.x() / l.z()) < 0.27 && std::abs(l.y() / l.z()) < 0.27 ? 10.0
                                                                                             : 0.0;
    };
    std::function<double(const Vec3&)> both = [&](const Vec3& w) { return smooth(w) + window(w); };
    const sh::SphereQuadrature hemi = sh::hemisphereQuadrature(120, 240);
    const sh::SphereQuadrature sphere = sh::sphereQuadrature(240, 240);
    auto upper = [](const std::function<double(const Vec3&)>& f) {
        return [f](const Vec3& w) { return w.z() > 0 ? f(w) : 0.0; };
    };
    const char* names[] = {"smooth", "window", "both"};
    const std::function<double(const Vec3&)> fields[] = {smooth, window, both};
    std::vector<Vec3> outgoing;
    for (int a = 0; a < 6; ++a)
        for (int b = 0; b < 12; ++b)
            outgoing.push_back(sphericalDirection(0.1 + 0.9 * (a + 0.5) / 6, TwoPi * b / 12));
    // The reference L_o per field and outgoing direction, by the hemisphere rule.
    std::vector<std::vector<double>> ref(3, std::vector<double>(outgoing.size(), 0.0));
    for (size_t o = 0; o < outgoing.size(); ++o)
        for (int i = 0; i < int(hemi.z.size()); ++i)
            for (int j = 0; j < hemi.nphi; ++j) {
                const Vec3 wi = hemi.direction(i, j);
                const double g = hemi.weight(i) * phong.eval(outgoing[o], wi)[0] * wi.z();
                for (int f = 0; f < 3; ++f) ref[f][o] += g * fields[f](wi);
            }
    std::printf("%-8s %5s %6s %14s %14s %8s\n", "field", "order", "coeffs", "HSH rel. error",
                "SH rel. error", "SH/HSH");
    for (int n : {2, 3, 4, 5, 6, 8, 10}) {
        std::vector<Eigen::VectorXd> lh, ls;
        for (int f = 0; f < 3; ++f) {
            lh.push_back(sh::projectHSH(n, fields[f], hemi));
            ls.push_back(sh::projectSH(n, upper(fields[f]), sphere));
        }
        double eh[3] = {0, 0, 0}, es[3] = {0, 0, 0}, r2[3] = {0, 0, 0};
        for (size_t o = 0; o < outgoing.size(); ++o) {
            const Vec3 wo = outgoing[o];
            auto g = [&](const Vec3& wi) { return phong.eval(wo, wi)[0] * std::max(0.0, wi.z()); };
            const Eigen::VectorXd gh = sh::projectHSH(n, g, hemi);
            const Eigen::VectorXd gs = sh::projectSH(n, upper(g), sphere);
            for (int f = 0; f < 3; ++f) {
                eh[f] += sqr(lh[f].dot(gh) - ref[f][o]);
                es[f] += sqr(ls[f].dot(gs) - ref[f][o]);
                r2[f] += sqr(ref[f][o]);
            }
        }
        for (int f = 0; f < 3; ++f)
            std::printf("%-8s %5d %6d %14.5f %14.5f %8.2f\n", names[f], n, n * n,
                        std::sqrt(eh[f] / r2[f]), std::sqrt(es[f] / r2[f]),
                        std::sqrt(es[f] / eh[f]));
    }
}
