#include "shvol/render/film.h"

#include <algorithm>

namespace shvol {

Image Film::image() const {
    Image img(width, height);
    for (size_t i = 0; i < pixels(); ++i)
        for (int c = 0; c < 3; ++c)
            img.rgb[3 * i + c] = count[i] ? float(sum[3 * i + c] / count[i]) : 0.f;
    return img;
}

uint32_t Film::minCount() const {
    return count.empty() ? 0 : *std::min_element(count.begin(), count.end());
}

uint32_t Film::maxCount() const {
    return count.empty() ? 0 : *std::max_element(count.begin(), count.end());
}

}  // namespace shvol
