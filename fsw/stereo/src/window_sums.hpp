// The disparity search's inner passes: per-pixel costs into the ring and the column sums,
// then window sums and the best disparity per pixel. Pixel-major: a pixel's D costs are
// contiguous, because the cost of left pixel x at disparity d is the DT row's byte at
// column centre(x) - d, so the D costs of x are D consecutive bytes of the DT row, read
// backwards (slot s = 0..D-1 is disparity index j = D-1-s). They are moved and summed a
// word at a time, 16-bit sums packed into words (sum_lanes.hpp).
#pragma once

#include <cstdint>

#include "plan.hpp"
#include "sum_lanes.hpp"

namespace vtm::stereo::detail {

// Index into colSums-like / winSums arrays (slotStride uint16 per pixel) of pixel x's sum
// at disparity index j.
inline std::size_t sumIndex(const Plan& p, std::int32_t x, std::int32_t j) noexcept {
    return static_cast<std::size_t>(x) * static_cast<std::size_t>(p.slotStride) +
           static_cast<std::size_t>(sumPosition(p.disparities - 1 - j));
}

// Pushes one template row into ring slot `ring` (width * slotStride bytes) and updates the
// column sums (costStride columns of slotStride uint16; image column x is column x + half):
// col += new - old per column and disparity. costs[x]: pixel x's slot 0 in dtRow (its
// D costs are dtRow[costs[x] .. costs[x] + D)); nullptr: a row of zero cost (below the image).
void pushCostRow(const Plan& p, std::int32_t width, const std::uint8_t* dtRow, const std::int32_t* costs,
                 std::uint8_t* ring, std::uint16_t* colSums) noexcept;

// Window sums of the completed row (running sums of the column sums along x) into
// winSums (width pixels of slotStride uint16), and the best disparity index per pixel
// (least sum; ties: the lowest disparity) with its sum.
void windowSumsAndBest(const Plan& p, std::int32_t width, const std::uint16_t* colSums, std::uint16_t* winSums,
                       std::int32_t* best, std::int16_t* bestIndex) noexcept;

}  // namespace vtm::stereo::detail
