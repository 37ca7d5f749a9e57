// The orthophoto of an elevation grid from a panorama's images (paper §3; docs/kriging.md
// "Orthophoto"). Each node (x, y from the grid, elevation from the map) is projected into
// every image of every station (vtm/core/image_network.hpp: siteFromEye, modelOfEye,
// projectPoint); among the images that see it (in front of the camera, the projection
// inside [0, w-1] x [0, h-1] so that the bilinear interpolation has its four pixels), the
// one whose projection lies closest to the image centre ((w-1)/2, (h-1)/2) gives the grey
// value, bilinear, rounded to nearest. Equal distances go to the lower source index.
// Occlusion (OrthophotoConfig::occlusion_test): an image does not see a node when the line
// from the node to the image's projection centre passes more than occlusion_margin_m under
// the elevation grid's surface (bilinear through the nodes, marched in half-cell steps
// from one cell away; relief outside the grid is not known and does not occlude).
// No memory of its own: outputs are the caller's views. + - * / sqrt: the same bits on
// every target.
#pragma once

#include <cstddef>
#include <cstdint>

#include "vtm/core/image.hpp"
#include "vtm/core/image_network.hpp"
#include "vtm/core/span.hpp"
#include "vtm/core/status.hpp"
#include "vtm/terrain/height_map.hpp"

namespace vtm::kriging {

// Source index of a node: 2 * station + eye (0 left, 1 right); kNoSource where no image
// sees the node (grey 0 there).
constexpr std::uint16_t kNoSource = 0xFFFFU;
constexpr std::size_t kMaxOrthoStations = 32767U;

struct OrthophotoConfig {
    bool occlusion_test = true;
    double occlusion_margin_m = 0.02;  // >= 0, finite: relief this much above the line still lets it through
    [[nodiscard]] Status validate() const noexcept;  // kInvalidConfig naming the field
};

struct OrthophotoStats {
    std::int32_t filled = 0;          // nodes with a grey value
    std::int32_t not_seen = 0;        // nodes that no image sees (outside every image, or occluded in all)
    std::int32_t no_elevation = 0;    // NO_DATA nodes of the elevation grid
    std::int32_t occluded_views = 0;  // views the occlusion test rejected (tested only where the view would win)
};

// grid: the elevation grid's convention (terrain::GridConfig); elevation_m: cols * rows
// values, row-major, row 0 north (KrigedMap::elevations()), NaN = NO_DATA (no grey, source
// kNoSource). stations[i] pairs with images[i]. grey and source: cols x rows views.
// kInvalidConfig: config invalid; kInvalidArgument: grid invalid, elevations of the wrong count, stations and images of
// different counts or more than kMaxOrthoStations, a station that fails
// validateNetworkStation (detail = its index); kSizeMismatch: an output view not cols x rows,
// an image view not the size of its eye's camera model (detail = 2 * station + eye).
// Nothing is written when refused.
[[nodiscard]] Status buildOrthophoto(const OrthophotoConfig& config, const terrain::GridConfig& grid, Span<const float> elevation_m,
                                     Span<const NetworkStation> stations, Span<const StationImages> images,
                                     const ImageView<std::uint8_t>& grey, const ImageView<std::uint16_t>& source,
                                     OrthophotoStats* stats = nullptr) noexcept;

// The orthophoto's mean absolute grey step between east-west neighbour nodes, split into
// pairs whose sources differ (a border between two images) and pairs of one source: a seam
// shows as steps across borders larger than those within one image (ratio() > 1). Nodes
// without a source are left out; views of different sizes give no pairs.
struct SeamSteps {
    double across_dn = 0.0;
    double within_dn = 0.0;
    std::int32_t across_pairs = 0;
    std::int32_t within_pairs = 0;
    // across / within; 0 when either has no pair or within is 0.
    [[nodiscard]] double ratio() const noexcept {
        return (across_pairs > 0 && within_pairs > 0 && within_dn > 0.0) ? across_dn / within_dn : 0.0;
    }
};
[[nodiscard]] SeamSteps measureSeamSteps(const ImageView<const std::uint8_t>& grey,
                                         const ImageView<const std::uint16_t>& source) noexcept;

}  // namespace vtm::kriging
