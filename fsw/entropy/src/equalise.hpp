// Grey-level equalisation before the entropy image (registration.hpp, docs/entropy.md):
// over the whole image (histogram equalisation) or within a square around each pixel
// (its rank among its neighbours). Internal to vtm_entropy.
#pragma once

#include <cstdint>

#include "vtm/core/image.hpp"
#include "vtm/core/span.hpp"

namespace vtm::entropy::detail {

// Counts localRank() works in: 256 grey levels and 16 groups of 16.
constexpr std::size_t kRankCounts = 256U + 16U;
// Largest radius localRank() takes: (2 r + 1)^2 samples fit its 16-bit counts.
constexpr std::int32_t kMaxRankRadius = 63;

// Histogram equalisation: grey level v becomes round(255 (cdf(v) - cdf(first)) / (n - cdf(first)))
// (cdf(v): pixels at or below v, first: the lowest level present), integer arithmetic.
// Pixels at or below fillMax (-1: none) are left out of the histogram and become 0.
// src and dst may be the same view.
void equalise(const ImageView<const std::uint8_t>& src, const ImageView<std::uint8_t>& dst,
              std::int32_t fillMax) noexcept;

// Local rank: each pixel v becomes min(255, 256 (2 below + equal) / (2 n)) over the samples
// of the (2 radius + 1)^2 square centred on it, clipped at the image's borders (below: the
// samples darker than v, equal: those at v, n: all), so a sensor's response, however it
// varies across the image, drops out as long as it keeps the order of the grey levels.
// Pixels at or below fillMax (-1: none) are not counted and become 0. Integer arithmetic,
// O(radius) per pixel: the window slides along each row, a column out and a column in.
// counts: kRankCounts entries. radius 1..kMaxRankRadius; src and dst distinct, same size.
void localRank(const ImageView<const std::uint8_t>& src, const ImageView<std::uint8_t>& dst, std::int32_t radius,
               std::int32_t fillMax, Span<std::uint16_t> counts) noexcept;

}  // namespace vtm::entropy::detail
