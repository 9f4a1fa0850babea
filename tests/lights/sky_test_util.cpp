#include "sky_test_util.h"

#include "shvol/lights/latlong.h"

namespace shvol::test {

Image testSky(int W, const Vec3& sun, double sunRadius, double sunRadiance) {
    const int H = W / 2;
    Image img(W, H);
    const double cosSun = std::cos(sunRadius);
    constexpr int S = 8;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            Spectrum sum = Spectrum::Zero();
            for (int j = 0; j < S; ++j)
                for (int i = 0; i < S; ++i) {
                    const Vec3 w = latLongDirection(
                        LatLongMapping::Blender, (x + (i + 0.5) / S) / W, (y + (j + 0.5) / S) / H);
                    Spectrum L = w.z() >= 0 ? Spectrum(0.3 + 0.5 * (1 - w.z()), 0.5, 1.0)
                                            : Spectrum(0.1, 0.09, 0.08);
                    if (w.dot(sun) >= cosSun) L = Spectrum::Constant(sunRadiance);
                    sum += L;
                }
            img.set(x, y, sum / (S * S));
        }
    return img;
}

}  // namespace shvol::test
