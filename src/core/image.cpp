#include "shvol/core/image.h"

#include <cmath>
#include <limits>

namespace shvol {

ImageStatistics imageStatistics(const Image& image) {
    ImageStatistics st;
    Spectrum sum = Spectrum::Zero();
    Spectrum lo = Spectrum::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    long long count[3] = {0, 0, 0};
    for (size_t i = 0; i < image.rgb.size(); ++i) {
        const double v = image.rgb[i];
        const int c = int(i % 3);
        if (!std::isfinite(v)) {
            ++st.nonFinite;
            continue;
        }
        sum[c] += v, ++count[c];
        lo[c] = std::min(lo[c], v), hi[c] = std::max(hi[c], v);
    }
    for (int c = 0; c < 3; ++c)
        if (count[c] > 0)
            st.mean[c] = sum[c] / count[c], st.min[c] = lo[c], st.max[c] = hi[c];
        else
            st.mean[c] = st.min[c] = st.max[c] = std::numeric_limits<double>::quiet_NaN();
    return st;
}

}  // namespace shvol
