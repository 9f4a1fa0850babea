#include "shvol/sampling/texel_sampler.h"

#include <algorithm>
#include <cmath>

#include "shvol/core/error.h"
#include "shvol/sampling/alias_table.h"

namespace shvol {

namespace {
/// The weights as the sampler counts them: ≤ 0, NaN and infinite ones are 0.
std::vector<double> cleaned(const double* w, int width, int height) {
    if (width <= 0 || height <= 0) fail("", "texel sampler", "needs at least one texel");
    std::vector<double> c(size_t(width) * height);
    for (size_t i = 0; i < c.size(); ++i) c[i] = w[i] > 0 && std::isfinite(w[i]) ? w[i] : 0.0;
    return c;
}

std::vector<double> rowSums(const std::vector<double>& w, int width, int height) {
    std::vector<double> sums(size_t(height), 0.0);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) sums[size_t(y)] += w[size_t(y) * width + x];
    return sums;
}
}  // namespace

TexelSampler::TexelSampler(const double* weights, const float* rgb, int width, int height)
    : TexelSampler(cleaned(weights, width, height), rgb, width, height) {}

TexelSampler::TexelSampler(const std::vector<double>& w, const float* rgb, int width, int height)
    : width_(width), height_(height), marginal_(rowSums(w, width, height).data(), height) {
    records_.resize(w.size());
    for (int y = 0; y < height; ++y) {
        const size_t row = size_t(y) * width;
        const std::vector<AliasColumn> table = buildAliasTable(w.data() + row, width);
        for (int x = 0; x < width; ++x) {
            const size_t t = row + size_t(x);
            records_[t] = {table[size_t(x)].q,
                           w[t],
                           table[size_t(x)].alias,
                           {rgb[3 * t], rgb[3 * t + 1], rgb[3 * t + 2]}};
        }
    }
    if (integral() > 0) invIntegral_ = 1 / integral();
}

TexelSampler::Draw TexelSampler::sample(const Vec2& u) const {
    if (!(invIntegral_ > 0)) return {Vec2(0.5, 0.5), 0, 0, 0.0, Spectrum::Zero()};
    int y = 0;
    const double v = marginal_.sampleContinuous(u[1], nullptr, &y);
    const Record* row = records_.data() + size_t(y) * width_;
    const AliasDraw d = aliasDraw(u[0], width_, [row](int j) {
        return AliasColumn{row[j].q, row[j].alias};
    });
    const Record& r = row[d.bin];
    return {Vec2(pointInBin(d.bin, d.du, width_), v), d.bin, y, r.weight * invIntegral_,
            Spectrum(r.rgb[0], r.rgb[1], r.rgb[2])};
}

double TexelSampler::pdf(const Vec2& uv) const {
    const int x = std::clamp(int(uv[0] * width_), 0, width_ - 1);
    const int y = std::clamp(int(uv[1] * height_), 0, height_ - 1);
    return records_[size_t(y) * width_ + x].weight * invIntegral_;
}

}  // namespace shvol
