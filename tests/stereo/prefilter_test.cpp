// The stereo prefilter (detail::removeLocalMean, fsw/stereo/src/plan.hpp) against its
// definition in the same run: 128 + 2 (I - mean over the window), the mean rounded, the
// window's pixels beyond the border replicated, clamped to 0..255. Its fast form slides
// the window without the border's clamps in the interior; images narrower and shorter
// than the window keep every pixel on a border.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "plan.hpp"
#include "vtm/core/random.hpp"

namespace {

std::int32_t clampTo(std::int32_t v, std::int32_t n) { return v < 0 ? 0 : (v >= n ? n - 1 : v); }

TEST(Prefilter, RemovesTheLocalMeanAsDefinedForEveryWidthAndWindow) {
    vtm::Random rng(20261207);
    std::int32_t checked = 0;
    for (std::int32_t trial = 0; trial < 300; ++trial) {
        const auto w = static_cast<std::int32_t>(rng.uniformInt(1, 40));
        const auto h = static_cast<std::int32_t>(rng.uniformInt(1, 12));
        const auto window = static_cast<std::int32_t>(2 * rng.uniformInt(0, 8) + 1);  // 1..17
        std::vector<std::uint8_t> in(static_cast<std::size_t>(w * h)), out(in.size());
        for (auto& p : in) {
            p = static_cast<std::uint8_t>(rng.uniformInt(0, 255));
        }
        std::vector<std::int32_t> columns(static_cast<std::size_t>(w));
        vtm::stereo::detail::removeLocalMean(vtm::ImageView<const std::uint8_t>(in.data(), w, h), window,
                                             columns.data(), vtm::ImageView<std::uint8_t>(out.data(), w, h));
        const std::int32_t r = window / 2, area = window * window;
        for (std::int32_t y = 0; y < h; ++y) {
            for (std::int32_t x = 0; x < w; ++x) {
                std::int32_t sum = 0;
                for (std::int32_t dy = -r; dy <= r; ++dy) {
                    for (std::int32_t dx = -r; dx <= r; ++dx) {
                        sum += in[static_cast<std::size_t>(clampTo(y + dy, h) * w + clampTo(x + dx, w))];
                    }
                }
                const std::int32_t v = 128 + 2 * (in[static_cast<std::size_t>(y * w + x)] - (sum + area / 2) / area);
                const std::int32_t expected = v < 0 ? 0 : (v > 255 ? 255 : v);
                ASSERT_EQ(out[static_cast<std::size_t>(y * w + x)], expected)
                    << "w " << w << " h " << h << " window " << window << " at (" << x << ", " << y << ")";
                ++checked;
            }
        }
    }
    EXPECT_GT(checked, 10000);
}

}  // namespace
