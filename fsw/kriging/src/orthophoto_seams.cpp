// measureSeamSteps: the orthophoto's grey steps across source borders and within one source.
#include "vtm/kriging/orthophoto.hpp"

namespace vtm::kriging {

SeamSteps measureSeamSteps(const ImageView<const std::uint8_t>& grey, const ImageView<const std::uint16_t>& source) noexcept {
    SeamSteps s;
    if (grey.width() != source.width() || grey.height() != source.height()) {
        return s;
    }
    double across = 0.0;
    double within = 0.0;
    for (std::int32_t r = 0; r < grey.height(); ++r) {
        const std::uint8_t* g = grey.row(r);
        const std::uint16_t* src = source.row(r);
        for (std::int32_t c = 0; c + 1 < grey.width(); ++c) {
            if (src[c] == kNoSource || src[c + 1] == kNoSource) {
                continue;
            }
            const int d = static_cast<int>(g[c]) - static_cast<int>(g[c + 1]);
            const double step = static_cast<double>(d < 0 ? -d : d);
            if (src[c] == src[c + 1]) {
                within += step;
                ++s.within_pairs;
            } else {
                across += step;
                ++s.across_pairs;
            }
        }
    }
    s.across_dn = s.across_pairs > 0 ? across / s.across_pairs : 0.0;
    s.within_dn = s.within_pairs > 0 ? within / s.within_pairs : 0.0;
    return s;
}

}  // namespace vtm::kriging
