// shvol diff: error metrics between two EXR images (for convergence and validation studies).
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "shvol/core/error.h"
#include "shvol/io/exr.h"

namespace shvol::app {

namespace {

struct DiffArgs {
    std::string image, reference;
    bool json = false;
    /// Thresholds (--max-rmse, --max-relative-rmse, --max-abs-error); negative: not given.
    double maxRmse = -1, maxRelRmse = -1, maxAbs = -1;
    bool anyThreshold() const { return maxRmse >= 0 || maxRelRmse >= 0 || maxAbs >= 0; }
};

}  // namespace

void addDiffCommand(CLI::App& app, std::function<int()>& run) {
    auto args = std::make_shared<DiffArgs>();
    CLI::App* c = app.add_subcommand(
        "diff", "Compare an image with a reference: RMSE, relative RMSE, mean and max error");
    c->add_option("image", args->image, "Image (EXR)")->required()->check(nonEmptyName());
    c->add_option("reference", args->reference, "Reference image (EXR)")
        ->required()
        ->check(nonEmptyName());
    c->add_flag("--json", args->json, "JSON output");
    const auto threshold = [&](const char* name, double& v, const char* metric) {
        c->add_option(name, v,
                      std::string("Exit with code 2 when ") + metric +
                          " is above this (or an infinite value is not matched in the other image)")
            ->check(numberIn(0, 1e300))
            ->default_str("none");
    };
    threshold("--max-rmse", args->maxRmse, "rmse");
    threshold("--max-relative-rmse", args->maxRelRmse, "relative_rmse");
    threshold("--max-abs-error", args->maxAbs, "max_abs_error");
    c->callback([&run, args] {
        run = [args] {
            // Any value but NaN: shvol's own standard-error images hold +inf (unknown), and
            // another renderer's filter can ring below 0.
            const Image a = readExr(args->image, ExrValues::Compared),
                        b = readExr(args->reference, ExrValues::Compared);
            if (a.width != b.width || a.height != b.height)
                fail(args->image, "",
                     "size " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                         " differs from the reference's " + std::to_string(b.width) + "x" +
                         std::to_string(b.height));
            // Over the channel values finite in both images: RMSE = √(mean (a−b)²); relative
            // RMSE = √(mean ((a−b)/(|b|+0.01))²) (the 0.01 keeps dark reference pixels from
            // dominating); mean of a and b. Values infinite in either image are counted apart.
            // Of those, the ones the other image does not match (finite there, or infinite of the
            // other sign) are a difference no metric shows, counted again apart.
            double se = 0, rel = 0, maxAbs = 0, meanA = 0, meanB = 0;
            size_t n = 0, infinite = 0, mismatched = 0;
            for (size_t i = 0; i < a.rgb.size(); ++i) {
                if (!std::isfinite(a.rgb[i]) || !std::isfinite(b.rgb[i])) {
                    ++infinite;
                    mismatched += a.rgb[i] != b.rgb[i];
                    continue;
                }
                const double d = double(a.rgb[i]) - b.rgb[i];
                se += d * d;
                rel += sqr(d / (std::abs(b.rgb[i]) + 0.01));
                maxAbs = std::max(maxAbs, std::abs(d));
                meanA += a.rgb[i], meanB += b.rgb[i], ++n;
            }
            if (n == 0)
                fail(args->image, "",
                     "no channel value is finite in both images: nothing to compare");
            const double rmse = std::sqrt(se / double(n)), relRmse = std::sqrt(rel / double(n));
            meanA /= double(n), meanB /= double(n);
            if (args->json) {
                nlohmann::json j{{"rmse", rmse},
                                 {"relative_rmse", relRmse},
                                 {"max_abs_error", maxAbs},
                                 {"mean", meanA},
                                 {"reference_mean", meanB},
                                 {"infinite_values", infinite},
                                 {"infinite_mismatched", mismatched}};
                std::printf("%s\n", j.dump(2).c_str());
            } else {
                std::printf(
                    "rmse %.6g\nrelative_rmse %.6g\nmax_abs_error %.6g\nmean %.6g\n"
                    "reference_mean %.6g\ninfinite_values %zu\ninfinite_mismatched %zu\n",
                    rmse, relRmse, maxAbs, meanA, meanB, infinite, mismatched);
            }
            if (!args->anyThreshold()) return 0;
            // One line on stderr naming every threshold passed, and exit code 2 (1 is an error).
            std::string above;
            const auto check = [&](const char* metric, double v, double limit, const char* opt) {
                if (limit >= 0 && v > limit) {
                    // Six digits, or as many more as tell the two apart (a float image's
                    // 0.30000001 would read "0.3 is above 0.3").
                    int digits = 6;
                    const auto text = [&](double x) {
                        char b[40];
                        std::snprintf(b, sizeof b, "%.*g", digits, x);
                        return std::string(b);
                    };
                    while (digits < 17 && text(v) == text(limit)) ++digits;
                    above += (above.empty() ? "" : "; ") + std::string(metric) + " " + text(v) +
                             " is above " + opt + " " + text(limit);
                }
            };
            check("rmse", rmse, args->maxRmse, "--max-rmse");
            check("relative_rmse", relRmse, args->maxRelRmse, "--max-relative-rmse");
            check("max_abs_error", maxAbs, args->maxAbs, "--max-abs-error");
            if (mismatched > 0)
                above += (above.empty() ? "" : "; ") + std::to_string(mismatched) +
                         (mismatched == 1 ? " infinite value is" : " infinite values are") +
                         " not matched in the other image (finite there, or of the other sign)";
            if (above.empty()) return 0;
            std::fprintf(stderr, "shvol: diff: %s: %s\n", args->image.c_str(), above.c_str());
            return 2;
        };
    });
}

}  // namespace shvol::app
