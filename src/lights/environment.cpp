#include "shvol/lights/environment.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <mutex>
#include <vector>

#include "shvol/core/error.h"
#include "shvol/sampling/warp.h"

namespace shvol {

Environment Environment::constant(const Spectrum& L, bool lowerHemisphereBlack) {
    Environment e;
    e.L_ = L;
    e.lowerBlack_ = lowerHemisphereBlack;
    e.black_ = !(L.maxCoeff() > 0);
    e.brightest_ = std::max(0.0, L.maxCoeff());
    return e;
}

namespace {
/// The part of row y (of H) above the horizon, where lowerHemisphereBlack leaves only that seen:
/// 0 for the rows below it, ½ for the middle row of an odd height, which straddles it (counted
/// exactly: the float θ's put 10⁻¹⁶ of row H/2 of 142 even heights up to 4096 above it; review).
double rowSeen(int y, int H, bool lowerHemisphereBlack) {
    if (!lowerHemisphereBlack) return 1;
    return 2 * y + 1 < H ? 1.0 : 2 * y + 1 == H ? 0.5 : 0.0;
}
}  // namespace

Environment Environment::image(Image img, double scale, double rotationDegrees,
                               bool lowerHemisphereBlack, LatLongMapping mapping) {
    if (img.width <= 0 || img.height <= 0 || img.rgb.size() != size_t(3) * img.width * img.height)
        fail("", "environment", "the environment image is empty or malformed");
    Environment e;
    e.lowerBlack_ = lowerHemisphereBlack;
    e.scale_ = scale;
    e.rotation_ = rotationDegrees * Pi / 180.0;
    e.mapping_ = mapping;
    const int W = img.width, H = img.height;
    const int rows = lowerHemisphereBlack ? (H + 1) / 2 : H;  // (those with a part seen)
    e.texels_ = std::make_shared<LazyTexels>();
    e.peak_ = std::make_shared<LazyPeak>();
    // Judged by the pixels seen (a sky lit only below the horizon is black, one uniform above it
    // uniform; review).
    const auto seen = img.rgb.begin(), seenEnd = img.rgb.begin() + size_t(3) * W * rows;
    for (auto v = seen + 3; v < seenEnd && e.uniform_; ++v)
        e.uniform_ = *v == seen[(v - seen) % 3];  // (every pixel the first)
    e.black_ = !(scale > 0) || std::all_of(seen, seenEnd, [](float v) { return v <= 0; });
    e.brightest_ = seen == seenEnd ? 0.0 : double(*std::max_element(seen, seenEnd));
    double power = 0, moment = 0;  // ∫ Y dω, ∫ Y² dω over the directions seen
    for (int y = 0; y < rows; ++y) {
        const double omega = TwoPi / W * (std::cos(Pi * y / H) - std::cos(Pi * (y + 1) / H)) *
                             rowSeen(y, H, lowerHemisphereBlack);
        double rowPower = 0, rowMoment = 0;
        for (int x = 0; x < W; ++x) {
            const double Y = luminance(img.at(x, y));
            rowPower += Y, rowMoment += Y * Y;
        }
        power += rowPower * omega, moment += rowMoment * omega;
    }
    // Over the whole sphere, also below a black horizon: phase sampling draws there too.
    if (power > 0 && moment > 0) e.secondMomentRatio_ = FourPi * moment / (power * power);
    e.image_ = std::make_shared<const Image>(std::move(img));
    return e;
}

struct Environment::LazyTexels {
    std::mutex building;
    std::atomic<const TexelSampler*> built{nullptr};
    std::unique_ptr<const TexelSampler> sampler;
};

const TexelSampler& Environment::texels() const {
    if (const TexelSampler* t = texels_->built.load(std::memory_order_acquire)) return *t;
    const std::lock_guard<std::mutex> lock(texels_->building);
    if (!texels_->sampler) {
        const Image& img = *image_;
        const int W = img.width, H = img.height;
        std::vector<double> weights(size_t(W) * H);
        for (int y = 0; y < H; ++y) {
            const double sinTheta = std::sin(Pi * (y + 0.5) / H),
                         above = rowSeen(y, H, lowerBlack_);
            for (int x = 0; x < W; ++x)
                weights[size_t(y) * W + x] = luminance(img.at(x, y)) * sinTheta * above;
        }
        texels_->sampler =
            std::make_unique<const TexelSampler>(weights.data(), img.rgb.data(), W, H);
        texels_->built.store(texels_->sampler.get(), std::memory_order_release);
    }
    return *texels_->sampler;
}

Vec2 Environment::toUv(const Vec3& w, double* sinTheta) const {
    const double cosTheta = std::clamp(w.z(), -1.0, 1.0);
    *sinTheta = safeSqrt(1 - cosTheta * cosTheta);
    return {latLongU(mapping_, sphericalPhi(w) - rotation_), std::acos(cosTheta) * InvPi};
}

Spectrum Environment::texelRadiance(const Spectrum& rgb, const Vec3& w) const {
    if (lowerBlack_ && w.z() < 0) return Spectrum::Zero();
    return scale_ * rgb;
}

Spectrum Environment::Le(const Vec3& dir) const {
    if (!image_) return lowerBlack_ && dir.z() < 0 ? Spectrum::Zero() : L_;
    const Vec3 w = dir.normalized();
    double sinTheta;
    const Vec2 uv = toUv(w, &sinTheta);
    return texelRadiance(image_->at(std::clamp(int(uv[0] * image_->width), 0, image_->width - 1),
                                    std::clamp(int(uv[1] * image_->height), 0, image_->height - 1)),
                         w);
}

LightSample Environment::sample(const Vec2& u) const {
    if (!image_) {
        const Vec3 w = lowerBlack_ ? sampleUniformHemisphere(u) : sampleUniformSphere(u);
        return {w, L_, lowerBlack_ ? uniformHemispherePdf() : uniformSpherePdf()};
    }
    const TexelSampler& texels = this->texels();
    if (!(texels.integral() > 0)) return {Vec3(0, 0, 1), Spectrum::Zero(), 0.0};
    const TexelSampler::Draw d = texels.sample(u);
    const double theta = Pi * d.uv[1], phi = latLongPhi(mapping_, d.uv[0]) + rotation_;
    const Vec2 csTheta = cosSin(theta), csPhi = cosSin(phi);
    const double sinTheta = csTheta.y();
    const Vec3 w(sinTheta * csPhi.x(), sinTheta * csPhi.y(), csTheta.x());
    // (A NaN pdf goes on, for the path tracer to count: InvalidDraws.)
    if (!(sinTheta > 0) || d.pdf <= 0) return {w, Spectrum::Zero(), 0.0};
    // The radiance of the texel drawn, from its sampling record (the one Le(w) finds, without the
    // round trip through w's angles or another read of the image).
    return {w, texelRadiance(d.rgb, w), d.pdf / (2 * Pi * Pi * sinTheta)};
}

double Environment::pdf(const Vec3& dir) const {
    if (!image_) {
        if (lowerBlack_) return dir.z() >= 0 ? uniformHemispherePdf() : 0.0;
        return uniformSpherePdf();
    }
    const TexelSampler& texels = this->texels();
    if (!(texels.integral() > 0)) return 0.0;
    double sinTheta;
    const Vec2 uv = toUv(dir.normalized(), &sinTheta);
    if (!(sinTheta > 0)) return 0.0;
    return texels.pdf(uv) / (2 * Pi * Pi * sinTheta);
}

struct Environment::LazyPeak {
    std::once_flag once;
    Peak value;
};

Environment::Peak Environment::peak() const {
    if (!peak_) return computePeak();
    std::call_once(peak_->once, [&] { peak_->value = computePeak(); });
    return peak_->value;
}

bool Environment::hasSun() const {
    const Peak p = peak();
    return p.solidAngle < kSunSolidAngle * (lowerBlack_ ? TwoPi : FourPi) &&
           p.powerShare >= kSunShare;
}

Environment::Peak Environment::computePeak() const {
    if (black_) return {};
    const double seen = lowerBlack_ ? TwoPi : FourPi;
    if (!image_) return {seen / 2, 0.5, kSunSolidAngle};
    // Each texel's luminance Y and solid angle seen, (2π/W)·(cos θ0 − cos θ1) times the part of
    // its row above the horizon (as the sampling weights take it), binned by Y, 64 bins an octave
    // below the brightest (the last bin holds everything 64 octaves down): a sort of every texel
    // would take 2 GB for a sky 16384 texels wide (helper 163).
    const int W = image_->width, H = image_->height;
    const auto forEachTexel = [&](auto&& f) {
        for (int y = 0; y < H; ++y) {
            const double omega = TwoPi / W * (std::cos(Pi * y / H) - std::cos(Pi * (y + 1) / H)) *
                                 rowSeen(y, H, lowerBlack_);
            if (omega <= 0) continue;
            for (int x = 0; x < W; ++x)
                if (const double Y = luminance(image_->at(x, y)); Y > 0) f(Y, omega);
        }
    };
    double brightest = 0;
    forEachTexel([&](double Y, double) { brightest = std::max(brightest, Y); });
    constexpr int kPerOctave = 64, kBins = 64 * kPerOctave;
    struct Bin {
        double omega = 0, power = 0, moment = 0;  // ∫ dω, ∫ Y dω, ∫ Y² dω
    };
    std::vector<Bin> bins(kBins);
    double power = 0, moment = 0;
    forEachTexel([&](double Y, double omega) {
        const double below = std::log2(brightest / Y) * kPerOctave;
        Bin& b = bins[size_t(std::min(double(kBins - 1), std::floor(below)))];
        b.omega += omega, b.power += Y * omega, b.moment += Y * Y * omega;
        power += Y * omega, moment += Y * Y * omega;
    });
    if (!(power > 0)) return {};
    // The brightest first, down to half of ∫ Y² dω, the last bin in part (its texels of about
    // equal Y hold its moment in proportion to their solid angle).
    Peak p;
    double held = 0, need = moment / 2;
    for (const Bin& b : bins) {
        if (!(b.moment > 0)) continue;
        const double part = std::min(1.0, need / b.moment);
        p.solidAngle += part * b.omega, held += part * b.power;
        if ((need -= b.moment) <= 0) break;
    }
    p.powerShare = std::min(1.0, held / power);
    // The brightest directions that make up kSunSolidAngle of the sky seen, and their light.
    double omegaLeft = kSunSolidAngle * (lowerBlack_ ? TwoPi : FourPi), brightestPower = 0;
    for (const Bin& b : bins) {
        if (!(b.omega > 0)) continue;
        const double part = std::min(1.0, omegaLeft / b.omega);
        brightestPower += part * b.power;
        if ((omegaLeft -= b.omega) <= 0) break;
    }
    p.brightestShare = std::min(1.0, brightestPower / power);
    return p;
}

SkyHierarchy Environment::skyHierarchy(size_t waveletCoefficients) const {
    if (!image_) return SkyHierarchy::constant(luminance(L_), lowerBlack_);
    SkyHierarchy::LatLongSource src;
    src.image = image_.get();
    src.mapping = mapping_;
    src.scale = scale_;
    src.rotation = rotation_;
    src.lowerHemisphereBlack = lowerBlack_;
    return SkyHierarchy::fromLatLong(src, -1, waveletCoefficients);
}

}  // namespace shvol
