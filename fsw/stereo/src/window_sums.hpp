// The disparity search's inner passes: per-pixel costs into the ring and the column sums,
// then window sums and the best disparity per pixel. Pixel-major: a pixel's D costs are
// contiguous, because the cost of left pixel x at disparity d is the DT row's byte at
// column centre(x) - d, so the D costs of x are D consecutive bytes of the DT row, read
// backwards (slot s = 0..D-1 is disparity index j = D-1-s). They are moved and summed a
// word at a time, 16-bit sums packed into words (sum_lanes.hpp).
#pragma once

#include <cstddef>
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

// Calls f(j, sum) for each disparity index j of pixel x's window sums, in memory order
// (slot g + 2 i + h lies at position g + h kLanes + i of its word group g).
template <class F>
void forEachSum(const Plan& p, const std::uint16_t* winSums, std::int32_t x, F&& f) noexcept {
    const std::uint16_t* sums = winSums + static_cast<std::size_t>(x) * static_cast<std::size_t>(p.slotStride);
    const std::int32_t used = (p.disparities + kWordBytes - 1) / kWordBytes * kWordBytes;
    for (std::int32_t g = 0; g < used; g += kWordBytes) {
        for (std::int32_t h = 0; h < 2; ++h) {
            for (std::int32_t i = 0; i < kLanes; ++i) {
                const std::int32_t j = p.disparities - 1 - (g + 2 * i + h);
                if (j >= 0) {
                    f(j, std::int32_t{sums[g + h * kLanes + i]});
                }
            }
        }
    }
}

// Where a completed row's window sums and best disparities go.
struct SearchRow {
    std::uint16_t* winSums;    // width pixels of slotStride uint16
    std::int32_t* best;        // least window sum per pixel
    std::int16_t* bestIndex;   // its disparity index (ties: the lowest)
};

// Pushes one template row into ring slot `ring` (width * slotStride bytes) and updates the
// column sums (costStride columns of slotStride uint16; image column x is column x + half):
// col += new - old per column and disparity. costs[x]: pixel x's slot 0 in dtRow (its
// D costs are dtRow[costs[x] .. costs[x] + D)); nullptr: a row of zero cost (below the
// image). With `out`, the row `half` rows up is then complete, and its window sums
// (running sums of the column sums along x) and best disparities are written to `out`
// in the same pass: each pushed column enters the window of the pixel `half` to its left.
void pushCostRow(const Plan& p, std::int32_t width, const std::uint8_t* dtRow, const std::int32_t* costs,
                 std::uint8_t* ring, std::uint16_t* colSums, const SearchRow* out) noexcept;

}  // namespace vtm::stereo::detail
