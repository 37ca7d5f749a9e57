// Quantities derived from a validated Config: sizes, fixed-point scales, radii. One
// place computes them, so workspaceBytes(), init() and compute() cannot disagree.
#pragma once

#include <cstddef>
#include <cstdint>

#include "vtm/stereo/ml_stereo.hpp"

namespace vtm::stereo::detail {

struct Plan {
    std::int32_t width = 0;            // max_width
    std::int32_t height = 0;           // max_height
    std::int32_t disparities = 0;      // d_max - d_min + 1
    std::int32_t half = 0;             // window / 2
    std::int32_t bins = 0;             // intensity bins Q
    std::int32_t binShift = 0;         // grey level >> binShift = bin
    std::int32_t radius = 0;           // DT radius r, pixels (0: no distance transform)
    std::int32_t d2Scale = 0;          // F: squared distances are stored in 1/F px^2
    std::int32_t d2Cap = 0;            // r^2 F (or the intensity cap without a DT), <= 255
    std::int32_t binWeight = 0;        // D2 units per bin^2 along the intensity axis
    std::int32_t binReach = 0;         // bins within the cap of a pixel's own bin
    std::int32_t maxCost = 0;          // cost of an outlier / of no right pixel
    std::int32_t padLeft = 0;          // max(d_max, 0) + disparities: DT row columns left of u = 0
    std::int32_t dtStride = 0;         // width + padLeft + max(-d_min, 0) + disparities + kSlotGroup
    std::int32_t costStride = 0;       // width + 2 * half: columns of the column sums
    std::int32_t slotStride = 0;       // disparities rounded up to kSlotGroup: bytes (costs) or
                                       // uint16 (sums) per pixel (window_sums.hpp)
    double costPerNat = 0.0;           // cost units per nat of log-likelihood
};

// The plan of a config that passed validate().
[[nodiscard]] Plan makePlan(const Config& c) noexcept;

// Cost (0..maxCost) of each squared distance D2 = 0..d2Cap (D2 in 1/F px^2), from the
// density f(D) = alpha N(D; 0, sigma) + (1 - alpha) f_out (or without the outlier term).
// table must hold 256 entries; entries above d2Cap repeat maxCost.
void buildCostTable(const Config& c, const Plan& p, std::uint8_t* table) noexcept;

// 3D distance transform of one right-image row, x pass: for every intensity bin i and
// column u, the least D2 to a pixel of this row within the radius, capped at d2Cap.
// out: bins * width bytes (bin-major).
void distanceTransformRowX(const Plan& p, const std::uint8_t* rightRow, std::int32_t width,
                           std::uint8_t* out) noexcept;

// y pass for one row y: combines the x-pass rows y-r..y+r held in the ring (row v in slot
// v mod (2r+1)), maps each D2 through the cost table and writes matching costs into
// dtRow (bins rows of dtStride), columns [padLeft, padLeft + width) of the used bins only.
// The columns outside the right image must hold maxCost: compute() fills dtRow once.
struct RowGeometry {
    std::int32_t y;       // the row
    std::int32_t height;  // image height
    std::int32_t width;   // image width
    // Per intensity bin: non-zero when some template pixel of row y has that bin; only
    // those bins' costs are ever read, so only they are computed.
    const std::uint8_t* binUsed;
};
void distanceTransformRowY(const Plan& p, const RowGeometry& g, const std::uint8_t* ring,
                           const std::uint8_t* costTable, std::uint8_t* dtRow) noexcept;

// Local-mean-removed image: 128 + 2 (I - mean over window), clamped to 0..255;
// columns: scratch of width int32. Borders replicate.
void removeLocalMean(const ImageView<const std::uint8_t>& in, std::int32_t window, std::int32_t* columns,
                     const ImageView<std::uint8_t>& out) noexcept;

}  // namespace vtm::stereo::detail
