// shvol phase fit | sample: the zonal SH fit of a phase function, and samples from the SH-sampled
// phase function exactly as a render builds it (same keys, defaults, pdf and weights), or from
// the phase function's own sampler.
#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>

#include "commands.h"
#include "shvol/core/atomic_file.h"
#include "shvol/core/error.h"
#include "shvol/core/rng.h"
#include "shvol/io/phase_spec.h"
#include "shvol/phase/sh_sampled_phase.h"
#include "shvol/phase/zonal_fit.h"
#include "shvol/sampling/sh_sampler.h"
#include "shvol/sampling/warp.h"
#include "shvol/sampling/zonal_sh_sampler.h"

namespace shvol::app {

namespace {

/// Command-line values; an empty string or 0 means "not given": the spec's key, else the
/// renderer's default, applies.
struct PhaseArgs {
    std::string spec, order, window, evaluate, out, sampler = "zonal";
    double tolerance = 0;
    int depth = 0;
    long long count = 10000;
    unsigned long long seed = 1;
    bool json = false;
};

constexpr int kGeneralMaxDepth = 10;  ///< SHSampler's table mode

/// The SH-sampled phase function the spec and the options name: the spec's SH keys, each
/// replaced by its option when that is given; "sampling": "sh" is implied.
SHSampledPhase shPhase(const PhaseArgs& a) {
    Json j = phaseSpecToJson(a.spec);
    // (implied, not overridden: a spec that says "analytic", a medium's phase object pasted,
    // would be fitted in silence against its word; helper 77)
    if (j.contains("sampling") && j["sampling"] != "sh")
        fail(specName(a.spec), "sampling",
             "the spec asks for " + j["sampling"].dump() +
                 ", and this command fits an SH sampler (leave the key out)");
    j["sampling"] = "sh";
    if (!a.order.empty()) {
        if (a.order == "auto")
            j["order"] = "auto";
        else
            j["order"] = std::stoi(a.order);  // validated by the option's check
    }
    if (a.tolerance > 0) {
        if (j.contains("order") && j["order"].is_number())
            failOption("--tolerance",
                       "only valid with --order auto (" +
                           (a.order.empty() ? "the spec's order is " + j["order"].dump()
                                            : "got --order " + a.order) +
                           ")");
        j["tolerance"] = a.tolerance;
    } else if (!a.order.empty() && a.order != "auto") {
        j.erase("tolerance");  // the spec's, for its "order": "auto", which --order replaced
    }
    if (!a.window.empty()) j["window"] = a.window;
    if (!a.evaluate.empty()) j["evaluate"] = a.evaluate;
    if (a.depth > 0) j["sh_depth"] = a.depth;
    const PhaseFunction p = readPhaseFunction(j, specName(a.spec), "");
    return std::get<SHSampledPhase>(p.variant());
}

/// x^n as %.3g, or as "10^k" (k = n·log10 x rounded) where it leaves the range of a double (for
/// x > 0).
std::string powerText(double x, int n) {
    const double p = std::pow(x, n);
    char text[64];
    if (x <= 0 || (std::isfinite(p) && p >= DBL_MIN))
        std::snprintf(text, sizeof text, "%.3g", p);
    else
        std::snprintf(text, sizeof text, "10^%.0f", n * std::log10(x));
    return text;
}

const char* evaluateName(const SHSampledPhase& sh) {
    return sh.evaluate() == SHSampledPhase::Evaluate::Exact ? "exact" : "sh";
}

/// m₂ of the same fit used the other way (Exact ↔ Reconstruction).
double otherSecondMoment(const SHSampledPhase& sh) {
    const auto other = sh.evaluate() == SHSampledPhase::Evaluate::Exact
                           ? SHSampledPhase::Evaluate::Reconstruction
                           : SHSampledPhase::Evaluate::Exact;
    return SHSampledPhase(sh.base(), int(sh.fit().p.size()), sh.fit().window, other,
                          sh.sampler().depth())
        .weightSecondMoment();
}

/// The warning of blindSHFitText on stderr, naming the spec.
void warnIfBlind(const PhaseArgs& a, const SHSampledPhase& sh) {
    if (const std::string blind = blindSHFitText(sh); !blind.empty())
        std::fprintf(stderr,
                     "shvol: warning: %s: %s; use \"sampling\": \"analytic\" (phase sample "
                     "--sampler analytic)\n",
                     escapeControlCharacters(a.spec).c_str(), blind.c_str());
}

}  // namespace

std::string blindSHFitText(const SHSampledPhase& sh) {
    if (!(std::abs(sh.quadratureMass() - 1) > SHSampledPhase::kBlindQuadrature)) return "";
    // Exact: the weight p/pdf is 0 where the fit has none of the lobe, and its light is lost
    // (the furnace); sh: the function rendered is the fit, not the table.
    char msg[400];
    std::snprintf(msg, sizeof msg,
                  "the function has structure finer than the quadrature of its SH fit sees (it "
                  "finds %.4g of its integral, 1): the fit, and the checks of its error and "
                  "weight, are blind to it, and %s",
                  sh.quadratureMass(),
                  sh.evaluate() == SHSampledPhase::Evaluate::Exact
                      ? "the render can lose its light"
                      : "the function rendered, the fit, need not resemble it");
    return msg;
}

namespace {

int runFit(const PhaseArgs& a) {
    const SHSampledPhase sh = shPhase(a);
    warnIfBlind(a, sh);
    const ZonalFit& f = sh.fit();
    const int order = int(f.p.size());
    const double m2 = sh.weightSecondMoment(), m2other = otherSecondMoment(sh);
    const bool exact = sh.evaluate() == SHSampledPhase::Evaluate::Exact;
    const double m2exact = exact ? m2 : m2other;
    if (a.json) {
        nlohmann::json j;
        j["spec"] = a.spec;
        j["order"] = order;
        j["window"] = shWindowName(f.window);
        j["evaluate"] = evaluateName(sh);
        j["sh_depth"] = sh.sampler().depth();
        j["coefficients"] = f.p;
        j["before_window"] = {{"energy_fraction", f.energyFraction}};
        j["after_window"] = {{"l2_error", f.l2Error},
                             {"relative_l2_error", f.relativeL2Error},
                             {"max_error", f.maxError},
                             {"min_value", f.minValue},
                             {"peak_value", f.peakValue}};
        j["rendered_relative_l2_error"] = sh.renderedRelativeL2Error();
        j["quadrature_mass"] = sh.quadratureMass();
        j["clamped_bins_fraction"] = sh.sampler().clampedFraction();
        j["defensive_fraction"] = sh.defensiveFraction();
        j["weight_second_moment"] = m2;
        j["weight_second_moment_exact"] = m2exact;
        std::printf("%s\n", dumpJson(j, 2).c_str());
        return 0;
    }
    // (a spec of several lines stays on the comment's line)
    std::printf("# zonal SH fit of %s: p(mu) ~ sum_l p_l y_l^0(mu)\n",
                escapeControlCharacters(a.spec).c_str());
    std::printf(
        "order              %d\nwindow             %s\nevaluate           %s\n"
        "sh_depth           %d\n",
        order, shWindowName(f.window), evaluateName(sh), sh.sampler().depth());
    std::printf(
        "# before the window: the plain projection (Gautron 2004 eq. 15)\n"
        "energy_fraction    %.10g\n",
        f.energyFraction);
    std::printf(
        "# after the window: the fit, against the function\n"
        "l2_error           %.6g\nrelative_l2_error  %.6g\nmax_error          %.6g\n"
        "min_value          %.6g\npeak_value         %.6g\n",
        f.l2Error, f.relativeL2Error, f.maxError, f.minValue, f.peakValue);
    std::printf(
        "# the function rendered (evaluate sh: the fit averaged over the sampler's z-bins,\n"
        "# clamped at 0 and normalised; evaluate exact: the function itself), against the "
        "function\n"
        "rendered_relative_l2_error  %.6g  (evaluate %s)\n"
        "# the share of the function's integral the quadrature of these figures finds (1 unless "
        "the\n# function has structure finer than its nodes: then they are blind to it)\n"
        "quadrature_mass             %.6g\n",
        sh.renderedRelativeL2Error(), evaluateName(sh), sh.quadratureMass());
    std::printf(
        "# the sampler: weight p/pdf per phase sample, E[(p/pdf)^2] by quadrature\n"
        "clamped_bins_fraction       %.6g\ndefensive_fraction          %.6g\n"
        "weight_second_moment        %.6g  (evaluate %s)\n"
        "weight_second_moment_exact  %.6g  (evaluate exact; ^100 = %s)\n",
        sh.sampler().clampedFraction(), sh.defensiveFraction(), m2, evaluateName(sh), m2exact,
        powerText(m2exact, 100).c_str());
    std::printf("l,p_l\n");
    for (int l = 0; l < order; ++l) std::printf("%d,%.17g\n", l, f.p[l]);
    return 0;
}

/// Mean, variance and maximum of the weights f/pdf, by Welford's updates: Σw²/n − mean², of
/// weights within 10⁻⁷ of 1, was all rounding (0 or 6·10⁻¹², for a variance of 10⁻¹⁴; helper 164).
struct WeightStats {
    long long n = 0;
    double mean_ = 0, m2 = 0, max = 0;  // m2: Σ (w − mean)²
    void add(double w) {
        const double d = w - mean_;
        mean_ += d / double(++n);
        m2 += d * (w - mean_);
        max = std::max(max, w);
    }
    double mean() const { return mean_; }
    double variance() const { return m2 / double(n); }
};

/// `phase sample --sampler analytic`: the phase function's own sampler, as `"sampling":
/// "analytic"` renders it, so that an outside test can check it (a histogram against the
/// formula); the SH options have nothing to act on there.
PhaseFunction analyticPhase(const PhaseArgs& a, const Json& j) {
    const std::pair<const char*, bool> shOptions[] = {{"--order", !a.order.empty()},
                                                      {"--tolerance", a.tolerance > 0},
                                                      {"--window", !a.window.empty()},
                                                      {"--evaluate", !a.evaluate.empty()},
                                                      {"--depth", a.depth > 0}};
    for (const auto& [name, given] : shOptions)
        if (given) failOption(name, "not with --sampler analytic: it samples no SH fit");
    if (j.contains("sampling") && j["sampling"] == "sh")
        failOption("--sampler",
                   "analytic samples the phase function itself, and the spec asks "
                   "for \"sampling\": \"sh\"");
    return readPhaseFunction(j, specName(a.spec), "");
}

/// Writes the samples' CSV (x,y,z,pdf,weight) through a temporary and prints the weights' mean,
/// variance and maximum: rows(rng, row) calls row(direction, value, pdf) for each sample.
template <typename Rows>
void writeSamples(const PhaseArgs& a, const Json& spec, Rows&& rows) {
    // The samples must not replace the table they are drawn from.
    if (spec.contains("file") && spec["file"].is_string() &&
        sameFile(a.out, spec["file"].get<std::string>()))
        failOption("--output", a.out +
                                   " is the phase table being sampled (the spec's file); write the "
                                   "samples elsewhere");
    WeightStats ws;
    writeAtomically(a.out, [&](const std::string& tmp) {
        writeStreamTo(tmp, a.out, "CSV", [&](std::ofstream& csv) {
            csv << std::setprecision(17) << "x,y,z,pdf,weight\n";
            Rng rng(a.seed, 0);
            rows(rng, [&](const Vec3& w, double value, double pdf) {
                const double weight = pdf > 0 ? value / pdf : 0.0;
                ws.add(weight);
                csv << w.x() << ',' << w.y() << ',' << w.z() << ',' << pdf << ',' << weight << '\n';
                // (at once, while errno is the failed write's: the sampling may set it later)
                if (!csv) failWriting(a.out, errno);
            });
        });
    });
    std::fprintf(stderr,
                 "wrote %lld samples to %s\nweight p/pdf: mean %.6g, variance %.6g, max %.6g",
                 a.count, a.out.c_str(), ws.mean(), ws.variance(), ws.max);
}

int runSample(const PhaseArgs& a) {
    if (a.sampler == "analytic") {
        const Json spec = phaseSpecToJson(a.spec);
        const PhaseFunction phase = analyticPhase(a, spec);
        writeSamples(a, spec, [&](Rng& rng, const auto& row) {
            for (long long i = 0; i < a.count; ++i) {
                const PhaseSample x = phase.sample(Vec3(0, 0, 1), rng.uniform2());
                row(x.wi, x.value, x.pdf);
            }
        });
        std::fprintf(stderr, "\n");
        return 0;
    }
    const bool general = a.sampler == "general";
    if (general && a.depth > kGeneralMaxDepth)
        failOption("--depth", "the general sampler supports depths up to 10");
    if (general && a.order != "auto" && !a.order.empty() && std::stoi(a.order) > 128)
        failOption("--order", "the general sampler supports orders up to 128");
    const SHSampledPhase sh = shPhase(a);
    const PhaseFunction phase(sh);
    const int order = int(sh.fit().p.size());
    const Json spec = phaseSpecToJson(a.spec);
    if (general && order > 128) {  // the spec's own order, or an automatic one
        const bool specOrder =
            a.order.empty() && spec.contains("order") && spec["order"].is_number();
        failOption(
            "--sampler",
            "the general sampler supports orders up to 128, and " +
                (specOrder
                     ? "the spec's order is " + std::to_string(order) + "; give --order 128 or less"
                     : "the automatic order of " + a.spec + " is " + std::to_string(order) +
                           "; give --order 128 or less, or a larger --tolerance"));
    }
    // The general sampler's depth: --depth, else the spec's sh_depth as for the zonal one (it
    // was ignored), else its own limit.
    const int generalDepth = a.depth > 0                 ? a.depth
                             : spec.contains("sh_depth") ? sh.sampler().depth()
                                                         : kGeneralMaxDepth;
    if (general && generalDepth > kGeneralMaxDepth)
        failOption("--sampler",
                   "the general sampler supports depths up to 10, and the spec's "
                   "sh_depth is " +
                       std::to_string(generalDepth) + "; give --depth 10 or less");
    warnIfBlind(a, sh);
    const Vec3 z(0, 0, 1);
    // The general sampler's defensive share, the zonal one's, in both uses: evaluated exactly,
    // the function is positive where the fit rings below 0 and the warp never goes; as the fit,
    // it is the fit on the zonal sampler's 2^sh_depth bins, positive in fine bins within coarse
    // cells whose mass the warp's coarser table clamps to 0 (HG 0.999 at order 128: mean weight
    // 0.9895 ± 0.0019 without it; helper 110).
    constexpr double generalAlpha = SHSampledPhase::kDefensiveFraction;
    writeSamples(a, spec, [&](Rng& rng, const auto& row) {
        if (!general) {
            for (long long i = 0; i < a.count; ++i) {
                const PhaseSample x = phase.sample(z, rng.uniform2());
                row(x.wi, x.value, x.pdf);
            }
            return;
        }
        std::vector<double> c(size_t(order) * order, 0.0);
        for (int l = 0; l < order; ++l) c[size_t(l) * (l + 1)] = sh.fit().p[l];
        const SHSampler s(order, c.data(), SHSampler::Mode::Tables, generalDepth);
        for (long long i = 0; i < a.count; ++i) {
            // A uniform share α keeps E[p/pdf] = 1 (evaluated exactly it was 0.98 for HG 0.9 at
            // order 4; helper 55), pdf = (1 − α) pdf_warp + α/(4π).
            const Vec2 u = rng.uniform2();
            const Vec3 w =
                rng.uniform() < generalAlpha ? sampleUniformSphere(u) : s.warp(u).direction();
            row(w, phase.eval(z, w),
                (1 - generalAlpha) * s.pdf(w) + generalAlpha * uniformSpherePdf());
        }
    });
    // The quadrature, the clamped bins and the defensive share are the zonal sampler's.
    if (!general)
        std::fprintf(stderr,
                     " (E[(p/pdf)^2] by quadrature %.6g); clamped bins %.4g%%, defensive share "
                     "%.4g",
                     sh.weightSecondMoment(), 100 * sh.sampler().clampedFraction(),
                     sh.defensiveFraction());
    else
        std::fprintf(stderr, "; defensive share %.4g", generalAlpha);
    std::fprintf(stderr, "\n");
    return 0;
}

/// The options of both subcommands; `general`: the command has --sampler general, whose depths
/// --depth's help names too (phase fit's named a sampler it does not have; helper 122).
void commonOptions(CLI::App* c, PhaseArgs& a, bool general) {
    c->add_option("spec", a.spec,
                  "Phase function: JSON as in a scene (its SH keys are used), or short form such "
                  "as hg:g=0.9, rayleigh, tabulated:file=mie.csv")
        ->required();
    c->add_option("--order", a.order, "Number of SH bands (l < order), or auto")
        ->check(CLI::Validator(
            [](std::string& v) -> std::string {
                if (v == "auto") return "";
                return integerIn(1, 256)(v);
            },
            "integer in [1, 256] or auto", "order"))
        ->default_str("the spec's order, else auto");
    c->add_option("--tolerance", a.tolerance, "Relative L2 error that --order auto must reach")
        ->check(numberIn(1e-9, 1))
        ->default_str("the spec's tolerance, else 0.01");
    c->add_option("--window", a.window, "Ringing window: auto, none, hann or lanczos")
        ->check(CLI::IsMember({"auto", "none", "hann", "lanczos"}))
        ->default_str("the spec's window, else auto");
    c->add_option("--evaluate", a.evaluate,
                  "sh: the fit is the phase function (weight 1); exact: the function itself")
        ->check(CLI::IsMember({"sh", "exact"}))
        ->default_str("the spec's evaluate, else sh");
    c->add_option("--depth", a.depth,
                  general ? "Warp depth: 2^depth z-bins (zonal sampler, 4..22; general sampler, "
                            "<= 10)"
                          : "Warp depth of the zonal sampler: 2^depth z-bins, 4..22")
        ->transform(integerIn(4, 22))
        ->default_str(general ? "the spec's sh_depth, else 16 (general: 10)"
                              : "the spec's sh_depth, else 16");
}

}  // namespace

void addPhaseCommand(CLI::App& app, std::function<int()>& run) {
    auto a = std::make_shared<PhaseArgs>();
    CLI::App* phase =
        app.add_subcommand("phase", "Zonal SH fits of phase functions and their samples");
    phase->require_subcommand(1);
    CLI::App* fit = phase->add_subcommand(
        "fit", "Print the zonal SH fit, its error and the sampler's weight moments");
    commonOptions(fit, *a, false);
    fit->add_flag("--json", a->json, "JSON output");
    fit->callback([&run, a] { run = [a] { return runFit(*a); }; });

    CLI::App* sample = phase->add_subcommand(
        "sample", "Sample directions around +z as a render would (CSV) and report the weights");
    commonOptions(sample, *a, true);
    sample->add_option("--count", a->count, "Number of samples")
        ->transform(integerIn(1, 1LL << 32));
    sample->add_option("--seed", a->seed, "Random seed")->transform(integerIn(0, kMaxSeed));
    // (named --output in errors, as every other command's output: helper 96)
    sample->add_option("-o,--output,--out", a->out, "Output CSV (x,y,z,pdf,weight)")
        ->required()
        ->check(nonEmptyName())
        ->check(outputNamed(".csv", "phase sample writes CSV"));
    sample
        ->add_option("--sampler", a->sampler,
                     "zonal (the renderer's SH sampler: 1D warp in z, uniform phi, defensive "
                     "share), general (2D hierarchical warp of the fit, 1D-table mode) or "
                     "analytic (the phase function's own sampler, \"sampling\": \"analytic\")")
        ->check(CLI::IsMember({"zonal", "general", "analytic"}));
    sample->callback([&run, a] { run = [a] { return runSample(*a); }; });
}

}  // namespace shvol::app
