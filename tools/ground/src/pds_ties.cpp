// Tie points between neighbouring PDS frames with fsw/features (pds_panorama.hpp).
#include <cmath>
#include <cstddef>
#include <memory>

#include "vtm/core/arena.hpp"
#include "vtm/core/pose.hpp"
#include "vtm/features/features.hpp"
#include "vtm/ground/pds_panorama.hpp"

namespace vtm::ground {
namespace {

// rover B from rover A: X_b = R_b^T (R_a X_a + t_a - t_b).
RigidPose bFromA(const PdsImage& a, const PdsImage& b) { return relativePose(a.site_from_rover, b.site_from_rover); }

double segmentDistance(const Vec2& p, const Vec2& s0, const Vec2& s1) {
    const Vec2 d = s1 - s0;
    const double len2 = d.squaredNorm();
    const double t = len2 > 0.0 ? std::min(1.0, std::max(0.0, (p - s0).dot(d) / len2)) : 0.0;
    return (p - (s0 + t * d)).norm();
}

features::MatchPrediction prediction(const PdsImage& a, const PdsImage& b, const PdsTieConfig& config) {
    features::MatchPrediction p;
    p.pair.model_a = a.camera_model;
    p.pair.model_b = b.camera_model;
    p.pair.b_from_a = bFromA(a, b);
    p.range_min_m = config.range_min_m;
    p.range_max_m = config.range_max_m;
    p.margin_px = config.margin_px;
    p.surface_normal_a = a.site_from_rover.R.transpose() * Vec3(0.0, 0.0, -1.0);  // site up (z down)
    return p;
}

}  // namespace

bool pdsTransferPixel(const PdsImage& a, const PdsImage& b, const Vec2& pixel_a, double range_m, Vec2& pixel_b) {
    CameraRay ray;
    if (!backProjectPixel(a.camera_model, pixel_a, ray).isOk()) return false;
    const Vec3 x_b = transformPoint(bFromA(a, b), ray.origin_m + range_m * ray.direction);
    return projectPoint(b.camera_model, x_b, pixel_b).isOk();
}

double pdsEpipolarDistance(const PdsImage& a, const PdsImage& b, const Vec2& pixel_a, const Vec2& pixel_b,
                           double range_min_m) {
    constexpr int kSegments = 512;
    double best = 1e300;
    Vec2 previous;
    bool have_previous = false;
    for (int k = 0; k <= kSegments; ++k) {
        // inverse range from 1 / range_min_m down to (nearly) 0: the point at infinity as 1e7 m.
        const double inverse = (1.0 / range_min_m) * static_cast<double>(kSegments - k) / kSegments;
        const double range = inverse > 0.0 ? 1.0 / inverse : 1e7;
        Vec2 px;
        if (!pdsTransferPixel(a, b, pixel_a, range, px)) {
            have_previous = false;
            continue;
        }
        best = std::min(best, have_previous ? segmentDistance(pixel_b, previous, px) : (pixel_b - px).norm());
        previous = px;
        have_previous = true;
    }
    return best;
}

Result<PdsTieResult> matchPdsNeighbours(const PdsImage& a, const PdsImage& b, const PdsTieConfig& config) {
    for (const PdsImage* f : {&a, &b}) {
        if (!f->has_camera_model || !f->has_rover_pose || f->pixels.empty()) {
            return Result<PdsTieResult>::failure(f->info.product_id + ": tie points need an image, a camera model and a rover pose");
        }
    }
    const GreyImage ga = pdsStretchToGrey8(a.pixels), gb = pdsStretchToGrey8(b.pixels);
    features::DetectorConfig dc;
    dc.max_width = dc.max_height = 1024;
    dc.grid_cols = 8;
    dc.grid_rows = 16;
    dc.per_cell = 4;
    features::MatcherConfig mc;
    mc.max_width = mc.max_height = 1024;
    mc.template_window = 15;
    mc.min_score = config.min_score;
    std::vector<std::byte> pool(features::ForstnerDetector::workspaceBytes(dc) +
                                features::TemplateMatcher::workspaceBytes(mc));
    Arena arena(pool.data(), pool.size());
    features::ForstnerDetector detector;
    features::TemplateMatcher matcher;
    if (!detector.init(dc, arena).isOk() || !matcher.init(mc, arena).isOk()) {
        return Result<PdsTieResult>::failure(a.info.product_id + ": feature detector or matcher refused its configuration");
    }
    const features::MatchPrediction p = prediction(a, b, config);
    features::VisibilityPrior prior;
    prior.up_a = p.surface_normal_a;
    prior.camera_height_m = config.camera_height_m;
    prior.margin_px = 16.0;
    GreyImage mask(ga.width, ga.height);
    std::int64_t visible = 0;
    const Status vs = features::predictVisibility(p, prior, mask.view(), visible);
    if (!vs.isOk()) return Result<PdsTieResult>::failure(a.info.product_id + ": visibility: " + vs.reason());
    PdsTieResult out;
    if (visible == 0) return Result<PdsTieResult>::success(out);
    const auto fs = std::make_unique<features::FeatureSet>();
    const auto ms = std::make_unique<features::MatchSet>();
    const Status ds = detector.detect(ga.view(), *fs, nullptr, mask.view());
    if (!ds.isOk()) return Result<PdsTieResult>::failure(a.info.product_id + ": detector: " + ds.reason());
    features::MatchStats stats;
    const Status m = matcher.match(ga.view(), gb.view(), *fs, p, *ms, &stats);
    if (!m.isOk()) return Result<PdsTieResult>::failure(a.info.product_id + ": matcher: " + m.reason());
    out.features = fs->count;
    out.attempted = stats.attempted;
    out.low_score = stats.low_score;
    out.not_refined = stats.not_refined;
    out.not_mutual = stats.not_mutual;
    out.no_region = stats.no_region;
    for (std::int32_t i = 0; i < ms->count; ++i) {
        PdsTie t;
        t.pixel_a = ms->items[i].pixel_a;
        t.pixel_b = ms->items[i].pixel_b;
        t.score = ms->items[i].score;
        t.epipolar_px = pdsEpipolarDistance(a, b, t.pixel_a, t.pixel_b, config.range_min_m);
        Vec2 far;
        t.sphere_px = pdsTransferPixel(a, b, t.pixel_a, config.sphere_radius_m, far) ? (far - t.pixel_b).norm() : -1.0;
        out.ties.push_back(t);
    }
    return Result<PdsTieResult>::success(out);
}

}  // namespace vtm::ground
