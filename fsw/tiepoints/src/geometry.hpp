// Small geometry of the tie points (internal): rays in the site frame, the midpoint of two
// rays, a camera's pixels per radian, the ray cast onto the coarse elevation map.
#pragma once

#include <cstdint>

#include "vtm/core/camera_model.hpp"
#include "vtm/core/eigen.hpp"
#include "vtm/core/pose.hpp"
#include "vtm/terrain/height_map.hpp"

namespace vtm::tiepoints::detail {

struct SiteRay {
    Vec3 origin = Vec3::Zero();
    Vec3 direction = Vec3::UnitZ();  // unit
};

// The ray of a pixel in the site frame; false when the model cannot back-project it.
[[nodiscard]] bool siteRay(const CameraModel& model, const RigidPose& site_from_cam, const Vec2& pixel,
                           SiteRay& ray) noexcept;

// Midpoint of the shortest segment between two rays; false for (near) parallel rays or a
// point behind either origin.
[[nodiscard]] bool midpoint(const SiteRay& a, const SiteRay& b, Vec3& point) noexcept;

// Pixel of a site point in a camera; false behind it or outside [border, size - 1 - border].
[[nodiscard]] bool projectInside(const CameraModel& model, const RigidPose& site_from_cam, const Vec3& site_m,
                                 double border_px, Vec2& pixel) noexcept;

// Pixels per radian at the image centre (from two back-projected rays 1 px apart); 0 on failure.
[[nodiscard]] double pixelsPerRadian(const CameraModel& model) noexcept;

// Elevation (up, m) of the map at a site point: its cell's mean, else the mean of the filled
// cells in the smallest square window of radius 1..fill_radius that has any; NaN if none.
[[nodiscard]] double elevationNear(const terrain::HeightMap& map, double north_m, double east_m,
                                   std::int32_t fill_radius) noexcept;

// Range along the ray at which it first meets the map: `steps` samples over [min, max], the
// crossing refined by 12 bisections. False when no sample is above the map before one at or
// below it.
[[nodiscard]] bool castOnMap(const terrain::HeightMap& map, const SiteRay& ray, double range_min_m,
                             double range_max_m, std::int32_t steps, std::int32_t fill_radius,
                             double& range_m) noexcept;

}  // namespace vtm::tiepoints::detail
