// The orthophoto: per node, the grey value of the image that sees it nearest its centre.
#include <cmath>

#include "grid_occlusion.hpp"
#include "vtm/core/camera_model.hpp"
#include "vtm/core/math.hpp"
#include "vtm/kriging/orthophoto.hpp"

namespace vtm::kriging {
namespace {

struct Pick {
    std::uint16_t source = kNoSource;
    Vec2 pixel = Vec2::Zero();
    double distance2 = 0.0;
};

Eye eyeOf(std::int32_t e) noexcept { return e == 0 ? Eye::kLeft : Eye::kRight; }

Status checkInputs(const terrain::GridConfig& grid, Span<const float> elevation_m, Span<const NetworkStation> stations,
                   Span<const StationImages> images, const ImageView<std::uint8_t>& grey,
                   const ImageView<std::uint16_t>& source) noexcept {
    VTM_RETURN_IF_ERROR(grid.validate());
    const std::size_t cells = static_cast<std::size_t>(grid.cols) * static_cast<std::size_t>(grid.rows);
    if (elevation_m.size() != cells) {
        return Status(StatusCode::kInvalidArgument, "orthophoto: elevation_m must hold cols * rows values",
                      static_cast<std::int64_t>(elevation_m.size()));
    }
    if (stations.size() != images.size() || stations.size() > kMaxOrthoStations) {
        return Status(StatusCode::kInvalidArgument, "orthophoto: stations and images differ in count or exceed 32767",
                      static_cast<std::int64_t>(stations.size()));
    }
    if (!grey.valid() || !grey.sameSize(grid.cols, grid.rows) || !source.valid() ||
        !source.sameSize(grid.cols, grid.rows)) {
        return Status(StatusCode::kSizeMismatch, "orthophoto: grey and source views must be cols x rows");
    }
    for (std::size_t s = 0; s < stations.size(); ++s) {
        if (!validateNetworkStation(stations[s]).isOk()) {
            return Status(StatusCode::kInvalidArgument, "orthophoto: a station fails validateNetworkStation (index)",
                          static_cast<std::int64_t>(s));
        }
        for (std::int32_t e = 0; e < 2; ++e) {
            const ImageView<const std::uint8_t>& view = imageOfEye(images[s], eyeOf(e));
            if (view.data() == nullptr) {
                continue;
            }
            const CameraModel& model = modelOfEye(stations[s], eyeOf(e));
            if (!view.valid() || !view.sameSize(model.width_px, model.height_px) || view.width() < 2 ||
                view.height() < 2) {
                return Status(StatusCode::kSizeMismatch,
                              "orthophoto: an image is not its camera model's size (2 * station + eye)",
                              static_cast<std::int64_t>(2U * s + static_cast<std::size_t>(e)));
            }
        }
    }
    return Status::ok();
}

// The projection centre of an eye in the site frame (pinhole: the frame's origin; CAHV(OR): C).
Vec3 eyeCentreSite(const RigidPose& site_from_eye, const CameraModel& model) noexcept {
    const Vec3 centre = model.kind == CameraModelKind::kPinholeBrown ? Vec3::Zero()
                                                                      : Vec3(model.c[0], model.c[1], model.c[2]);
    return transformPoint(site_from_eye, centre);
}

struct Scene {
    const OrthophotoConfig* config = nullptr;
    const detail::ElevationSurface* surface = nullptr;
    Span<const NetworkStation> stations{};
    Span<const StationImages> images{};
};

// The image that sees the site point nearest its centre (and, with the occlusion test, whose
// line of sight to the point is clear).
Pick pickImage(const Vec3& point_site_m, const Scene& scene, std::int32_t& occluded_views) noexcept {
    const Span<const NetworkStation> stations = scene.stations;
    const Span<const StationImages> images = scene.images;
    Pick best;
    for (std::size_t s = 0; s < stations.size(); ++s) {
        for (std::int32_t e = 0; e < 2; ++e) {
            const ImageView<const std::uint8_t>& view = imageOfEye(images[s], eyeOf(e));
            if (view.data() == nullptr) {
                continue;
            }
            const RigidPose pose = siteFromEye(stations[s], eyeOf(e));
            const Vec3 cam = pose.R.transpose() * (point_site_m - pose.t_m);
            Vec2 px = Vec2::Zero();
            if (!projectPoint(modelOfEye(stations[s], eyeOf(e)), cam, px).isOk()) {
                continue;
            }
            const double w1 = static_cast<double>(view.width() - 1);
            const double h1 = static_cast<double>(view.height() - 1);
            if (!(px.x() >= 0.0 && px.x() <= w1 && px.y() >= 0.0 && px.y() <= h1)) {
                continue;
            }
            const double dx = px.x() - 0.5 * w1;
            const double dy = px.y() - 0.5 * h1;
            const double d2 = dx * dx + dy * dy;
            if (best.source != kNoSource && !(d2 < best.distance2)) {
                continue;  // cannot win: no need to test its line of sight
            }
            if (scene.config->occlusion_test &&
                detail::occluded(*scene.surface, point_site_m, eyeCentreSite(pose, modelOfEye(stations[s], eyeOf(e))),
                                 scene.config->occlusion_margin_m)) {
                ++occluded_views;
                continue;
            }
            best.source = static_cast<std::uint16_t>(2U * s + static_cast<std::size_t>(e));
            best.pixel = px;
            best.distance2 = d2;
        }
    }
    return best;
}

// Bilinear grey at a pixel inside [0, w-1] x [0, h-1], rounded to nearest.
std::uint8_t bilinear(const ImageView<const std::uint8_t>& view, const Vec2& px) noexcept {
    auto x0 = static_cast<std::int32_t>(math::floor(px.x()));
    auto y0 = static_cast<std::int32_t>(math::floor(px.y()));
    x0 = x0 < view.width() - 1 ? x0 : view.width() - 2;
    y0 = y0 < view.height() - 1 ? y0 : view.height() - 2;
    const double fx = px.x() - static_cast<double>(x0);
    const double fy = px.y() - static_cast<double>(y0);
    const std::uint8_t* r0 = view.row(y0) + x0;
    const std::uint8_t* r1 = view.row(y0 + 1) + x0;
    const double top = (1.0 - fx) * static_cast<double>(r0[0]) + fx * static_cast<double>(r0[1]);
    const double bottom = (1.0 - fx) * static_cast<double>(r1[0]) + fx * static_cast<double>(r1[1]);
    const double v = (1.0 - fy) * top + fy * bottom;
    const double rounded = math::floor(v + 0.5);
    return static_cast<std::uint8_t>(rounded < 0.0 ? 0.0 : (rounded > 255.0 ? 255.0 : rounded));
}

}  // namespace

Status OrthophotoConfig::validate() const noexcept {
    if (!std::isfinite(occlusion_margin_m) || occlusion_margin_m < 0.0) {
        return Status(StatusCode::kInvalidConfig, "orthophoto.occlusion_margin_m: must be finite and >= 0");
    }
    return Status::ok();
}

Status buildOrthophoto(const OrthophotoConfig& config, const terrain::GridConfig& grid, Span<const float> elevation_m,
                       Span<const NetworkStation> stations, Span<const StationImages> images,
                       const ImageView<std::uint8_t>& grey, const ImageView<std::uint16_t>& source,
                       OrthophotoStats* stats) noexcept {
    VTM_RETURN_IF_ERROR(config.validate());
    VTM_RETURN_IF_ERROR(checkInputs(grid, elevation_m, stations, images, grey, source));
    detail::ElevationSurface surface;
    surface.grid = grid;
    surface.elevation_m = elevation_m;
    surface.highest_m = config.occlusion_test ? detail::highestElevation(elevation_m) : 0.0;
    const Scene scene{&config, &surface, stations, images};
    OrthophotoStats st;
    for (std::int32_t row = 0; row < grid.rows; ++row) {
        const double north = grid.north_edge_m - (static_cast<double>(row) + 0.5) * grid.cell_m;
        for (std::int32_t col = 0; col < grid.cols; ++col) {
            const double east = grid.west_edge_m + (static_cast<double>(col) + 0.5) * grid.cell_m;
            const float h = elevation_m[static_cast<std::size_t>(row) * static_cast<std::size_t>(grid.cols) +
                                        static_cast<std::size_t>(col)];
            grey.row(row)[col] = 0U;
            source.row(row)[col] = kNoSource;
            if (terrain::isNoData(h)) {
                ++st.no_elevation;
                continue;
            }
            const Pick pick = pickImage(Vec3(north, east, -static_cast<double>(h)), scene, st.occluded_views);
            if (pick.source == kNoSource) {
                ++st.not_seen;
                continue;
            }
            grey.row(row)[col] = bilinear(imageOfEye(images[pick.source / 2U], eyeOf(static_cast<std::int32_t>(pick.source % 2U))), pick.pixel);
            source.row(row)[col] = pick.source;
            ++st.filled;
        }
    }
    if (stats != nullptr) {
        *stats = st;
    }
    return Status::ok();
}

}  // namespace vtm::kriging
