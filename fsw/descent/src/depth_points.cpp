// Depth image to site points, handed to the height map (terrain::HeightMap bins and reduces).
#include <cmath>

#include "geometry.hpp"

namespace vtm::descent {
namespace {

// Points go to the map in batches (one call per kBatch points, in pixel order).
constexpr std::size_t kBatch = 64U;

Status checkInputs(const ImageView<const float>& depth_m, const CameraModel& camera,
                   const RigidPose& site_from_cam) noexcept {
    if (!depth_m.valid()) {
        return Status(StatusCode::kInvalidArgument, "depth_m: empty or malformed view");
    }
    VTM_RETURN_IF_ERROR(detail::checkPinhole(camera));
    if (!depth_m.sameSize(camera.width_px, camera.height_px)) {
        return Status(StatusCode::kSizeMismatch, "depth_m: size differs from the camera's", depth_m.width());
    }
    return detail::checkPose(site_from_cam, "site_from_cam: not finite or its rotation is not a rotation");
}

// The site points of row y's valid depths into batch[n..], a full batch to the map.
Status addRow(const float* d, std::int32_t width, std::int32_t y, const Mat3& Kinv, const RigidPose& site_from_cam,
              terrain::HeightMap& map, Vec3* batch, std::size_t& n, terrain::HeightMapStats& stats) noexcept {
    for (std::int32_t x = 0; x < width; ++x) {
        if (!std::isfinite(d[x])) {
            continue;
        }
        const Vec3 ray = Kinv * Vec3(static_cast<double>(x), static_cast<double>(y), 1.0);  // z = 1
        batch[n] = site_from_cam.R * (ray * static_cast<double>(d[x])) + site_from_cam.t_m;
        ++n;
        if (n == kBatch) {
            n = 0U;
            VTM_RETURN_IF_ERROR(map.add(Span<const Vec3>(batch, kBatch), &stats));
        }
    }
    return Status::ok();
}

}  // namespace

Status addDepthToHeightMap(const ImageView<const float>& depth_m, const CameraModel& camera,
                           const RigidPose& site_from_cam, terrain::HeightMap& map,
                           terrain::HeightMapStats* stats) noexcept {
    VTM_RETURN_IF_ERROR(checkInputs(depth_m, camera, site_from_cam));
    terrain::HeightMapStats local;
    const Mat3 Kinv = detail::inverseIntrinsics(camera);
    Vec3 batch[kBatch];
    std::size_t n = 0U;
    for (std::int32_t y = 0; y < depth_m.height(); ++y) {
        VTM_RETURN_IF_ERROR(addRow(depth_m.row(y), depth_m.width(), y, Kinv, site_from_cam, map, batch, n, local));
    }
    VTM_RETURN_IF_ERROR(map.add(Span<const Vec3>(batch, n), &local));
    if (stats != nullptr) {
        stats->added += local.added;
        stats->outside += local.outside;
    }
    return Status::ok();
}

}  // namespace vtm::descent
