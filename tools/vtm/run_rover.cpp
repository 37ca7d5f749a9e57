#include "run_rover.hpp"
#include "command_support.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>
#include <vector>

#include "hal/event_log.hpp"
#include "hal/posix/monotonic_clock.hpp"
#include "sim/render.hpp"
#include "vtm/app/wide_baseline_mapper.hpp"
#include "vtm/ground/disparity_colormap.hpp"
#include "vtm/ground/image_io.hpp"
#include "vtm/ground/pfm.hpp"
#include "vtm/ground/terrain_products.hpp"

namespace vtm::tools {
namespace {

using ground::FloatImage;
using ground::GreyImage;


// The flight defaults (docs/app.md) at the scenario camera's size; the mount is the
// simulator's camera pose in its vehicle frame (the calibration).
app::WideBaselineMapperConfig configFor(const sim::ScenarioFrame& f) {
    app::WideBaselineMapperConfig c;
    const std::int32_t w = f.model.width_px;
    const std::int32_t h = f.model.height_px;
    c.frame_width = w;  // the modules' capacities follow from the frame size
    c.frame_height = h;
    c.refine.match_margin_px = 75.0 * static_cast<double>(std::max(w, h)) / 1024.0;  // the heading error in pixels
    // Speckles: the default's share of a 1024 x 1024 image (100 px).
    c.speckle.max_region_px = static_cast<std::int32_t>(100LL * w * h / (1024LL * 1024LL));
    c.mount = cameraMountOf(f);
    return c;
}

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
}

struct RoverMeasures {
    double rot_before_deg = 0.0, rot_after_deg = 0.0;
    double dir_before_deg = 0.0, dir_after_deg = 0.0;
    double baseline_scale_error = 0.0;  // odometry baseline length / true - 1
    long long range_pixels = 0;         // image-1 pixels with a range and a true range
    double range_median = 0.0;          // |range - true| / true
    double range_within5 = 0.0;
    double range_true_median_m = 0.0;   // of the mapped pixels: how far the map reaches
    // Coverage of the band (issue 21): image-1 pixels whose true point image 2 sees, with a
    // true range in [band_min_m, band_max_m]; of those, how many got a range and how many
    // a range within 5 % of the truth; ranges published on sky or on pixels image 2 does
    // not see.
    double band_min_m = 0.0, band_max_m = 300.0;
    long long band_pixels = 0, band_ranged = 0, band_good = 0;
    double band_median = 0.0;
    long long ranged_on_sky = 0, ranged_unseen = 0;
    GreyImage coverage;  // RGB over image 1: band pixels green (within 5 %), red (beyond), blue (no range)
    long long cells = 0;
    double dz_median_m = 0.0;           // |map - terrain| at the cell centres
    double dz_mean_m = 0.0;
};

// Range of image 1's pixels from the mapper's published points (each triangulated from a
// rectified disparity, within the mapper's range and uncertainty limits): each point to the
// rectified left pixel whose ray it lies on (the nearer point wins), then each image-1
// pixel's ray into the rectified image and the range of the nearest rectified pixel there,
// from the rectified left centre. NaN where none. (Projecting the points into image 1
// directly left a grid of holes where the rectified pixels are sparser than image 1's.)
FloatImage rangeImage(const app::WideBaselineProducts& p) {
    const CameraModel& cam = p.camera;
    const terrain::RectifiedGeometry& g = p.triangulation_geometry;
    const std::int32_t rw = p.disparity_px16.width(), rh = p.disparity_px16.height();
    FloatImage rect(rw, rh, 1, std::nanf(""));
    const auto toRect = [&](const Vec3& v, std::int32_t& ix, std::int32_t& iy) {
        if (!(v.z() > 0.0)) return false;
        ix = static_cast<std::int32_t>(std::floor(g.fx_px * v.x() / v.z() + g.cx_left_px + 0.5));
        iy = static_cast<std::int32_t>(std::floor(g.fy_px * v.y() / v.z() + g.cy_px + 0.5));
        return ix >= 0 && iy >= 0 && ix < rw && iy < rh;
    };
    for (const terrain::TerrainPoint& tp : p.points) {
        const Vec3 d = Vec3(tp.x_m, tp.y_m, tp.z_m) - g.left_centre_site_m;
        std::int32_t ix = 0, iy = 0;
        if (!toRect(g.R_site_from_rect.transpose() * d, ix, iy)) continue;
        const auto r = static_cast<float>(d.norm());
        float& cell = rect.at(ix, iy);
        if (!(cell <= r)) cell = r;
    }
    FloatImage range(cam.width_px, cam.height_px, 1, std::nanf(""));
    const Mat3 R_rect_from_cam1 = g.R_site_from_rect.transpose() * p.site_from_cam1.R;
    for (std::int32_t y = 0; y < cam.height_px; ++y) {
        for (std::int32_t x = 0; x < cam.width_px; ++x) {
            CameraRay ray;
            std::int32_t ix = 0, iy = 0;
            if (!backProjectPixel(cam, Vec2(x, y), ray).isOk() || !toRect(R_rect_from_cam1 * ray.direction, ix, iy)) {
                continue;
            }
            range.at(x, y) = rect.at(ix, iy);
        }
    }
    return range;
}

GreyImage copy8(const ImageView<const std::uint8_t>& v) {
    GreyImage out(v.width(), v.height());
    for (std::int32_t y = 0; y < v.height(); ++y) {
        for (std::int32_t x = 0; x < v.width(); ++x) out.at(x, y) = v.row(y)[x];
    }
    return out;
}

// The band's coverage (RoverMeasures::band_*, ranged_*, coverage) from image 1's true range and
// site points and image 2's true range. Seen by camera 2: the point projects into image 2
// and image 2's true range there is the point's (within 1 %: not hidden behind other terrain).
void measureBand(const app::WideBaselineProducts& p, const sim::ScenarioFrame& f1, const sim::ScenarioFrame& f2,
                 const FloatImage& range, const std::vector<float>& truth, const std::vector<float>& point1,
                 const std::vector<float>& truth2, RoverMeasures& m) {
    const std::int32_t W = range.width, H = range.height;
    const auto seenBy2 = [&](std::size_t i) {
        const Vec3 site(point1[3 * i], point1[3 * i + 1], point1[3 * i + 2]);
        const Vec3 X2 = f2.camera_pose.R.transpose() * (site - f2.camera_pose.t_m);
        Vec2 px;
        if (!projectPoint(f2.model, X2, px).isOk()) return false;
        const auto ix = static_cast<std::int32_t>(std::floor(px.x() + 0.5));
        const auto iy = static_cast<std::int32_t>(std::floor(px.y() + 0.5));
        if (ix < 0 || iy < 0 || ix >= W || iy >= H) return false;
        const double r2 = truth2[static_cast<std::size_t>(iy) * static_cast<std::size_t>(W) + static_cast<std::size_t>(ix)];
        return std::isfinite(r2) && std::fabs(r2 - X2.norm()) <= 0.01 * X2.norm();
    };
    m.band_min_m = std::max(10.0, 2.5 * (f2.camera_pose.t_m - f1.camera_pose.t_m).norm());
    std::vector<double> band_rel;
    m.coverage = GreyImage(W, H, 3);
    for (std::int32_t y = 0; y < H; ++y) {
        for (std::int32_t x = 0; x < W; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(W) + static_cast<std::size_t>(x);
            const float r = range.at(x, y);
            const float t = truth[i];
            const bool seen = std::isfinite(t) && seenBy2(i);
            if (std::isfinite(r) && !std::isfinite(t)) ++m.ranged_on_sky;
            if (std::isfinite(r) && std::isfinite(t) && !seen) ++m.ranged_unseen;
            const std::uint8_t grey = static_cast<std::uint8_t>(p.image1.row(y)[x] / 2);
            std::uint8_t rgb[3] = {grey, grey, grey};
            if (seen && t >= m.band_min_m && t <= m.band_max_m) {
                ++m.band_pixels;
                rgb[0] = rgb[1] = 0;
                rgb[2] = 255;
                if (std::isfinite(r)) {
                    const double e = std::fabs(static_cast<double>(r - t)) / t;
                    ++m.band_ranged;
                    m.band_good += e <= 0.05 ? 1 : 0;
                    band_rel.push_back(e);
                    rgb[0] = e <= 0.05 ? 0 : 255;
                    rgb[1] = e <= 0.05 ? 255 : 0;
                    rgb[2] = 0;
                }
            }
            for (std::int32_t c = 0; c < 3; ++c) m.coverage.at(x, y, c) = rgb[c];
        }
    }
    m.band_median = median(band_rel);
}

RoverMeasures measure(const ground::SimWorld& w, const app::WideBaselineProducts& p, const FloatImage& range) {
    RoverMeasures m;
    const sim::ScenarioFrame* f1 = ground::frameAt(w, p.frame1.timestamp_ns);
    const sim::ScenarioFrame* f2 = ground::frameAt(w, p.frame2.timestamp_ns);
    if (f1 == nullptr || f2 == nullptr) return m;
    const Mat3 R_true = f2->camera_pose.R.transpose() * f1->camera_pose.R;
    const Vec3 t_true = f2->camera_pose.R.transpose() *
                        (f1->camera_pose.t_m - f2->camera_pose.t_m);
    m.rot_before_deg = kDegPerRad * motion::rotationAngleRad(p.odometry_2_from_1.R, R_true);
    m.rot_after_deg = kDegPerRad * motion::rotationAngleRad(p.refine.motion.R_b_from_a, R_true);
    m.dir_before_deg = kDegPerRad * motion::directionAngleRad(p.odometry_2_from_1.t_m, t_true);
    m.dir_after_deg = kDegPerRad * motion::directionAngleRad(p.refine.motion.t_b_from_a_m, t_true);
    m.baseline_scale_error = p.odometry_2_from_1.t_m.norm() / t_true.norm() - 1.0;
    // The renderer's true range of image 1.
    const std::int32_t W = range.width, H = range.height;
    std::vector<std::uint8_t> img(static_cast<std::size_t>(W) * static_cast<std::size_t>(H));
    std::vector<std::uint16_t> img16(img.size());
    std::vector<float> truth(img.size());
    sim::FrameOutput o;
    if (w.scenario.sensor.bit_depth > 8) {
        o.image16 = ImageView<std::uint16_t>(img16.data(), W, H);
    } else {
        o.image8 = ImageView<std::uint8_t>(img.data(), W, H);
    }
    o.truth.range_m = ImageView<float>(truth.data(), W, H);
    std::vector<float> point1(img.size() * 3U);
    o.truth.point_site_m = ImageView<float>(point1.data(), W * 3, H);
    if (!sim::renderFrame(sim::scenarioFrameRequest(w.scenario, w.terrain, *f1), o, nullptr).isOk()) return m;
    std::vector<float> truth2(img.size());
    o.truth = sim::FrameTruth{};
    o.truth.range_m = ImageView<float>(truth2.data(), W, H);
    if (!sim::renderFrame(sim::scenarioFrameRequest(w.scenario, w.terrain, *f2), o, nullptr).isOk()) return m;
    measureBand(p, *f1, *f2, range, truth, point1, truth2, m);
    std::vector<double> rel, reach;
    for (std::int32_t y = 0; y < H; ++y) {
        for (std::int32_t x = 0; x < W; ++x) {
            const float r = range.at(x, y);
            const float t = truth[static_cast<std::size_t>(y) * static_cast<std::size_t>(W) + static_cast<std::size_t>(x)];
            if (!std::isfinite(r) || !std::isfinite(t)) continue;
            rel.push_back(std::fabs(static_cast<double>(r - t)) / t);
            reach.push_back(t);
        }
    }
    m.range_pixels = static_cast<long long>(rel.size());
    m.range_median = median(rel);
    m.range_true_median_m = median(reach);
    m.range_within5 = rel.empty() ? 0.0
                                  : static_cast<double>(std::count_if(rel.begin(), rel.end(),
                                                                      [](double e) { return e <= 0.05; })) /
                                        static_cast<double>(rel.size());
    const terrain::HeightMap& map = *p.height_map;
    const terrain::GridConfig& g = map.grid();
    std::vector<double> dz;
    double sum = 0.0;
    for (std::int32_t row = 0; row < g.rows; ++row) {
        for (std::int32_t col = 0; col < g.cols; ++col) {
            if (map.count(col, row) == 0U) continue;
            const double e = static_cast<double>(map.elevation(col, row)) -
                             w.terrain.elevationAt(map.centreNorthM(row), map.centreEastM(col));
            dz.push_back(std::fabs(e));
            sum += e;
        }
    }
    m.cells = static_cast<long long>(dz.size());
    m.dz_median_m = median(dz);
    m.dz_mean_m = dz.empty() ? 0.0 : sum / static_cast<double>(dz.size());
    return m;
}

std::string writeProducts(const std::string& dir, const app::WideBaselineProducts& p, const FloatImage& range,
                          const GreyImage& coverage) {
    const std::string base = dir + "/rover_";
    FloatImage disparity(p.disparity_px16.width(), p.disparity_px16.height(), 1, std::nanf(""));
    float lo = 1e9F, hi = -1e9F;  // the colours span the disparities found (the range searched is far wider)
    for (std::int32_t y = 0; y < disparity.height; ++y) {
        for (std::int32_t x = 0; x < disparity.width; ++x) {
            const std::int16_t d = p.disparity_px16.row(y)[x];
            if (d == stereo::kNoDisparity) continue;
            const float v = static_cast<float>(d) / stereo::kDisparityScale;
            disparity.at(x, y) = v;
            lo = std::min(lo, v);
            hi = std::max(hi, v);
        }
    }
    if (lo > hi) lo = hi = 0.0F;
    std::vector<Vec3> points;
    points.reserve(p.points.size());
    for (const terrain::TerrainPoint& q : p.points) points.emplace_back(q.x_m, q.y_m, q.z_m);
    const FloatImage elevation = ground::elevationImage(*p.height_map);
    ground::Outcome r = ground::writePng(base + "image1.png", copy8(p.image1));
    if (r.ok) r = ground::writePng(base + "image2.png", copy8(p.image2));
    if (r.ok) r = ground::writePng(base + "rectified1.png", copy8(p.rectified1));
    if (r.ok) r = ground::writePng(base + "rectified2.png", copy8(p.rectified2));
    if (r.ok) r = ground::writePfm(base + "disparity.pfm", disparity);
    if (r.ok) {
        r = ground::writePng(base + "disparity.png",
                             ground::colorizeDisparity(disparity, lo, hi));
    }
    if (r.ok) r = ground::writePfm(base + "range.pfm", range);
    if (r.ok) r = ground::writePng(base + "coverage.png", coverage);
    for (const auto& [name, view] : {std::pair<const char*, ImageView<const std::int16_t>>{"surface.pfm", p.surface_px},
                                     {"prior.pfm", p.prior_px}}) {
        FloatImage f(view.width(), view.height(), 1, std::nanf(""));
        for (std::int32_t y = 0; y < f.height; ++y) {
            for (std::int32_t x = 0; x < f.width; ++x) {
                if (view.row(y)[x] != stereo::kNoDisparity) f.at(x, y) = view.row(y)[x];
            }
        }
        if (r.ok) r = ground::writePfm(base + name, f);
    }
    if (r.ok) r = ground::writePfm(base + "elevation.pfm", elevation);
    if (r.ok) {
        r = ground::writePng(base + "elevation.png",
                             ground::shadedRelief(ground::cropToFinite(elevation), p.height_map->grid().cell_m));
    }
    if (r.ok) r = ground::writePly(base + "points.ply", points);
    return r.ok ? "" : r.error;
}

}  // namespace

app::CameraMount cameraMountOf(const sim::ScenarioFrame& f) {
    const RigidPose vehicle_from_camera = sim::vehicleFromCamera(f);
    app::CameraMount m;
    m.R_vehicle_from_camera = vehicle_from_camera.R;
    m.position_vehicle_m = vehicle_from_camera.t_m;
    return m;
}

std::string flyRover(const ground::SimWorld& world, hal::Camera& camera, hal::Odometry& odometry,
                     const std::string& out_dir, std::string& section, bool& mapped) {
    mapped = false;
    const auto t0 = std::chrono::steady_clock::now();
    hal::MonotonicClock clock;
    auto events = std::make_unique<hal::EventLog>();
    const app::WideBaselineMapperConfig config = configFor(world.frames->frames[0]);
    std::vector<std::byte> pool(app::WideBaselineMapper::workspaceBytes(config) + 64U);
    Arena arena(pool.data(), pool.size());
    auto mapper = std::make_unique<app::WideBaselineMapper>();
    Status st = mapper->init(config, arena, camera, odometry, clock, *events);
    if (!st.isOk()) return std::string("WideBaselineMapper::init: ") + st.reason();
    arena.freeze();
    std::fprintf(stderr, "vtm run: rover pair: mapping (%d x %d, coarse to fine)\n", config.frame_width,
                 config.frame_height);
    const auto tm = std::chrono::steady_clock::now();
    st = mapper->map();
    const double map_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - tm).count();
    std::ostringstream md;
    char b[2048];
    md << "## Rover wide-baseline pair\n\n"
       << "The executive `WideBaselineMapper` (fsw/app) on frames 0 and 1 of the mast camera, the poses from the "
          "odometry with its navigation errors. Frames "
       << config.frame_width << " x " << config.frame_height << ", stereo coarse to fine (" << config.stereo.coarse_disparities
       << " disparities at 1/" << (1 << config.stereo.levels) << " resolution around the inliers' plane, +-"
       << config.stereo.fine_radius_px << " px at full resolution), ranges " << config.range_min_m << ".." << config.range_max_m << " m, height map "
       << config.height_map.grid.cols << " x " << config.height_map.grid.rows << " cells of "
       << config.height_map.grid.cell_m
       << " m; mapper memory planned at init: " << mapper->memoryBytes() << " bytes.\n\n";
    const app::WideBaselineProducts* p = mapper->products();
    if (!st.isOk() || p == nullptr) {
        const app::StageRecord* f = mapper->stages().failed();
        const std::string failure = std::string(f != nullptr ? app::stageName(f->stage) : "?") + ": " + st.reason();
        std::fprintf(stderr, "vtm run: rover pair failed at %s\n", failure.c_str());
        md << "**Request failed** at " << failure << ".\n\n";
        section = md.str();
        return "";
    }
    mapped = true;
    const FloatImage range = rangeImage(*p);
    const RoverMeasures m = measure(world, *p, range);
    const std::string written = writeProducts(out_dir, *p, range, m.coverage);
    if (!written.empty()) return written;
    std::snprintf(b, sizeof b,
                  "| figure | value |\n|---|---|\n"
                  "| matches / inliers | %d / %d |\n"
                  "| rotation error against truth: odometry -> refined | %.3f -> %.3f deg |\n"
                  "| translation direction error: odometry -> refined | %.3f -> %.3f deg |\n"
                  "| vertical disparity the refiner predicts after rectification | %.3f px |\n"
                  "| rotation / direction uncertainty the refiner predicts (1 sigma) | %.3f / %.3f deg |\n"
                  "| baseline length error (odometry, kept) | %+.2f %% |\n"
                  "| exposure gain applied to rectified 2 (1: the pair's medians agreed) | %.3f |\n"
                  "| disparity range searched | %d..%d px (coarse level: %d of %d pixels found, %d filled) |\n"
                  "| disparities found / dropped as speckles / dropped by the ground bound | %d / %d / %d |\n"
                  "| points triangulated | %d |\n"
                  "| image-1 pixels with a range | %lld (%.1f %%), true range median %.1f m |\n"
                  "| range error: median / within 5 %% | %.2f %% / %.1f %% |\n"
                  "| band %.1f..%.0f m (image-1 pixels image 2 sees there) | %lld |\n"
                  "| coverage / good coverage of the band / median range error there | %.1f %% / %.1f %% / %.2f %% |\n"
                  "| ranges published on sky / on pixels image 2 does not see | %lld / %lld |\n"
                  "| height map: cells / median abs error / mean error | %lld / %.3f m / %+.3f m |\n"
                  "| time of the request | %.2f s |\n\n",
                  p->refine.matching.matched, p->refine.motion.inliers, m.rot_before_deg, m.rot_after_deg, m.dir_before_deg,
                  m.dir_after_deg, p->refine.motion.epipolar_sigma_px, kDegPerRad * p->refine.motion.rotation_sigma_rad,
                  kDegPerRad * p->refine.motion.direction_sigma_rad, 100.0 * m.baseline_scale_error,
                  static_cast<double>(p->exposure_gain_q16) / 65536.0, p->disparity_min, p->disparity_max,
                  p->pyramid.coarse.valid_pixels,
                  (p->disparity_px16.width() >> config.stereo.levels) * (p->disparity_px16.height() >> config.stereo.levels),
                  p->pyramid.coarse_filled, p->stereo.valid_pixels + p->speckles, p->speckles, p->outside_window, p->triangulation.points,
                  m.range_pixels, 100.0 * static_cast<double>(m.range_pixels) / (range.width * range.height),
                  m.range_true_median_m, 100.0 * m.range_median, 100.0 * m.range_within5, m.band_min_m, m.band_max_m,
                  m.band_pixels, m.band_pixels > 0 ? 100.0 * static_cast<double>(m.band_ranged) / static_cast<double>(m.band_pixels) : 0.0,
                  m.band_pixels > 0 ? 100.0 * static_cast<double>(m.band_good) / static_cast<double>(m.band_pixels) : 0.0,
                  100.0 * m.band_median, m.ranged_on_sky, m.ranged_unseen, m.cells, m.dz_median_m,
                  m.dz_mean_m, map_s);
    md << b
       << "Range and height errors are against the renderer's true range of image 1 and the terrain's elevation at "
          "the cell centres. The band is where the wide-baseline map is meant to work (issue 21): true range from "
          "max(10 m, 2.5 x baseline) to 300 m; coverage = band pixels with a range / band pixels, good coverage = band "
          "pixels with a range within 5 % of the truth / band pixels (an image-1 pixel's range: that of the published "
          "point on the rectified pixel its ray meets). A residual rotation error about the vertical shifts every disparity alike and scales "
          "the far ranges (docs/app.md).\n\n"
       << "### Time per stage (ms, hal::MonotonicClock on this host)\n\n|";
    for (std::size_t i = 0; i < mapper->stages().size(); ++i) md << " " << app::stageName(mapper->stages().at(i).stage) << " |";
    md << "\n|";
    for (std::size_t i = 0; i < mapper->stages().size(); ++i) md << "---|";
    md << "\n|";
    for (std::size_t i = 0; i < mapper->stages().size(); ++i) {
        std::snprintf(b, sizeof b, " %.1f |", 1e-6 * static_cast<double>(mapper->stages().at(i).duration_ns));
        md << b;
    }
    md << "\n\n### Products\n\n"
       << "Image 1, image 2 (after the drive), the rectified pair, the disparity of rectified image 1 (near red ... "
          "far purple, black: none) and the shaded height map (north up):\n\n"
       << "![image 1](rover_image1.png) ![image 2](rover_image2.png)\n"
       << "![rectified 1](rover_rectified1.png) ![rectified 2](rover_rectified2.png)\n"
       << "![disparity](rover_disparity.png) ![elevation](rover_elevation.png)\n\n"
       << "The band's coverage over image 1 (green: a range within 5 %, red: a range beyond 5 %, blue: no range; "
          "grey: outside the band or not seen by image 2):\n\n![coverage](rover_coverage.png)\n\n"
       << "Files: `rover_disparity.pfm` (px, NaN = none), `rover_range.pfm` (metres per pixel of image 1), "
          "`rover_elevation.pfm` (metres, north up, NaN = NO_DATA), `rover_points.ply` (site frame).\n\n";
    section = md.str();
    std::fprintf(stderr, "vtm run: rover pair: inlier plane d = %.4f x + %.4f y + %.1f (%d used, %.2f px)\n",
                 p->inlier_plane.a, p->inlier_plane.b, p->inlier_plane.c, p->inlier_plane.used,
                 p->inlier_plane.residual_px);
    std::fprintf(stderr, "vtm run: rover pair mapped in %.1f s: %lld points, median range error %.2f %%\n",
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
                 static_cast<long long>(p->triangulation.points), 100.0 * m.range_median);
    return "";
}

}  // namespace vtm::tools
