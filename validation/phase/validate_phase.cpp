// validate_phase: the experiments behind validation/phase/README.md. For every phase function,
// order and window it fits the zonal SH series, builds the SH sampler (SHSampledPhase) and
// measures fit quality, chi² of the SH-sampled directions against the SH pdf and against the
// analytic pdf, the variance of a one-sample estimator of I = ∫ p(wo·ω) L(ω) dω, and the cost per
// sample. Writes CSV files to validation/phase/results/ (or argv[1]). Run through run.sh.
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "shvol/core/rng.h"
#include "shvol/phase/phase_function.h"
#include "shvol/phase/phase_table_csv.h"
#include "shvol/phase/sh_sampled_phase.h"
#include "shvol/phase/zonal_fit.h"
#include "shvol/sampling/chi2.h"
#include "shvol/sampling/zonal_sh_sampler.h"

using namespace shvol;

namespace {

std::string outDir;

std::ofstream open(const std::string& name) {
    std::ofstream f(outDir + "/" + name);
    if (!f) throw std::runtime_error("cannot write " + outDir + "/" + name);
    f.precision(8);
    return f;
}

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

// ---------------------------------------------------------------------------------------------
// Experiment parameters.
const std::vector<int> kOrders = {2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64};
const std::vector<SHWindow> kWindows = {SHWindow::None, SHWindow::Hann};
constexpr long long kChi2Samples = 200000;
constexpr int kChi2ZBins = 100, kChi2PhiBins = 8;
constexpr long long kVarianceSamples = 200000;
constexpr int kTimingSamples = 1 << 20;  // ≥ 1e6, best of kTimingRepeats
constexpr int kTimingRepeats = 5;

// The estimator's setting: an off-axis propagation direction and a sky-like radiance (constant
// ground + zenith gradient + a broad sun lobe, none of them aligned with wo).
const Vec3 kWo = Vec3(0.5, -0.2, 0.84).normalized();
const Vec3 kSun = Vec3(0.4, 0.3, 0.866).normalized();
double radiance(const Vec3& w) {
    return 0.3 + std::max(0.0, w.z()) + 5.0 * std::exp(40.0 * (w.dot(kSun) - 1.0));
}

// ∫_{t0}^{t1} f(θ) dθ, adaptive Gauss–Kronrod on panels graded geometrically towards θ = 0 and
// θ = π (forward/backward peaks as narrow as HG g = 0.99 are then resolved).
double integrateTheta(const std::function<double(double)>& f, double t0, double t1) {
    static const std::vector<double> breaks = [] {
        std::vector<double> b = {0};
        for (double t = 1e-5; t < 0.5; t *= 3) b.push_back(t);
        b.push_back(0.5);
        b.push_back(Pi / 2);
        b.push_back(Pi - 0.5);
        std::vector<double> back;
        for (double t = 1e-5; t < 0.5; t *= 3) back.push_back(Pi - t);
        for (auto it = back.rbegin(); it != back.rend(); ++it) b.push_back(*it);
        b.push_back(Pi);
        return b;
    }();
    double sum = 0;
    for (size_t i = 0; i + 1 < breaks.size(); ++i) {
        const double a = std::max(t0, breaks[i]), b = std::min(t1, breaks[i + 1]);
        if (b <= a) continue;
        sum += boost::math::quadrature::gauss_kronrod<double, 31>::integrate(f, a, b, 10, 1e-10);
    }
    return sum;
}

// ∫_{z0}^{z1} 2π p(μ) dμ, the probability of a z-slab for a density p(μ) around +z.
double slabProbability(const std::function<double(double)>& p, double z0, double z1) {
    const double t0 = std::acos(std::clamp(z1, -1.0, 1.0));
    const double t1 = std::acos(std::clamp(z0, -1.0, 1.0));
    return integrateTheta([&](double t) { return TwoPi * p(std::cos(t)) * std::sin(t); }, t0, t1);
}

// L̄(μ): the average of L over the circle at angle θ = acos μ around kWo (trapezoid in φ with
// 2048 points), tabulated once at 16384 equal steps in θ and interpolated linearly (error ~1e-8;
// calling the trapezoid inside the adaptive quadrature made it chase the rule's own noise).
double circleAverageRadiance(double mu) {
    constexpr int nTheta = 16384, nPhi = 2048;
    static const std::vector<double> table = [] {
        const Frame frame(kWo);
        std::vector<double> t(nTheta + 1);
        for (int i = 0; i <= nTheta; ++i) {
            const double m = std::cos(Pi * i / nTheta);
            double s = 0;
            for (int k = 0; k < nPhi; ++k)
                s += radiance(frame.toWorld(sphericalDirection(m, TwoPi * (k + 0.5) / nPhi)));
            t[i] = s / nPhi;
        }
        return t;
    }();
    const double x = std::acos(std::clamp(mu, -1.0, 1.0)) / Pi * nTheta;
    const int i = std::min(int(x), nTheta - 1);
    return table[i] + (x - i) * (table[i + 1] - table[i]);
}

// I = ∫ p(kWo·ω) L(ω) dω = ∫ 2π p(μ) L̄(μ) dμ.
double integralAgainstRadiance(const std::function<double(double)>& p) {
    return integrateTheta(
        [&](double t) {
            const double mu = std::cos(t);
            return TwoPi * p(mu) * circleAverageRadiance(mu) * std::sin(t);
        },
        0, Pi);
}

struct Case {
    std::string name;
    PhaseFunction phase;
};

double evalCos(const PhaseFunction& p, double mu) {
    return p.eval(Vec3(0, 0, 1), sphericalDirection(mu, 0));
}

struct MeanVar {
    double mean = 0, var = 0;
    long long n = 0;
};

// One-sample estimator f/pdf · L of I with directions drawn by `phase` around kWo.
MeanVar estimatorStats(const PhaseFunction& phase, long long n, uint64_t seed) {
    Rng rng(seed, 7);
    double mean = 0, m2 = 0;
    for (long long i = 0; i < n; ++i) {
        const PhaseSample s = phase.sample(kWo, rng.uniform2());
        const double x = s.pdf > 0 ? s.value / s.pdf * radiance(s.wi) : 0.0;
        const double d = x - mean;
        mean += d / double(i + 1);
        m2 += d * (x - mean);
    }
    return {mean, m2 / double(n - 1), n};
}

// Nanoseconds per phase.sample(kWo, u) over kTimingSamples pre-drawn u.
double nsPerSample(const PhaseFunction& phase, const std::vector<Vec2>& us) {
    double acc = 0;
    const auto t0 = Clock::now();
    for (const Vec2& u : us) {
        const PhaseSample s = phase.sample(kWo, u);
        acc += s.wi.z() + s.pdf;
    }
    const double ns = secondsSince(t0) * 1e9 / double(us.size());
    static volatile double sink = 0;
    sink = sink + acc;
    return ns;
}

// The zonal warp alone (cos θ, φ, pdf around +z; no frame, no evaluation of p).
double nsPerLocalSample(const ZonalSHSampler& sampler, const std::vector<Vec2>& us) {
    double acc = 0;
    const auto t0 = Clock::now();
    for (const Vec2& u : us) {
        const ZonalSHSampler::LocalSample s = sampler.warpLocal(u);
        acc += s.cosTheta + s.pdf;
    }
    const double ns = secondsSince(t0) * 1e9 / double(us.size());
    static volatile double sink = 0;
    sink = sink + acc;
    return ns;
}

struct Timing {
    double analytic = 1e30, sh = 1e30, local = 1e30;
};
// Analytic, SH and warp-only passes interleaved, best of kTimingRepeats each, so that all three
// see the same machine load (another build may share the 2 cores).
Timing timeSamplers(const PhaseFunction& analytic, const PhaseFunction& sh,
                    const ZonalSHSampler& sampler, const std::vector<Vec2>& us) {
    Timing t;
    for (int r = 0; r < kTimingRepeats; ++r) {
        t.analytic = std::min(t.analytic, nsPerSample(analytic, us));
        t.sh = std::min(t.sh, nsPerSample(sh, us));
        t.local = std::min(t.local, nsPerLocalSample(sampler, us));
    }
    return t;
}

Chi2Options chi2Options(int numTests) {
    Chi2Options o;
    o.zBins = kChi2ZBins;
    o.phiBins = kChi2PhiBins;
    o.sampleCount = kChi2Samples;
    o.numTests = numTests;
    return o;
}

}  // namespace

int main(int argc, char** argv) {
    outDir = argc > 1 ? argv[1] : std::string(SHVOL_SOURCE_DIR) + "/validation/phase/results";
    const auto tStart = Clock::now();

    const std::vector<Case> cases = {
        {"isotropic", IsotropicPhase()},
        {"hg_0.5", HenyeyGreensteinPhase(0.5)},
        {"hg_0.9", HenyeyGreensteinPhase(0.9)},
        {"hg_0.99", HenyeyGreensteinPhase(0.99)},
        {"two_term_hg", TwoTermHenyeyGreensteinPhase(0.9, -0.3, 0.8)},
        {"rayleigh", RayleighPhase()},
        {"schlick_0.7", SchlickPhase(0.7)},
        {"cornette_shanks_0.8", CornetteShanksPhase(0.8)},
        {"tabulated_mie_like",
         readPhaseTableCsv(std::string(SHVOL_SOURCE_DIR) + "/media/phase/mie_like.csv")},
    };
    const int numTests = int(cases.size() * kOrders.size() * kWindows.size());

    std::vector<Vec2> us(kTimingSamples);
    {
        Rng rng(12345, 3);
        for (Vec2& u : us) u = rng.uniform2();
    }
    const Vec3 zAxis(0, 0, 1);

    auto analytic = open("analytic.csv");
    analytic << "phase,I_ref,estimator_mean,estimator_var,z_score,ns_per_sample,chi2_p,"
                "chi2_passed,slab_prob_sum\n";
    auto table = open("phase_sh.csv");
    table << "phase,window,order,energy_fraction,l2_error,rel_l2_error,max_error,peak_value,"
             "min_value,min_over_peak,clamped_fraction,defensive_alpha,chi2_sh_p,chi2_sh_passed,"
             "chi2_analytic_p,chi2_analytic_passed,chi2_analytic_stat,chi2_analytic_dof,"
             "var_analytic,var_sh,var_ratio_sh_over_analytic,mean_sh,z_sh,I_ref,I_recon,"
             "recon_rel_bias,mean_recon,var_recon,ns_analytic,ns_sh,ns_sh_local,build_ms,max_"
             "weight,mu_max_weight\n";

    for (const Case& c : cases) {
        const auto tCase = Clock::now();
        const auto p = [&](double mu) { return evalCos(c.phase, mu); };
        // Exact cell probabilities of the analytic density around +z, one slab per z bin.
        std::vector<double> slab(kChi2ZBins);
        double slabSum = 0;
        for (int i = 0; i < kChi2ZBins; ++i) {
            slab[i] =
                slabProbability(p, -1 + 2.0 * i / kChi2ZBins, -1 + 2.0 * (i + 1) / kChi2ZBins);
            slabSum += slab[i];
        }
        const auto analyticCell = [&](double z0, double z1, double phi0, double phi1) {
            const int i =
                std::clamp(int(std::lround((z0 + 1) / 2 * kChi2ZBins)), 0, kChi2ZBins - 1);
            (void)z1;
            return slab[i] * (phi1 - phi0) / TwoPi;
        };
        const double iRef = integralAgainstRadiance(p);
        const MeanVar an = estimatorStats(c.phase, kVarianceSamples, 11);
        double nsAnalytic = 1e30;
        for (int r = 0; r < kTimingRepeats; ++r)
            nsAnalytic = std::min(nsAnalytic, nsPerSample(c.phase, us));
        // Sanity: the analytic sampler against the analytic cell probabilities.
        const Chi2Result anChi2 = chi2TestSphereCells(
            [&](Rng& rng) -> std::optional<Vec3> {
                return c.phase.sample(zAxis, rng.uniform2()).wi;
            },
            analyticCell, chi2Options(int(cases.size())));
        analytic << c.name << ',' << iRef << ',' << an.mean << ',' << an.var << ','
                 << (an.mean - iRef) / std::sqrt(an.var / double(an.n)) << ',' << nsAnalytic << ','
                 << anChi2.pValue << ',' << anChi2.passed << ',' << slabSum << '\n';
        analytic.flush();
        std::printf("%-20s I=%.6f analytic: mean %.6f var %.4g  %.1f ns/sample  chi2 p=%.3g\n",
                    c.name.c_str(), iRef, an.mean, an.var, nsAnalytic, anChi2.pValue);

        for (SHWindow window : kWindows) {
            for (int order : kOrders) {
                const auto tBuild = Clock::now();
                const SHSampledPhase sh(c.phase, order, window, SHSampledPhase::Evaluate::Exact);
                const double buildMs = secondsSince(tBuild) * 1e3;
                const SHSampledPhase recon(c.phase, order, window,
                                           SHSampledPhase::Evaluate::Reconstruction);
                const PhaseFunction shPhase(sh), reconPhase(recon);
                const ZonalFit& fit = sh.fit();
                const ZonalSHSampler& sampler = sh.sampler();
                const double alpha = sh.defensiveFraction();

                const auto sampleSH = [&](Rng& rng) -> std::optional<Vec3> {
                    return shPhase.sample(zAxis, rng.uniform2()).wi;
                };
                const Chi2Result chiSH = chi2TestSphereCells(
                    sampleSH,
                    [&](double z0, double z1, double phi0, double phi1) {
                        return (phi1 - phi0) / TwoPi *
                               ((1 - alpha) * (sampler.cdf(z1) - sampler.cdf(z0)) +
                                alpha * (z1 - z0) / 2);
                    },
                    chi2Options(numTests));
                const Chi2Result chiAn =
                    chi2TestSphereCells(sampleSH, analyticCell, chi2Options(numTests));

                const MeanVar est = estimatorStats(shPhase, kVarianceSamples, 11);
                const MeanVar rec = estimatorStats(reconPhase, kVarianceSamples, 13);
                const double iRecon = integralAgainstRadiance(
                    [&](double mu) { return reconPhase.eval(zAxis, sphericalDirection(mu, 0)); });
                const Timing tm = timeSamplers(c.phase, shPhase, sampler, us);
                // Largest weight p/pdf of the Exact use, over the centres of the sampler's bins.
                double maxWeight = 0, muMaxWeight = 1;
                const int bins = 1 << sampler.depth();
                for (int i = 0; i < bins; ++i) {
                    const double mu = -1 + (i + 0.5) * 2.0 / bins;
                    const double w =
                        evalCos(c.phase, mu) / sh.pdf(zAxis, sphericalDirection(mu, 0));
                    if (w > maxWeight) maxWeight = w, muMaxWeight = mu;
                }

                table << c.name << ',' << shWindowName(window) << ',' << order << ','
                      << fit.energyFraction << ',' << fit.l2Error << ',' << fit.relativeL2Error
                      << ',' << fit.maxError << ',' << fit.peakValue << ',' << fit.minValue << ','
                      << fit.minValue / fit.peakValue << ',' << sampler.clampedFraction() << ','
                      << alpha << ',' << chiSH.pValue << ',' << chiSH.passed << ',' << chiAn.pValue
                      << ',' << chiAn.passed << ',' << chiAn.statistic << ',' << chiAn.dof << ','
                      << an.var << ',' << est.var << ',' << est.var / an.var << ',' << est.mean
                      << ',' << (est.mean - iRef) / std::sqrt(est.var / double(est.n)) << ','
                      << iRef << ',' << iRecon << ',' << (iRecon - iRef) / iRef << ',' << rec.mean
                      << ',' << rec.var << ',' << tm.analytic << ',' << tm.sh << ',' << tm.local
                      << ',' << buildMs << ',' << maxWeight << ',' << muMaxWeight << '\n';
                table.flush();
                std::printf(
                    "  %-4s n=%2d E=%.5f relL2=%.3g min/peak=%+.3g clamp=%.3f chi2(SH) p=%.3g "
                    "chi2(an) p=%.3g var %.3gx max w %.3g  %.1f/%.1f ns  bias(recon) %+.2e\n",
                    shWindowName(window), order, fit.energyFraction, fit.relativeL2Error,
                    fit.minValue / fit.peakValue, sampler.clampedFraction(), chiSH.pValue,
                    chiAn.pValue, est.var / an.var, maxWeight, tm.sh, tm.analytic,
                    (iRecon - iRef) / iRef);
                if (!chiSH.passed) std::printf("%s\n", chiSH.report.c_str());
            }
        }
        std::printf("  (%s: %.1f s)\n", c.name.c_str(), secondsSince(tCase));
        std::fflush(stdout);
    }
    std::printf("validate_phase: %.1f s\n", secondsSince(tStart));
    return 0;
}
