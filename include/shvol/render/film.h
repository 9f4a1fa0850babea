#pragma once
/// \file The accumulation buffer of a render: per pixel the sum of its sample values (double, in
/// sample order) and the number of samples taken. The image is sum / count per pixel, so a render
/// stopped at any moment gives each pixel the mean of the samples it has; a render continued
/// from a film adds sample i of every pixel after samples 0 … i−1, exactly as one uninterrupted
/// run does, so resuming reproduces the uninterrupted image bit for bit.
#include <cstdint>
#include <vector>

#include "shvol/core/image.h"

namespace shvol {

struct Film {
    int width = 0, height = 0;
    std::vector<double> sum;      ///< 3 per pixel
    std::vector<uint32_t> count;  ///< samples taken per pixel (dropped NaN/Inf samples count)
    std::vector<double> sumSq;    ///< 3 per pixel, sums of squares; empty unless asked for
    /// 1 per pixel: Σ y² over its finite samples' luminances y (Σ y is the luminance of `sum`,
    /// luminance being linear for the non-negative radiance a render's samples carry),
    /// the spread within the pixel that meanRelativeError() is made of; empty where unknown (a
    /// checkpoint written before 6 Dec).
    std::vector<double> luminanceSumSq;

    Film() = default;
    Film(int w, int h)
        : width(w),
          height(h),
          sum(size_t(3) * w * h, 0.0),
          count(size_t(w) * h, 0),
          luminanceSumSq(size_t(w) * h, 0.0) {}
    size_t pixels() const { return count.size(); }
    /// sum / count per pixel (0 where no sample was taken yet).
    Image image() const;
    /// Standard error of each pixel's mean per channel, √(s²/n) with s² = (Σx²/n − x̄²)·n/(n − 1)
    /// the unbiased sample variance, i.e. √((Σx²/n − x̄²)/(n − 1)), from the sample moments; +∞
    /// (unknown) where fewer than 2 samples were taken or Σx² overflowed. Needs sumSq.
    Image standardError() const;
    /// The relative standard error of the image's mean luminance, √(s²/n)/ȳ over its n samples,
    /// s² the pooled variance of the samples within a pixel, Σ_p Σ (y − ȳ_p)² / Σ_p (n_p − 1)
    /// (the spread between pixels is the picture, not noise: the variance of all samples was
    /// 1.18× too large on media/default.json; helper 87), or, where pixels of two samples or more
    /// hold less than a quarter of the samples' degrees of freedom (1 spp), that of all samples,
    /// which overstates it. Samples are taken as independent, which overstates a stratified
    /// render's error and leaves out what its samples share (radiance-cache records); a dropped
    /// (NaN) sample counts in n. Summed in pixel order from the film, so it depends on the seed
    /// and the samples only, never on the threads, the passes or a resume (it was summed per pass
    /// and thread before 6 Dec; helper 93). ∞ without light or where luminanceSumSq is unknown.
    double meanRelativeError() const;
    /// How many degrees of freedom meanRelativeError's pooled variance rests on: Satterthwaite's
    ///   ν = (Σ_p W_p)² / Σ_p (W_p² / d_p),  W_p = Σ (y − ȳ_p)² a pixel's sum of squares,
    /// with d_p = min(n_p − 1, max(1, (Σ y)² / Σ y²)), the pixel's effective number of samples
    /// (Kish's) in place of n_p − 1: a pixel whose sum one sample carries counts as one
    /// observation however many it took. Kish's count is of the sum, not of the deviations: a
    /// rare large sample over a background as bright as its deviation leaves it at n_p − 1, and ν
    /// misses that tail (one sample holding a pixel's whole variance, 16 spp: ν = 1.0, 1.3, 5.0
    /// and 15 over backgrounds of 0, 0.01, 0.1 and 1 times its deviation, 15 beyond; helpers 163,
    /// 166); only the pixels' third and fourth moments, which the film does not keep, would see it.
    /// The stated error is uncertain by a factor of about 1 ± √(2/ν), and under a heavy tail, where
    /// a few pixels' rare large samples hold the variance, ν is small (helper 162: below 10 in 93%
    /// of the renders of heavy-tailed scenes, in 0.6% of the others, all at 32×24 and 16 spp).
    /// Pixels whose W_p is within the rounding of its sums (k·10⁻¹³·Σy²) are left out. ∞ where
    /// meanRelativeError is taken over all samples (1 spp) or is unknown, or no pixel's samples
    /// spread. Summed in pixel order, as meanRelativeError.
    double meanRelativeErrorDof() const;
    uint32_t minCount() const;
    uint32_t maxCount() const;
};

}  // namespace shvol
