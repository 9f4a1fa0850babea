#include "shvol/phase/zonal_fit.h"

#include <algorithm>
#include <cmath>

#include "shvol/core/error.h"
#include "shvol/core/math.h"
#include "shvol/sh/sh_basis.h"
#include "shvol/sh/sh_projection.h"

namespace shvol {

SHWindow shWindowFromName(const std::string& name) {
    if (name == "none") return SHWindow::None;
    if (name == "hann") return SHWindow::Hann;
    if (name == "lanczos") return SHWindow::Lanczos;
    throw Error("unknown SH window \"" + name + "\"; expected none, hann or lanczos");
}

const char* shWindowName(SHWindow w) {
    switch (w) {
        case SHWindow::Hann:
            return "hann";
        case SHWindow::Lanczos:
            return "lanczos";
        default:
            return "none";
    }
}

namespace {

struct Node {
    AngleCosine angle;  ///< the node's angle θ (its cosine and their complements)
    double weight;      ///< ∫ g(μ) dμ ≈ Σ weight · g(angle.mu)
};

/// Gauss–Legendre panels on gradedThetaEdges(), no wider than 8/(order+1) rad: the integrand
/// y_l^0(cos θ) p(cos θ) sin θ oscillates about l/(2π) times per radian, and 16 points per panel
/// resolve ~1.3 oscillations exactly enough (wider panels aliased: ⟨y_l, y_l⟩ came out 0.905 at
/// l = 96 before this cap). A panel that p's corners (a table's nodes) cut is integrated piece by
/// piece, each piece with at least its share of the 16 points, and at least the points that its
/// phase φ = width · (order + 1) asks of an integrand as smooth as a table's between its nodes
/// (linear in μ, times y_l sin θ): n with (φ/4)^{2n}/(2n)! ≤ 10⁻¹³, Gauss–Legendre's error on a
/// function of that frequency. A table of many rows then costs 2 or 3 nodes a row, not 16 (a fit
/// of 180,001 rows took 13 s with 16; helper 115).
constexpr int kPoints = 16;

/// The corners inside (0, π), ascending, without repeats (the poles are edges already).
std::vector<double> cornersInside(const std::vector<double>& corners) {
    std::vector<double> inside;
    for (double c : corners)
        if (c > 0 && c < Pi) inside.push_back(c);
    std::sort(inside.begin(), inside.end());
    inside.erase(std::unique(inside.begin(), inside.end()), inside.end());
    return inside;
}

/// The Gauss–Legendre points, 2 … kPoints, for a piece of phase φ (see thetaNodes).
int pointsForPhase(double phi) {
    double term = (phi / 4) * (phi / 4), bound = term * term / 24;  // n = 2: (φ/4)⁴/4!
    int n = 2;
    for (; n < kPoints && bound > 1e-13; ++n) bound *= term / ((2.0 * n + 1) * (2.0 * n + 2));
    return n;
}

std::vector<Node> thetaNodes(int order, const std::vector<double>& corners) {
    const std::vector<double> edges = gradedThetaEdges();
    const double maxWidth = 8.0 / (order + 1);
    const std::vector<double> cut = cornersInside(corners);
    std::vector<double> unitX[kPoints + 1], unitW[kPoints + 1];  // rules on [0, 1] by size
    std::vector<Node> out;
    const auto piece = [&](double a, double b, int n) {
        if (unitX[n].empty()) sh::gaussLegendre(n, 0.0, 1.0, unitX[n], unitW[n]);
        for (int j = 0; j < n; ++j) {
            const double t = a + (b - a) * unitX[n][j];
            out.push_back({AngleCosine::ofAngle(t), (b - a) * unitW[n][j] * std::sin(t)});
        }
    };
    auto next = cut.begin();
    for (size_t i = 0; i + 1 < edges.size(); ++i) {
        const int pieces = std::max(1, int(std::ceil((edges[i + 1] - edges[i]) / maxWidth)));
        for (int k = 0; k < pieces; ++k) {
            const double a = edges[i] + (edges[i + 1] - edges[i]) * k / pieces;
            const double b = edges[i] + (edges[i + 1] - edges[i]) * (k + 1) / pieces;
            while (next != cut.end() && *next <= a) ++next;
            if (next == cut.end() || *next >= b) {
                piece(a, b, kPoints);
                continue;
            }
            for (double from = a; from < b;) {
                const double to = next != cut.end() && *next < b ? *next++ : b;
                const int n = std::max(int(std::ceil(kPoints * (to - from) / (b - a))),
                                       pointsForPhase((to - from) * (order + 1)));
                if (to > from) piece(from, to, n);
                from = to;
            }
        }
    }
    return out;
}

double windowWeight(SHWindow w, int l, int n) {
    const double x = double(l) / n;
    switch (w) {
        case SHWindow::Hann:
            return 0.5 * (1 + std::cos(Pi * x));
        case SHWindow::Lanczos:
            return l == 0 ? 1.0 : std::sin(Pi * x) / (Pi * x);
        default:
            return 1.0;
    }
}

}  // namespace

std::vector<double> gradedThetaEdges(const std::vector<double>& corners) {
    std::vector<double> edges{0.0};
    for (double t = 1e-7; t < 0.5 * Pi / 1.25; t *= 1.25) edges.push_back(t);
    const size_t half = edges.size();
    edges.push_back(0.5 * Pi);
    for (size_t i = half; i-- > 1;) edges.push_back(Pi - edges[i]);
    edges.push_back(Pi);
    for (double c : cornersInside(corners)) edges.push_back(c);
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    return edges;
}

ZonalFit fitZonal(const std::function<double(const AngleCosine&)>& p, int order, SHWindow window,
                  const std::vector<double>& corners) {
    if (order < 1 || order > 1024) throw Error("SH order must be in [1, 1024]");
    const std::vector<Node> nodes = thetaNodes(order, corners);
    std::vector<double> value(nodes.size()), y(order);
    ZonalFit fit;
    fit.window = window;
    fit.p.assign(order, 0.0);
    double energy = 0;
    for (size_t i = 0; i < nodes.size(); ++i) {
        value[i] = p(nodes[i].angle);
        sh::shEvalZonal(order, nodes[i].angle.mu, y.data());
        for (int l = 0; l < order; ++l) fit.p[l] += TwoPi * nodes[i].weight * value[i] * y[l];
        energy += TwoPi * nodes[i].weight * value[i] * value[i];
        fit.peakValue = std::max(fit.peakValue, value[i]);
    }
    double captured = 0;
    for (int l = 0; l < order; ++l) captured += fit.p[l] * fit.p[l];
    fit.energy = energy;
    fit.energyFraction = energy > 0 ? captured / energy : 1.0;
    for (int l = 0; l < order; ++l) fit.p[l] *= windowWeight(window, l, order);

    const auto fitted = [&](double mu) {  // p̃(μ)
        sh::shEvalZonal(order, mu, y.data());
        double r = 0;
        for (int l = order - 1; l >= 0; --l) r += fit.p[l] * y[l];
        return r;
    };
    double err2 = 0;
    fit.minValue = INFINITY;
    for (size_t i = 0; i < nodes.size(); ++i) {
        const double r = fitted(nodes[i].angle.mu);
        const double e = value[i] - r;
        err2 += TwoPi * nodes[i].weight * e * e;
        fit.maxError = std::max(fit.maxError, std::abs(e));
        fit.minValue = std::min(fit.minValue, r);
    }
    // The peak, the largest error and the least value also at the poles and at the corners (a
    // table's nodes, where its peak is: a ring 0.1° wide at 60° had its peak and largest error
    // read 11% low from the quadrature nodes beside it; helper 142).
    std::vector<double> extra = cornersInside(corners);
    extra.insert(extra.end(), {0.0, Pi});
    for (const double theta : extra) {
        const AngleCosine c = AngleCosine::ofAngle(theta);
        const double v = p(c), r = fitted(c.mu);
        fit.peakValue = std::max(fit.peakValue, v);
        fit.maxError = std::max(fit.maxError, std::abs(v - r));
        fit.minValue = std::min(fit.minValue, r);
    }
    fit.l2Error = std::sqrt(err2);
    fit.relativeL2Error = energy > 0 ? fit.l2Error / std::sqrt(energy) : 0.0;
    return fit;
}

ZonalFit fitZonal(const std::function<double(double mu)>& p, int order, SHWindow window) {
    return fitZonal([&](const AngleCosine& c) { return p(c.mu); }, order, window);
}

double relativeL2ErrorByParseval(const std::vector<double>& pFull, double energy, int n,
                                 SHWindow w) {
    // ∫p² − Σ_{l<n} p_l² as the energy beyond the computed orders plus the tail Σ_{n≤l<L} p_l²:
    // subtracted in one go it cancels to noise of about L·2⁻⁵³·∫p² (a relative error floor near
    // 10⁻⁸, below which no tolerance could be met: isotropic went to order 256). The energy
    // beyond L is itself only known to that noise, and counts as 0 within it.
    double beyond = energy;
    for (double p : pFull) beyond -= p * p;
    if (std::abs(beyond) <= double(pFull.size() + 1) * 0x1p-52 * energy) beyond = 0;
    double err2 = std::max(0.0, beyond);
    for (size_t l = 0; l < pFull.size(); ++l) {
        const double d = int(l) < n ? 1 - windowWeight(w, int(l), n) : 1;
        err2 += d * d * pFull[l] * pFull[l];
    }
    return energy > 0 ? std::sqrt(err2 / energy) : 0.0;
}

namespace {

constexpr double kRingingThreshold = 1e-3;

/// Ringing that matters: the fit dips below −10⁻³ of the function's peak. Shallower dips are
/// clamped by the samplers at a cost below the fit's own error, while Hann would blur the lobe
/// (HG 0.9 to 1% error: order 55 without a window, 240 with Hann).
bool rings(const ZonalFit& f) {
    return f.minValue < -kRingingThreshold * f.peakValue;
}

/// The lowest order n in (from, to] whose unwindowed truncation of `full` (the unwindowed fit at
/// the highest order: the coefficients of every lower order are its first ones) does not ring on
/// the nodes of `full`'s order, or 0. One pass over the nodes, adding a band at a time: refitting
/// every order took a 1801-row table from 0.25 to 2.9 s (helper 131).
int lowestOrderNotRinging(const ZonalFit& full, const std::vector<double>& corners, int from,
                          int to) {
    if (to <= from) return 0;
    const int top = int(full.p.size());
    std::vector<double> least(size_t(top) + 1, INFINITY);
    std::vector<double> y(static_cast<size_t>(top));
    for (const Node& node : thetaNodes(top, corners)) {
        sh::shEvalZonal(top, node.angle.mu, y.data());
        double r = 0;
        for (int l = 0; l < to; ++l) {
            r += full.p[size_t(l)] * y[size_t(l)];
            least[size_t(l) + 1] = std::min(least[size_t(l) + 1], r);
        }
    }
    for (int n = from + 1; n <= to; ++n)
        if (!(least[size_t(n)] < -kRingingThreshold * full.peakValue)) return n;
    return 0;
}

/// The lowest order meeting the tolerance with window w, or 0 if none up to pFull.size() does.
int lowestOrder(const std::vector<double>& pFull, double energy, double tol, SHWindow w) {
    for (int n = 1; n <= int(pFull.size()); ++n)
        if (relativeL2ErrorByParseval(pFull, energy, n, w) <= tol) return n;
    return 0;
}

}  // namespace

ZonalFit fitZonal(const std::function<double(const AngleCosine&)>& p,
                  const ZonalFitRequest& request, const std::vector<double>& corners) {
    const auto fit = [&](int n, SHWindow w) { return fitZonal(p, n, w, corners); };
    int order = request.order;
    if (order == 0) {
        const int maxOrder = ZonalFitRequest::kMaxAutoOrder;
        const ZonalFit full = fit(maxOrder, SHWindow::None);
        const SHWindow first = request.window.value_or(SHWindow::None);
        order = lowestOrder(full.p, full.energy, request.tolerance, first);
        if (order == 0) return fit(maxOrder, first);  // the best it can do
        const ZonalFit f = fit(order, first);
        if (request.window || !rings(f)) return f;
        // Unwindowed it rings: the lower of a higher unwindowed order that does not ring (the
        // error only falls with the order) and the lowest Hann order that meets the tolerance,
        // else f (the samplers clamp what rings). Hann alone gave HG 0.9 order 105 at a
        // tolerance of 0.05 and order 49 unwindowed at 0.02, which meets 0.05 too without
        // ringing (helper 130).
        const int hannOrder = lowestOrder(full.p, full.energy, request.tolerance, SHWindow::Hann);
        // (Candidates by the nodes of the highest order, each confirmed on its own.)
        for (int n = order, last = hannOrder > 0 ? hannOrder - 1 : maxOrder;
             (n = lowestOrderNotRinging(full, corners, n, last)) > 0;)
            if (ZonalFit g = fit(n, SHWindow::None); !rings(g)) return g;
        return hannOrder > 0 ? fit(hannOrder, SHWindow::Hann) : f;
    }
    if (request.window) return fit(order, *request.window);
    const ZonalFit f = fit(order, SHWindow::None);
    return rings(f) ? fit(order, SHWindow::Hann) : f;
}

ZonalFit fitZonal(const std::function<double(double mu)>& p, const ZonalFitRequest& request) {
    return fitZonal([&](const AngleCosine& c) { return p(c.mu); }, request);
}

}  // namespace shvol
