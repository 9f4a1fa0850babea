#include "shvol/io/procedural.h"

#include "shvol/core/rng.h"

namespace shvol {

namespace {
double fade(double t) {
    return t * t * t * (t * (t * 6 - 15) + 10);
}
Vec3 gradient(int64_t i, int64_t j, int64_t k, uint64_t seed) {
    uint64_t h =
        mix64(seed ^ mix64(uint64_t(i) * 0x9E3779B1ULL ^
                           mix64(uint64_t(j) * 0x85EBCA77ULL ^ uint64_t(k) * 0xC2B2AE3DULL)));
    // A direction from two 26-bit uniforms.
    const double u = double(h & 0x3FFFFFF) / double(1 << 26), v = double(h >> 38) / double(1 << 26);
    return sphericalDirection(1 - 2 * u, TwoPi * v);
}
}  // namespace

double gradientNoise(const Vec3& p, uint64_t seed) {
    const Vec3 f = p.array().floor();
    const int64_t i = int64_t(f.x()), j = int64_t(f.y()), k = int64_t(f.z());
    const Vec3 d = p - f;
    double c[2][2][2];
    for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
            for (int e = 0; e < 2; ++e)
                c[a][b][e] = gradient(i + a, j + b, k + e, seed).dot(d - Vec3(a, b, e));
    const double u = fade(d.x()), v = fade(d.y()), w = fade(d.z());
    auto lerp = [](double t, double a, double b) { return a + t * (b - a); };
    // Gradient noise in 3D is bounded by √3/2; scale to about [−1, 1].
    return 2 / std::sqrt(3.0) *
           lerp(w, lerp(v, lerp(u, c[0][0][0], c[1][0][0]), lerp(u, c[0][1][0], c[1][1][0])),
                lerp(v, lerp(u, c[0][0][1], c[1][0][1]), lerp(u, c[0][1][1], c[1][1][1])));
}

double fbm(const Vec3& p, uint64_t seed, int octaves, double lacunarity, double gain) {
    double sum = 0, amp = 1, freq = 1;
    for (int o = 0; o < octaves; ++o) {
        sum += amp * gradientNoise(freq * p, seed + o);
        amp *= gain;
        freq *= lacunarity;
    }
    return sum;
}

double cloudDensity(const Vec3& p, const CloudParams& c) {
    // Flattened ellipsoid: wider than tall, with a flatter base.
    const Vec3 q(p.x() / 0.48, p.y() / 0.48, p.z() / (p.z() < 0 ? 0.28 : 0.42));
    const double r = q.norm();
    if (r >= 1) return 0;
    const double falloff = r * r * r;
    const double n = fbm(c.frequency * p, c.seed, c.octaves);
    return std::clamp((0.5 + 0.5 * n + c.coverage - falloff) * c.sharpness, 0.0, 1.0);
}

double sphereDensity(const Vec3& p, double radius, double edge) {
    const double d = p.norm() - radius;
    return std::clamp(0.5 - d / std::max(edge, 1e-12), 0.0, 1.0);
}

Image makeSky(const SkyParams& s) {
    Image img(s.width, s.height);
    const double el = s.sunElevationDegrees * Pi / 180, az = s.sunAzimuthDegrees * Pi / 180;
    const Vec3 sun = sphericalDirection(std::sin(el), az);
    const double cosSun = std::cos(s.sunAngularRadius);
    for (int y = 0; y < s.height; ++y)
        for (int x = 0; x < s.width; ++x) {
            const double theta = Pi * (y + 0.5) / s.height, phi = TwoPi * (x + 0.5) / s.width;
            const Vec3 w = sphericalDirection(std::cos(theta), phi);
            Spectrum L;
            if (w.z() >= 0) {
                const double t = std::pow(1 - w.z(), 3);
                L = s.zenith * (1 - t) + s.horizon * t;
                // A soft glow around the sun.
                L += Spectrum(1.0, 0.9, 0.7) * 0.8 * std::pow(std::max(0.0, w.dot(sun)), 32);
            } else {
                L = s.ground;
            }
            if (w.dot(sun) >= cosSun) L = Spectrum(1.0, 0.95, 0.85) * s.sunRadiance;
            img.set(x, y, L);
        }
    return img;
}

}  // namespace shvol
