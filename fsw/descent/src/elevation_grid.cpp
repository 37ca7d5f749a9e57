// Elevation grid from a depth image: back-project, move to the site frame, bin (mean).
#include <cmath>
#include <limits>

#include "geometry.hpp"

namespace vtm::descent {
namespace {

Status checkGridInputs(const ImageView<const float>& depth_m, const CameraModel& camera, const CameraPose& pose,
                       const GridSpec& grid, const ImageView<float>& elevation_out,
                       const ImageView<std::uint16_t>& count_out) noexcept {
    if (!depth_m.valid() || !elevation_out.valid() || !count_out.valid()) {
        return Status(StatusCode::kInvalidArgument, "depth_m/elevation_out/count_out: empty or malformed view");
    }
    if (!count_out.sameSize(elevation_out.width(), elevation_out.height())) {
        return Status(StatusCode::kSizeMismatch, "count_out: size differs from elevation_out", count_out.width());
    }
    if (!(grid.cell_m > 0.0) || !std::isfinite(grid.cell_m) || !std::isfinite(grid.origin_north_m) ||
        !std::isfinite(grid.origin_east_m)) {
        return Status(StatusCode::kInvalidArgument, "grid: cell_m must be > 0 and every field finite");
    }
    VTM_RETURN_IF_ERROR(detail::checkPinhole(camera));
    if (!depth_m.sameSize(camera.width_px, camera.height_px)) {
        return Status(StatusCode::kSizeMismatch, "depth_m: size differs from the camera's", depth_m.width());
    }
    return detail::checkPose(pose, "pose: not finite or its rotation is not a rotation");
}

}  // namespace

Status elevationGrid(const ImageView<const float>& depth_m, const CameraModel& camera, const CameraPose& pose,
                     const GridSpec& grid, const ImageView<float>& elevation_out,
                     const ImageView<std::uint16_t>& count_out, std::int64_t* outside) noexcept {
    VTM_RETURN_IF_ERROR(checkGridInputs(depth_m, camera, pose, grid, elevation_out, count_out));
    elevation_out.fill(0.0F);
    count_out.fill(0U);
    std::int64_t away = 0;
    const Mat3 Kinv = detail::inverseIntrinsics(camera);
    const auto cols = static_cast<double>(elevation_out.width());
    const auto rows = static_cast<double>(elevation_out.height());
    for (std::int32_t y = 0; y < depth_m.height(); ++y) {
        const float* d = depth_m.row(y);
        for (std::int32_t x = 0; x < depth_m.width(); ++x) {
            if (!std::isfinite(d[x])) {
                continue;
            }
            const Vec3 ray = Kinv * Vec3(static_cast<double>(x), static_cast<double>(y), 1.0);  // z = 1
            const Vec3 p = pose.R_site_from_cam * (ray * static_cast<double>(d[x])) + pose.position_site_m;
            const double row = std::floor((grid.origin_north_m - p.x()) / grid.cell_m);
            const double col = std::floor((p.y() - grid.origin_east_m) / grid.cell_m);
            if (!(row >= 0.0 && row < rows && col >= 0.0 && col < cols)) {
                ++away;
                continue;
            }
            const auto r = static_cast<std::int32_t>(row);
            const auto c = static_cast<std::int32_t>(col);
            std::uint16_t& n = count_out.row(r)[c];
            if (n < UINT16_MAX) {  // a saturated cell keeps the mean of its first 65535 points
                elevation_out.row(r)[c] += static_cast<float>(-p.z());
                ++n;
            }
        }
    }
    for (std::int32_t r = 0; r < elevation_out.height(); ++r) {
        for (std::int32_t c = 0; c < elevation_out.width(); ++c) {
            const std::uint16_t n = count_out.row(r)[c];
            float& e = elevation_out.row(r)[c];
            e = (n == 0U) ? std::numeric_limits<float>::quiet_NaN() : e / static_cast<float>(n);
        }
    }
    if (outside != nullptr) {
        *outside = away;
    }
    return Status::ok();
}

}  // namespace vtm::descent
