// detail::equalizeExposure (fsw/app/src/request_support.hpp), the wide-baseline executive's
// exposure equalisation, against an independent computation of the same rule: the gain is
// the ratio of the two images' medians over the pixels above 0, applied (rounded, clipped
// at 255) only beyond the tolerance. Exact expected bytes, so the same bits on every target.
// Also the refinement-certainty rule (relativeRotationSigmaRad, refinementIsCertainEnough).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "request_support.hpp"

namespace vtm::app::detail {
namespace {

constexpr std::int32_t kW = 37;
constexpr std::int32_t kH = 23;

// A textured image around `median` (every value in median - 20 .. median + 20 equally
// often, so the median is `median`), with a border of zeros (no content) on the left.
std::vector<std::uint8_t> textured(int median) {
    std::vector<std::uint8_t> px(static_cast<std::size_t>(kW) * kH, 0U);
    int k = 0;
    for (int y = 0; y < kH; ++y) {
        for (int x = 5; x < kW; ++x) {
            px[static_cast<std::size_t>(y * kW + x)] = static_cast<std::uint8_t>(median - 20 + (k++ * 7) % 41);
        }
    }
    return px;
}

// The median of the pixels above 0, the test's own way: sort them, take the lower middle.
int medianAboveZero(const std::vector<std::uint8_t>& px) {
    std::vector<int> v;
    for (std::uint8_t p : px) {
        if (p > 0U) {
            v.push_back(p);
        }
    }
    std::sort(v.begin(), v.end());
    return v.empty() ? 0 : v[(v.size() - 1U) / 2U];
}

ImageView<const std::uint8_t> view(const std::vector<std::uint8_t>& px) { return {px.data(), kW, kH}; }
ImageView<std::uint8_t> view(std::vector<std::uint8_t>& px) { return {px.data(), kW, kH}; }

TEST(ExposureEqualisation, ScalesTheDarkerImageToTheReferenceMedianWithinOneGreyLevel) {
    const std::vector<std::uint8_t> reference = textured(150);
    std::vector<std::uint8_t> image = textured(60);
    const std::vector<std::uint8_t> before = image;
    ASSERT_EQ(medianAboveZero(reference), 150);
    ASSERT_EQ(medianAboveZero(image), 60);
    const std::uint32_t gain = equalizeExposure(view(reference), view(image), 15);
    EXPECT_EQ(gain, 163840U);  // 150 / 60 = 2.5 in 1/65536, exact
    for (std::size_t i = 0U; i < image.size(); ++i) {
        const int want = std::min(255, static_cast<int>(std::floor(before[i] * 2.5 + 0.5)));
        ASSERT_EQ(image[i], want) << "pixel " << i << " of grey " << int(before[i]);
    }
    EXPECT_EQ(medianAboveZero(image), 150);
}

TEST(ExposureEqualisation, AnInexactRatioIsWithinOneGreyLevelOfTheExactProduct) {
    const std::vector<std::uint8_t> reference = textured(117);
    std::vector<std::uint8_t> image = textured(73);
    const std::vector<std::uint8_t> before = image;
    const std::uint32_t gain = equalizeExposure(view(reference), view(image), 15);
    EXPECT_EQ(gain, static_cast<std::uint32_t>(std::floor(117.0 * 65536.0 / 73.0 + 0.5)));
    int off_by_one = 0;
    for (std::size_t i = 0U; i < image.size(); ++i) {
        const int exact = std::min(255, static_cast<int>(std::floor(before[i] * 117.0 / 73.0 + 0.5)));
        ASSERT_LE(std::abs(image[i] - exact), 1) << "pixel " << i;
        off_by_one += image[i] != exact ? 1 : 0;
        ASSERT_EQ(image[i] == 0U, before[i] == 0U) << "content and no content stay apart";
    }
    EXPECT_LT(off_by_one, static_cast<int>(image.size()) / 100);
}

TEST(ExposureEqualisation, BrighterImagesAreDarkenedAndPairsWithinTheToleranceLeftAlone) {
    const std::vector<std::uint8_t> reference = textured(100);
    std::vector<std::uint8_t> brighter = textured(200);
    EXPECT_EQ(equalizeExposure(view(reference), view(brighter), 15), 32768U);
    EXPECT_EQ(medianAboveZero(brighter), 100);
    // 100 / 88: 13.6 % off, inside 15 %: nothing changes; at 10 % it is applied.
    std::vector<std::uint8_t> close = textured(88);
    const std::vector<std::uint8_t> before = close;
    EXPECT_EQ(equalizeExposure(view(reference), view(close), 15), 65536U);
    EXPECT_EQ(close, before);
    EXPECT_EQ(equalizeExposure(view(reference), view(close), 10), static_cast<std::uint32_t>(std::floor(100.0 * 65536.0 / 88.0 + 0.5)));
    EXPECT_NE(close, before);
}

TEST(ExposureEqualisation, AnImageWithoutContentIsLeftAlone) {
    const std::vector<std::uint8_t> black(static_cast<std::size_t>(kW) * kH, 0U);
    std::vector<std::uint8_t> image = textured(60);
    const std::vector<std::uint8_t> before = image;
    EXPECT_EQ(equalizeExposure(view(black), view(image), 15), 65536U);
    EXPECT_EQ(image, before);
    std::vector<std::uint8_t> empty = black;
    EXPECT_EQ(equalizeExposure(view(textured(60)), view(empty), 15), 65536U);
    EXPECT_EQ(empty, black);
}

// The odometry's relative rotation sigma from two poses' covariances: the rotation block's
// diagonal (indices 21, 28, 35 of the 6x6 row-major matrix) of both, summed, square root;
// the position block is not part of it.
TEST(RefinementCertainty, OdometrySigmaIsTheRmsOfBothPosesRotationVariances) {
    hal::PoseEstimate a, b;
    EXPECT_EQ(relativeRotationSigmaRad(a, b), 0.0);  // no covariance stated
    a.covariance[0] = a.covariance[7] = a.covariance[14] = 4.0;  // 2 m position sigma: not rotation
    EXPECT_EQ(relativeRotationSigmaRad(a, b), 0.0);
    b.covariance[21] = 0.001 * 0.001;
    b.covariance[28] = 0.002 * 0.002;
    b.covariance[35] = 0.02 * 0.02;  // heading dominates, as on a rover
    a.covariance[35] = 0.01 * 0.01;
    const double expected = std::sqrt(0.001 * 0.001 + 0.002 * 0.002 + 0.02 * 0.02 + 0.01 * 0.01);
    EXPECT_NEAR(relativeRotationSigmaRad(a, b), expected, 1e-15);
    EXPECT_EQ(relativeRotationSigmaRad(a, b), relativeRotationSigmaRad(b, a));
    b.covariance[35] = std::nan("");
    EXPECT_EQ(relativeRotationSigmaRad(a, b), 0.0);  // not a usable statement: no gate
}

// A refinement whose rotation is more than max_ratio times less certain than the odometry's
// is not published; the rule is off for max_ratio 0 and without an odometry covariance.
TEST(RefinementCertainty, RefusesOnlyARefinementBeyondTheRatio) {
    EXPECT_TRUE(refinementIsCertainEnough(0.02, 0.01, 2.0));     // exactly at the limit
    EXPECT_FALSE(refinementIsCertainEnough(0.0201, 0.01, 2.0));  // beyond it
    EXPECT_TRUE(refinementIsCertainEnough(0.001, 0.01, 0.5));
    EXPECT_FALSE(refinementIsCertainEnough(0.0084, 0.0168, 0.5 - 1e-9));
    EXPECT_TRUE(refinementIsCertainEnough(1.0, 0.01, 0.0));  // off
    EXPECT_TRUE(refinementIsCertainEnough(1.0, 0.0, 2.0));   // the odometry states nothing
    EXPECT_FALSE(refinementIsCertainEnough(std::nan(""), 0.01, 2.0));  // no sigma: not certain
}

}  // namespace
}  // namespace vtm::app::detail
