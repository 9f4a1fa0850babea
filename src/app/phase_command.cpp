// shvol phase fit | sample: the zonal SH fit of a phase function and samples from its SH sampler.
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
#include "shvol/phase/zonal_fit.h"
#include "shvol/sampling/sh_sampler.h"
#include "shvol/sampling/zonal_sh_sampler.h"

namespace shvol::app {

namespace {

struct PhaseArgs {
    std::string spec, window = "hann", out, sampler = "zonal";
    int order = 16, depth = 16;
    long long count = 10000;
    unsigned long long seed = 1;
    bool json = false;
};

/// The phase function a spec names; an SH-sampled spec contributes its underlying function.
PhaseFunction basePhase(const std::string& spec) {
    const PhaseFunction p = parsePhaseSpec(spec, "");
    if (const auto* sh = std::get_if<SHSampledPhase>(&p.variant())) return sh->base();
    return p;
}

ZonalFit fitOf(const PhaseArgs& a) {
    const PhaseFunction p = basePhase(a.spec);
    return fitZonal([&](double mu) { return p.eval(Vec3(0, 0, 1), sphericalDirection(mu, 0)); },
                    a.order, shWindowFromName(a.window));
}

int runFit(const PhaseArgs& a) {
    const ZonalFit f = fitOf(a);
    if (a.json) {
        nlohmann::json j;
        j["spec"] = a.spec;
        j["order"] = a.order;
        j["window"] = shWindowName(f.window);
        j["coefficients"] = f.p;
        j["energy_fraction"] = f.energyFraction;
        j["l2_error"] = f.l2Error;
        j["relative_l2_error"] = f.relativeL2Error;
        j["max_error"] = f.maxError;
        j["min_value"] = f.minValue;
        j["peak_value"] = f.peakValue;
        std::printf("%s\n", j.dump(2).c_str());
        return 0;
    }
    std::printf("# zonal SH fit of %s, order %d, window %s: p(mu) ~ sum_l p_l y_l^0(mu)\n",
                a.spec.c_str(), a.order, shWindowName(f.window));
    std::printf(
        "energy_fraction    %.10g\nl2_error           %.6g\nrelative_l2_error  %.6g\n"
        "max_error          %.6g\nmin_value          %.6g\npeak_value         %.6g\n",
        f.energyFraction, f.l2Error, f.relativeL2Error, f.maxError, f.minValue, f.peakValue);
    std::printf("l,p_l\n");
    for (int l = 0; l < a.order; ++l) std::printf("%d,%.17g\n", l, f.p[l]);
    return 0;
}

int runSample(const PhaseArgs& a) {
    if (a.sampler == "general" && a.order > 128)
        fail("", "--order", "the general sampler supports orders up to 128");
    const ZonalFit f = fitOf(a);
    writeAtomically(a.out, [&](const std::string& tmp) {
        std::ofstream csv(tmp);
        csv << std::setprecision(17) << "x,y,z,pdf\n";
        Rng rng(a.seed, 0);
        auto row = [&](const Vec3& w, double pdf) {
            csv << w.x() << ',' << w.y() << ',' << w.z() << ',' << pdf << '\n';
        };
        if (a.sampler == "zonal") {
            const ZonalSHSampler s(f.p, a.depth);
            if (!(s.positiveMass() > 0)) fail(a.spec, "", "the SH fit has no positive mass");
            for (long long i = 0; i < a.count; ++i) {
                const auto x = s.sampleLocal(rng.uniform2());
                row(sphericalDirection(x.cosTheta, x.phi), x.pdf);
            }
        } else {
            std::vector<double> c(size_t(a.order) * a.order, 0.0);
            for (int l = 0; l < a.order; ++l) c[size_t(l) * (l + 1)] = f.p[l];
            const SHSampler s(a.order, c.data(), SHSampler::Mode::Tables, std::min(a.depth, 10));
            for (long long i = 0; i < a.count; ++i) {
                const WarpSample x = s.warp(rng.uniform2());
                row(x.direction(), x.pdf);
            }
        }
        csv.close();
        if (!csv) fail(a.out, "", "cannot write file");
    });
    std::fprintf(stderr, "wrote %lld samples to %s\n", a.count, a.out.c_str());
    return 0;
}

void commonOptions(CLI::App* c, PhaseArgs& a) {
    c->add_option("spec", a.spec,
                  "Phase function: JSON as in a scene, or short form such as hg:g=0.9, rayleigh, "
                  "tabulated:file=mie.csv")
        ->required();
    c->add_option("--order", a.order, "Number of SH bands (l < order)")
        ->required()
        ->check(integerIn(1, 256));
    c->add_option("--window", a.window, "Ringing window: none, hann or lanczos")
        ->check(CLI::IsMember({"none", "hann", "lanczos"}));
}

}  // namespace

void addPhaseCommand(CLI::App& app, std::function<int()>& run) {
    auto a = std::make_shared<PhaseArgs>();
    CLI::App* phase =
        app.add_subcommand("phase", "Zonal SH fits of phase functions and their samples");
    phase->require_subcommand(1);
    CLI::App* fit = phase->add_subcommand("fit", "Print the zonal SH coefficients and fit quality");
    commonOptions(fit, *a);
    fit->add_flag("--json", a->json, "JSON output");
    fit->callback([&run, a] { run = [a] { return runFit(*a); }; });

    CLI::App* sample =
        phase->add_subcommand("sample", "Sample directions around +z with the SH sampler (CSV)");
    commonOptions(sample, *a);
    sample->add_option("--count", a->count, "Number of samples")->check(integerIn(1, 1LL << 32));
    sample->add_option("--seed", a->seed, "Random seed");
    sample->add_option("--out", a->out, "Output CSV (x,y,z,pdf)")->required();
    sample
        ->add_option("--sampler", a->sampler,
                     "zonal (1D warp in z, uniform phi) or general (2D hierarchical warp, "
                     "1D-table mode)")
        ->check(CLI::IsMember({"zonal", "general"}));
    sample->add_option("--depth", a->depth, "Warp depth (zonal: 2^depth z-bins; general: <= 10)")
        ->check(integerIn(4, 22));
    sample->callback([&run, a] { run = [a] { return runSample(*a); }; });
}

}  // namespace shvol::app
