// Output buffers of one MlStereo / PyramidStereo run in the stereo tests: disparity, sigma
// and reason of a W x H image, the stats and the Status, and the DisparityOutput over them.
#pragma once

#include <cstdint>
#include <vector>

#include "vtm/stereo/ml_stereo.hpp"

namespace vtm::stereo {

template <std::int32_t W, std::int32_t H>
struct StereoBuffers {
    std::vector<std::int16_t> disparity = std::vector<std::int16_t>(W * H);
    std::vector<float> sigma = std::vector<float>(W * H);
    std::vector<std::uint8_t> reason = std::vector<std::uint8_t>(W * H);
    StereoStats stats{};
    Status status{};
    DisparityOutput out() {
        return DisparityOutput{ImageView<std::int16_t>(disparity.data(), W, H), ImageView<float>(sigma.data(), W, H),
                               ImageView<std::uint8_t>(reason.data(), W, H)};
    }
};

}  // namespace vtm::stereo
