// The consumer of an installed VTM (tests/install/consumer/CMakeLists.txt): a smooth
// random texture and the same texture moved 7 px to the left, matched by the installed
// ML stereo; at least 90 % of the interior must come out at 7 +- 0.5 px. It also plans a
// wide-baseline request, so that vtm::app and everything it links are resolved.
// Exit 0 and one line "consumer: ..." when both hold; 1 with the reason otherwise.
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "vtm/app/wide_baseline_mapper.hpp"
#include "vtm/core/arena.hpp"
#include "vtm/core/random.hpp"
#include "vtm/stereo/ml_stereo.hpp"

namespace {

constexpr std::int32_t kW = 96;
constexpr std::int32_t kH = 64;
constexpr std::int32_t kShift = 7;

std::uint8_t left[kH][kW];
std::uint8_t right[kH][kW];
std::int16_t disparity[kH][kW];
std::byte pool[8U << 20U];
vtm::stereo::MlStereo stereo;

// Noise blurred by a 3 x 3 box, so that the texture is smooth at the pixel scale.
void makePair() {
    static double noise[kH][kW + kShift];
    vtm::Random rng(20261204U);
    for (auto& row : noise) {
        for (double& v : row) {
            v = rng.uniform01();
        }
    }
    for (std::int32_t y = 0; y < kH; ++y) {
        for (std::int32_t x = 0; x < kW + kShift; ++x) {
            double s = 0.0;
            for (std::int32_t dy = -1; dy <= 1; ++dy) {
                for (std::int32_t dx = -1; dx <= 1; ++dx) {
                    const std::int32_t yy = y + dy < 0 ? 0 : (y + dy >= kH ? kH - 1 : y + dy);
                    const std::int32_t xx = x + dx < 0 ? 0 : (x + dx >= kW + kShift ? kW + kShift - 1 : x + dx);
                    s += noise[yy][xx];
                }
            }
            const auto g = static_cast<std::uint8_t>(30.0 + 200.0 * s / 9.0);
            if (x < kW) {
                left[y][x] = g;  // left(x) = texture(x)
            }
            if (x >= kShift) {
                right[y][x - kShift] = g;  // right(x - 7) = texture(x): disparity 7
            }
        }
    }
}

}  // namespace

int main() {
    makePair();
    vtm::stereo::Config config;
    config.max_width = kW;
    config.max_height = kH;
    config.d_min = 0;
    config.d_max = 15;
    config.window = 9;
    vtm::Arena arena(pool, sizeof pool);
    const vtm::Status init = stereo.init(config, arena);
    if (!init.isOk()) {
        std::printf("consumer: stereo init failed: %s\n", init.reason());
        return 1;
    }
    const vtm::stereo::DisparityOutput out{vtm::ImageView<std::int16_t>(&disparity[0][0], kW, kH), {}, {}};
    const vtm::Status run = stereo.compute(vtm::ImageView<const std::uint8_t>(&left[0][0], kW, kH),
                                           vtm::ImageView<const std::uint8_t>(&right[0][0], kW, kH), out);
    if (!run.isOk()) {
        std::printf("consumer: stereo failed: %s\n", run.reason());
        return 1;
    }
    std::int32_t interior = 0;
    std::int32_t right_shift = 0;
    for (std::int32_t y = 8; y < kH - 8; ++y) {
        for (std::int32_t x = 8 + 15; x < kW - 8; ++x) {  // the whole search inside the right image
            ++interior;
            const std::int32_t d = disparity[y][x];
            right_shift += (d != vtm::stereo::kNoDisparity && std::abs(d - kShift * vtm::stereo::kDisparityScale) <= 8) ? 1 : 0;
        }
    }
    const vtm::app::WideBaselineMapperConfig mapper;
    const vtm::Status plan = mapper.validate();
    const std::size_t bytes = vtm::app::WideBaselineMapper::workspaceBytes(mapper);
    std::printf("consumer: %d of %d interior pixels at 7 +- 0.5 px; wide-baseline request plan %s, %zu bytes\n",
                right_shift, interior, plan.isOk() ? "valid" : plan.reason(), bytes);
    return (10 * right_shift >= 9 * interior && plan.isOk() && bytes > 0U) ? 0 : 1;
}
