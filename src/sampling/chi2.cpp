#include "shvol/sampling/chi2.h"

#include <algorithm>
#include <boost/math/special_functions/gamma.hpp>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <sstream>
#include <vector>

namespace shvol {

namespace {

constexpr int kPieces = 8;     // initial sub-intervals per cell side
constexpr int kMaxDepth = 16;  // further bisections per sub-interval
constexpr double kRelTol = 1e-7;

// Adaptive Simpson (Lyness 1969) on [a, b] given f at a, m, b and the Simpson value `whole`.
template <typename F>
double simpsonRec(F& f, double a, double b, double fa, double fm, double fb, double whole,
                  double tol, int depth) {
    const double m = 0.5 * (a + b), lm = 0.5 * (a + m), rm = 0.5 * (m + b);
    const double flm = f(lm), frm = f(rm);
    const double left = (m - a) / 6 * (fa + 4 * flm + fm);
    const double right = (b - m) / 6 * (fm + 4 * frm + fb);
    const double delta = left + right - whole;
    if (depth <= 0 || std::abs(delta) <= 15 * tol) return left + right + delta / 15;
    return simpsonRec(f, a, m, fa, flm, fm, left, 0.5 * tol, depth - 1) +
           simpsonRec(f, m, b, fm, frm, fb, right, 0.5 * tol, depth - 1);
}

// ∫_a^b f with absolute tolerance tol: kPieces fixed pieces (so narrow peaks are seen), each
// refined adaptively.
template <typename F>
double adaptiveSimpson(F&& f, double a, double b, double tol) {
    const double h = (b - a) / kPieces;
    double sum = 0;
    double fa = f(a);
    for (int i = 0; i < kPieces; ++i) {
        const double x0 = a + i * h, x1 = (i + 1 == kPieces) ? b : a + (i + 1) * h;
        const double xm = 0.5 * (x0 + x1);
        const double fm = f(xm), fb = f(x1);
        const double whole = (x1 - x0) / 6 * (fa + 4 * fm + fb);
        sum += simpsonRec(f, x0, x1, fa, fm, fb, whole, tol / kPieces, kMaxDepth);
        fa = fb;
    }
    return sum;
}

// Composite Simpson on a fixed (2·kPieces+1)² grid in (θ, φ): a cheap estimate to set the
// tolerance.
double coarseCell(const std::function<double(const Vec3&)>& f, double z0, double z1, double p0,
                  double p1) {
    const int n = 2 * kPieces;
    const double t0 = std::acos(z1), t1 = std::acos(z0);
    double sum = 0;
    for (int i = 0; i <= n; ++i) {
        const double theta =
            std::clamp(t0 + (t1 - t0) * i / n, t0 + 1e-10 * (t1 - t0), t1 - 1e-10 * (t1 - t0));
        const double wz = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
        const double s = std::sin(theta), z = std::cos(theta);
        for (int j = 0; j <= n; ++j) {
            const double phi =
                std::clamp(p0 + (p1 - p0) * j / n, p0 + 1e-10 * (p1 - p0), p1 - 1e-10 * (p1 - p0));
            const double wp = (j == 0 || j == n) ? 1 : (j % 2 ? 4 : 2);
            sum += wz * wp * s * f(Vec3(s * std::cos(phi), s * std::sin(phi), z));
        }
    }
    return sum * (t1 - t0) * (p1 - p0) / (9.0 * n * n);
}

// ∫∫_cell f dφ dz with absolute tolerance floorTol or relative kRelTol, whichever is larger.
// The outer integral is taken over θ (dz = sin θ dθ), which removes the integrable 1/sin θ
// singularities at the poles of pdfs defined on (θ, φ) maps and is smooth wherever f is.
double integrateCell(const std::function<double(const Vec3&)>& f, double z0, double z1, double p0,
                     double p1, double floorTol) {
    const double coarse = coarseCell(f, z0, z1, p0, p1);
    const double tol = std::max(kRelTol * std::abs(coarse), floorTol);
    const double t0 = std::acos(z1), t1 = std::acos(z0);  // θ range, t0 < t1
    const double innerTol = 0.01 * tol / (z1 - z0);
    // Evaluate one-sided limits at the cell edges, where pdfs often jump (z = 0, φ = 0).
    const double dt = 1e-10 * (t1 - t0), dp = 1e-10 * (p1 - p0);
    auto outer = [&](double theta) {
        theta = std::clamp(theta, t0 + dt, t1 - dt);
        const double s = std::sin(theta), z = std::cos(theta);
        auto inner = [&](double phi) {
            phi = std::clamp(phi, p0 + dp, p1 - dp);
            return f(Vec3(s * std::cos(phi), s * std::sin(phi), z));
        };
        return s * adaptiveSimpson(inner, p0, p1, innerTol / std::max(s, 1e-3));
    };
    return adaptiveSimpson(outer, t0, t1, tol);
}

std::vector<double> cellIntegrals(const std::function<double(const Vec3&)>& f, int zBins,
                                  int phiBins, double floorTol) {
    std::vector<double> out(size_t(zBins) * phiBins);
    for (int iz = 0; iz < zBins; ++iz) {
        const double z0 = -1 + 2.0 * iz / zBins, z1 = -1 + 2.0 * (iz + 1) / zBins;
        for (int ip = 0; ip < phiBins; ++ip) {
            const double p0 = TwoPi * ip / phiBins, p1 = TwoPi * (ip + 1) / phiBins;
            out[size_t(iz) * phiBins + ip] = integrateCell(f, z0, z1, p0, p1, floorTol);
        }
    }
    return out;
}

}  // namespace

double integrateOverSphere(const std::function<double(const Vec3&)>& f, int zBins, int phiBins) {
    const auto cells = cellIntegrals(f, zBins, phiBins, 1e-14);
    return std::accumulate(cells.begin(), cells.end(), 0.0);
}

namespace {

/// The test proper; `cellProbabilities(N)` returns the expected probability of each cell.
Chi2Result runChi2(const std::function<std::optional<Vec3>(Rng&)>& sample,
                   const std::function<std::vector<double>(double)>& cellProbabilities,
                   const Chi2Options& opt) {
    Chi2Result res;
    std::ostringstream rep;
    const int nz = opt.zBins, np = opt.phiBins;
    const size_t nCells = size_t(nz) * np;
    const double N = double(opt.sampleCount);

    // 1. Histogram of the samples.
    std::vector<double> observed(nCells, 0);
    Rng rng(opt.seed, 0);
    for (long long k = 0; k < opt.sampleCount; ++k) {
        const std::optional<Vec3> w = sample(rng);
        if (!w || !w->allFinite()) {
            ++res.failedSamples;
            res.nonFiniteSamples += w.has_value();
            continue;
        }
        // Binned as they come: a sampler's directions are used unnormalised by its callers, so
        // one of another length is a defect the test must show, not hide.
        if (!(std::abs(w->squaredNorm() - 1) < 2e-6)) ++res.nonUnitSamples;
        const Vec3& d = *w;
        const int iz = std::clamp(int((d.z() + 1) * 0.5 * nz), 0, nz - 1);
        const int ip = std::clamp(int(sphericalPhi(d) * Inv2Pi * np), 0, np - 1);
        ++observed[size_t(iz) * np + ip];
    }

    // 2. Expected counts.
    const std::vector<double> prob = cellProbabilities(N);
    res.pdfIntegral = std::accumulate(prob.begin(), prob.end(), 0.0);
    std::vector<double> expected(nCells);
    for (size_t i = 0; i < nCells; ++i) expected[i] = N * prob[i];

    auto cellName = [&](size_t i) {
        const int iz = int(i / np), ip = int(i % np);
        char buf[160];
        std::snprintf(buf, sizeof buf, "cell (z %.3f..%.3f, phi %.3f..%.3f)", -1 + 2.0 * iz / nz,
                      -1 + 2.0 * (iz + 1) / nz, TwoPi * ip / np, TwoPi * (ip + 1) / np);
        return std::string(buf);
    };

    rep << "chi2 test: " << nz << "x" << np << " cells, " << opt.sampleCount << " samples, "
        << res.failedSamples << " failed; pdf integral = " << res.pdfIntegral << "\n";

    if (res.nonUnitSamples > 0) {
        rep << "FAIL: " << res.nonUnitSamples << " directions are not of unit length\n";
        res.passed = false;
        res.pValue = 0;
        res.report = rep.str();
        return res;
    }
    if (res.nonFiniteSamples > 0 || (res.failedSamples > 0 && !opt.allowFailedSamples)) {
        rep << "FAIL: " << res.failedSamples << " samples were empty or not finite ("
            << res.nonFiniteSamples << " not finite)\n";
        res.passed = false;
        res.pValue = 0;
        res.report = rep.str();
        return res;
    }

    // 3. The χ² of the counts.
    const Chi2Result counts = chi2TestCounts(observed, expected, opt, cellName);
    res.passed = counts.passed;
    res.pValue = counts.pValue;
    res.statistic = counts.statistic;
    res.dof = counts.dof;
    res.report = rep.str() + counts.report;
    return res;
}

}  // namespace

Chi2Result chi2TestCounts(const std::vector<double>& observed, const std::vector<double>& expected,
                          const Chi2Options& opt,
                          const std::function<std::string(size_t)>& cellName) {
    Chi2Result res;
    std::ostringstream rep;
    rep.precision(12);  // (counts are doubles: whole counts print whole)
    auto name = [&](size_t i) { return cellName ? cellName(i) : "cell " + std::to_string(i); };
    auto fail = [&](const auto&... what) {
        ((rep << "FAIL: ") << ... << what) << "\n";
        res.report = rep.str();
        return res;
    };
    const size_t nCells = observed.size();
    if (expected.size() != nCells)
        return fail(nCells, " observed counts against ", expected.size(), " expected ones");
    if (!(opt.alpha > 0 && opt.alpha < 1) || opt.numTests < 1 || !(opt.minExpected > 0))
        return fail("alpha ", opt.alpha, ", numTests ", opt.numTests, ", minExpected ",
                    opt.minExpected, ": want 0 < alpha < 1, numTests >= 1, minExpected > 0");
    // Counts that are not counts fail at once, and so do samples where the pdf is zero.
    for (size_t i = 0; i < nCells; ++i) {
        if (!(observed[i] >= 0) || !std::isfinite(observed[i]))
            return fail(name(i), " has an observed count of ", observed[i]);
        if (!(expected[i] >= 0) || !std::isfinite(expected[i]))
            return fail(name(i), " has an expected count of ", expected[i]);
        if (observed[i] > 0 && expected[i] == 0)
            return fail(name(i), " has ", observed[i], " samples but expected count 0");
    }
    // Pool small cells (Mitsuba 3), accumulate χ².
    std::vector<size_t> order(nCells);
    std::iota(order.begin(), order.end(), size_t(0));
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return expected[a] < expected[b]; });
    double chi2 = 0, poolObs = 0, poolExp = 0;
    int tested = 0, pooledCells = 0;
    std::vector<std::pair<double, size_t>> contrib;
    for (size_t i : order) {
        if (expected[i] == 0 && observed[i] == 0) continue;
        if (expected[i] < opt.minExpected || (poolExp > 0 && poolExp < opt.minExpected)) {
            poolObs += observed[i];
            poolExp += expected[i];
            ++pooledCells;
        } else {
            const double d = observed[i] - expected[i];
            const double c = d * d / expected[i];
            chi2 += c;
            ++tested;
            contrib.emplace_back(c, i);
        }
    }
    if (poolExp >= opt.minExpected) {
        const double d = poolObs - poolExp;
        chi2 += d * d / poolExp;
        ++tested;
    } else if (poolObs > 0 || poolExp > 0) {
        rep << "pool of " << pooledCells << " cells (expected " << poolExp << ", observed "
            << poolObs << ") too small to test\n";
    }
    // (Totals need not agree: the sphere test's lost samples fall in no cell.)
    rep << "observed " << std::accumulate(observed.begin(), observed.end(), 0.0)
        << " in all, expected " << std::accumulate(expected.begin(), expected.end(), 0.0) << "\n";
    res.statistic = chi2;
    res.dof = tested - 1;
    if (res.dof < 1) {
        rep << "FAIL: too few cells to test (dof = " << res.dof << ")\n";
        res.passed = false;
        res.report = rep.str();
        return res;
    }
    res.pValue = boost::math::gamma_q(0.5 * res.dof, 0.5 * chi2);
    const double threshold = sidakThreshold(opt.alpha, opt.numTests);
    res.passed = res.pValue > threshold;

    rep << "chi2 = " << chi2 << ", dof = " << res.dof << ", p = " << res.pValue
        << ", threshold (Sidak, " << opt.numTests << " tests, alpha " << opt.alpha
        << ") = " << threshold << ", pooled " << pooledCells << " cells (expected " << poolExp
        << ", observed " << poolObs << ")\n";
    std::sort(contrib.rbegin(), contrib.rend());
    rep << "worst cells:\n";
    for (size_t k = 0; k < std::min<size_t>(5, contrib.size()); ++k) {
        const size_t i = contrib[k].second;
        rep << "  " << name(i) << ": observed " << observed[i] << ", expected " << expected[i]
            << ", contribution " << contrib[k].first << "\n";
    }
    rep << (res.passed ? "PASSED" : "FAILED") << "\n";
    res.report = rep.str();
    return res;
}

Chi2Result chi2TestSphere(const std::function<std::optional<Vec3>(Rng&)>& sample,
                          const std::function<double(const Vec3&)>& pdf, const Chi2Options& opt) {
    // The absolute floor 1e-4/N keeps the count error below 1e-4 per cell.
    return runChi2(
        sample, [&](double N) { return cellIntegrals(pdf, opt.zBins, opt.phiBins, 1e-4 / N); },
        opt);
}

Chi2Result chi2TestSphereCells(
    const std::function<std::optional<Vec3>(Rng&)>& sample,
    const std::function<double(double z0, double z1, double phi0, double phi1)>& cellProbability,
    const Chi2Options& opt) {
    return runChi2(
        sample,
        [&](double) {
            const int nz = opt.zBins, np = opt.phiBins;
            std::vector<double> out(size_t(nz) * np);
            for (int iz = 0; iz < nz; ++iz)
                for (int ip = 0; ip < np; ++ip)
                    out[size_t(iz) * np + ip] =
                        cellProbability(-1 + 2.0 * iz / nz, -1 + 2.0 * (iz + 1) / nz,
                                        TwoPi * ip / np, TwoPi * (ip + 1) / np);
            return out;
        },
        opt);
}

}  // namespace shvol
