#include "vtm/ground/occlusion_mask.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "vtm/ground/disparity_evaluation.hpp"

namespace vtm::ground {
namespace {

constexpr std::uint8_t kEvaluate = 255;

// Right-image column of left column x at disparity d: nearest integer, halves up.
long rightColumn(std::int32_t x, float d_px) {
    return static_cast<long>(std::floor(static_cast<double>(x) - static_cast<double>(d_px) + 0.5));
}

bool insideRow(long column, std::int32_t width) { return column >= 0 && column < width; }

}  // namespace

Result<GreyImage> leftRightCheckMask(const FloatImage& gt_left_px, const FloatImage& gt_right_px, float tolerance_px) {
    if (!gt_left_px.sameSize(gt_right_px)) {
        return Result<GreyImage>::failure("left ground truth is " + std::to_string(gt_left_px.width) + "x" +
                                          std::to_string(gt_left_px.height) + " but right ground truth is " +
                                          std::to_string(gt_right_px.width) + "x" + std::to_string(gt_right_px.height));
    }
    GreyImage mask(gt_left_px.width, gt_left_px.height);
    for (std::int32_t y = 0; y < gt_left_px.height; ++y) {
        for (std::int32_t x = 0; x < gt_left_px.width; ++x) {
            const float dl = gt_left_px.at(x, y);
            const long xr = isKnownDisparity(dl) ? rightColumn(x, dl) : -1;
            if (!insideRow(xr, gt_left_px.width)) {
                continue;  // unknown, or sees nothing in the right image
            }
            const float dr = gt_right_px.at(static_cast<std::int32_t>(xr), y);
            const bool agree = isKnownDisparity(dr) && std::fabs(dl - dr) <= tolerance_px;
            mask.at(x, y) = agree ? kEvaluate : 0;
        }
    }
    return Result<GreyImage>::success(std::move(mask));
}

GreyImage visibilityMask(const FloatImage& gt_left_px, float tolerance_px) {
    GreyImage mask(gt_left_px.width, gt_left_px.height);
    for (std::int32_t y = 0; y < gt_left_px.height; ++y) {
        // Scan right to left, keeping the leftmost right-image position of any known
        // pixel right of x: a nearer surface there covers right positions left of it.
        double leftmost = std::numeric_limits<double>::infinity();
        for (std::int32_t x = gt_left_px.width - 1; x >= 0; --x) {
            const float d = gt_left_px.at(x, y);
            if (!isKnownDisparity(d)) {
                continue;
            }
            const double r = static_cast<double>(x) - static_cast<double>(d);
            const bool visible = r >= 0.0 && r <= leftmost + static_cast<double>(tolerance_px);
            mask.at(x, y) = visible ? kEvaluate : 0;
            leftmost = std::min(leftmost, r);
        }
    }
    return mask;
}

double maskFraction(const GreyImage& mask) {
    if (mask.pixels.empty()) {
        return 0.0;
    }
    const auto n = std::count_if(mask.pixels.begin(), mask.pixels.end(), [](std::uint8_t v) { return v != 0; });
    return static_cast<double>(n) / static_cast<double>(mask.pixels.size());
}

}  // namespace vtm::ground
