// shvol diff: error metrics between two EXR images (for convergence and validation studies).
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "shvol/core/error.h"
#include "shvol/io/exr.h"

namespace shvol::app {

void addDiffCommand(CLI::App& app, std::function<int()>& run) {
    auto files = std::make_shared<std::pair<std::string, std::string>>();
    auto json = std::make_shared<bool>(false);
    CLI::App* c = app.add_subcommand(
        "diff", "Compare an image with a reference: RMSE, relative RMSE, mean and max error");
    c->add_option("image", files->first, "Image (EXR)")->required();
    c->add_option("reference", files->second, "Reference image (EXR)")->required();
    c->add_flag("--json", *json, "JSON output");
    c->callback([&run, files, json] {
        run = [files, json] {
            // Any value but NaN: shvol's own standard-error images hold +inf (unknown), and
            // another renderer's filter can ring below 0.
            const Image a = readExr(files->first, ExrValues::Compared),
                        b = readExr(files->second, ExrValues::Compared);
            if (a.width != b.width || a.height != b.height)
                fail(files->first, "",
                     "size " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                         " differs from the reference's " + std::to_string(b.width) + "x" +
                         std::to_string(b.height));
            // Over the channel values finite in both images: RMSE = √(mean (a−b)²); relative
            // RMSE = √(mean ((a−b)/(|b|+0.01))²) (the 0.01 keeps dark reference pixels from
            // dominating); mean of a and b. Values infinite in either image are counted apart.
            double se = 0, rel = 0, maxAbs = 0, meanA = 0, meanB = 0;
            size_t n = 0, infinite = 0;
            for (size_t i = 0; i < a.rgb.size(); ++i) {
                if (!std::isfinite(a.rgb[i]) || !std::isfinite(b.rgb[i])) {
                    ++infinite;
                    continue;
                }
                const double d = double(a.rgb[i]) - b.rgb[i];
                se += d * d;
                rel += sqr(d / (std::abs(b.rgb[i]) + 0.01));
                maxAbs = std::max(maxAbs, std::abs(d));
                meanA += a.rgb[i], meanB += b.rgb[i], ++n;
            }
            if (n == 0)
                fail(files->first, "",
                     "no channel value is finite in both images: nothing to compare");
            const double rmse = std::sqrt(se / double(n)), relRmse = std::sqrt(rel / double(n));
            meanA /= double(n), meanB /= double(n);
            if (*json) {
                nlohmann::json j{
                    {"rmse", rmse},  {"relative_rmse", relRmse}, {"max_abs_error", maxAbs},
                    {"mean", meanA}, {"reference_mean", meanB},  {"infinite_values", infinite}};
                std::printf("%s\n", j.dump(2).c_str());
            } else {
                std::printf(
                    "rmse %.6g\nrelative_rmse %.6g\nmax_abs_error %.6g\nmean %.6g\n"
                    "reference_mean %.6g\ninfinite_values %zu\n",
                    rmse, relRmse, maxAbs, meanA, meanB, infinite);
            }
            return 0;
        };
    });
}

}  // namespace shvol::app
