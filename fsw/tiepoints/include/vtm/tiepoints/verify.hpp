// Verification steps of the tie points (docs/tiepoints.md), public so that tests and the
// ground can run them on their own matches:
//  - parallax consistency: a match's parallax p = pixel_b - pixel_a is compared with a
//    robust local plane fit of the parallax of its nearest neighbours (in image A);
//  - grid thinning: each cell of a grid over image A keeps its best match.
// Both are deterministic (fixed orders, ties broken by index) and use only + - * /.
#pragma once

#include <cstdint>

#include "vtm/core/eigen.hpp"
#include "vtm/core/span.hpp"
#include "vtm/core/status.hpp"
#include "vtm/features/template_matcher.hpp"

namespace vtm::tiepoints {

// Largest neighbourhood of the parallax fit.
constexpr std::int32_t kMaxParallaxNeighbours = 16;

// Parallax consistency. For each match: its `neighbours` nearest other matches (distance
// in image A, ties by index) within max_radius_px; a plane p(x) = c + G (x - x_match)
// is fitted to their parallax by least squares (each component of p on its own), the
// neighbours whose residual exceeds tolerance_px are dropped and the plane fitted again
// once (with fewer than 3 left, or a degenerate layout, the plane is replaced by the
// component-wise median of the neighbours' parallax); the match is consistent when
// |p - c| <= tolerance_px (Euclidean). A match with fewer than min_neighbours
// neighbours cannot be checked and is rejected (isolated).
struct ParallaxConfig {
    std::int32_t neighbours = 8;        // 3..kMaxParallaxNeighbours
    std::int32_t min_neighbours = 4;    // 3..neighbours
    double max_radius_px = 80.0;        // > 0
    double tolerance_px = 1.0;          // > 0
    [[nodiscard]] Status validate() const noexcept;  // kInvalidConfig naming the field
};

struct ParallaxStats {
    std::int32_t consistent = 0, inconsistent = 0, isolated = 0;
};

// keep[k] = 1 for a consistent match, 0 otherwise (keep.size() >= matches.size(), else
// kSizeMismatch). O(n^2) in matches.size() (<= features::kMaxFeatures, else kInvalidArgument).
[[nodiscard]] Status checkParallax(Span<const features::Match> matches, const ParallaxConfig& config,
                                   Span<std::uint8_t> keep, ParallaxStats* stats = nullptr) noexcept;

// Grid thinning over image A (width x height pixels): cols x rows equal cells; among the
// matches with keep[k] != 0, each cell keeps the one of highest score (NCC; ties: the
// lower index); keep[] is rewritten. kInvalidArgument for a grid outside 1..256 per side,
// or width/height < 1; kSizeMismatch for keep shorter than matches. kept = survivors.
struct ThinningConfig {
    std::int32_t cols = 8, rows = 8;  // 1..256 each
    [[nodiscard]] Status validate() const noexcept;  // kInvalidConfig naming the field
};
[[nodiscard]] Status thinByGrid(Span<const features::Match> matches, const ThinningConfig& grid, std::int32_t width,
                                std::int32_t height, Span<std::uint8_t> keep, std::int32_t& kept) noexcept;

}  // namespace vtm::tiepoints
