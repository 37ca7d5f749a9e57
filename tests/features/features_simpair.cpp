// Host measurement of TemplateMatcher on a simulator wide-baseline pair (not a test:
// prints, never fails). The pair is a `vtm-sim render` output directory holding
// mast_000.png, mast_001.png, mast.cmod, camera_poses.txt (TRUE T_site_from_camera of
// frames 0 and 1) and mast_000_range.pfm / mast_001_range.pfm (true range per pixel).
//
//   build/<dir>/tests/features/vtm_features_simpair [dir] [--window N] [--levels N]
//       [--min-score S] [--margin PX] [--no-normal] [--tilt W] [--spoil] [--repeat N] [--oracle]
//
// --tilt W: normal = normalise(site up + W * A's -z axis) (an experiment: a terrain seen
// at a grazing angle faces the camera more than the flat ground does). --oracle: first
// matches each feature alone with its true range +-3 % and a 2 px margin (the best the
// templates can do), then the normal run. --ceiling: NCC at the TRUE match with a square
// template and with the true local affine map from the range images (bilinear on both
// sides; CEIL_VERBOSE=1 lists them). SIMPAIR_VERBOSE=1 lists matches without a truth.
// Prediction: the true relative pose (or, with --spoil, B's pose turned 2 deg about the
// site vertical through B's centre and moved 5 % of the baseline sideways, horizontally
// perpendicular to the baseline), ranges 1..500 m, margin 60 px, the terrain normal = site
// up seen from A (unless --no-normal). Accuracy: each match's pixel_a is back-projected
// with the true range (bilinear in mast_000_range.pfm; skipped where the 4 neighbours differ by > 15 %),
// projected into B with the TRUE pose and compared with pixel_b; a match whose true point
// is hidden in B (B's true range shorter by > 5 %) counts as occluded, not in the figures.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "vtm/core/math.hpp"
#include "vtm/features/features.hpp"
#include "vtm/ground/camera_model_io.hpp"
#include "vtm/ground/image_io.hpp"
#include "vtm/ground/pfm.hpp"

namespace {

using namespace vtm;

struct Pose {
    Mat3 R = Mat3::Identity();  // site from camera
    Vec3 t = Vec3::Zero();      // camera centre in the site, metres
};

bool readPoses(const std::string& path, Pose& a, Pose& b) {
    std::ifstream in(path);
    std::string line;
    int found = 0;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#' || line.rfind("vtm-", 0) == 0) {
            continue;
        }
        std::istringstream ss(line);
        int frame = -1;
        std::string cam;
        long long ts = 0;
        double x = 0, y = 0, z = 0, qw = 1, qx = 0, qy = 0, qz = 0;
        if (!(ss >> frame >> cam >> ts >> x >> y >> z >> qw >> qx >> qy >> qz) || cam != "mast") {
            continue;
        }
        Pose p;
        p.R = Quat(qw, qx, qy, qz).normalized().toRotationMatrix();
        p.t = Vec3(x, y, z);
        if (frame == 0) {
            a = p;
            ++found;
        } else if (frame == 1) {
            b = p;
            ++found;
        }
    }
    return found == 2;
}

// Bilinear range at a subpixel position; false at the border, sky or a discontinuity.
bool rangeAt(const ground::FloatImage& r, const Vec2& p, double& out) {
    const auto x0 = static_cast<std::int32_t>(std::floor(p.x()));
    const auto y0 = static_cast<std::int32_t>(std::floor(p.y()));
    if (x0 < 0 || y0 < 0 || x0 + 1 >= r.width || y0 + 1 >= r.height) {
        return false;
    }
    const double v00 = r.at(x0, y0), v10 = r.at(x0 + 1, y0), v01 = r.at(x0, y0 + 1), v11 = r.at(x0 + 1, y0 + 1);
    const double lo = std::min({v00, v10, v01, v11}), hi = std::max({v00, v10, v01, v11});
    if (!std::isfinite(hi) || hi > 1.15 * lo) {
        return false;
    }
    const double fx = p.x() - x0, fy = p.y() - y0;
    out = (v00 * (1 - fx) + v10 * fx) * (1 - fy) + (v01 * (1 - fx) + v11 * fx) * fy;
    return true;
}

double bilinear(const ground::GreyImage& im, double x, double y) {
    const auto x0 = static_cast<std::int32_t>(std::floor(x)), y0 = static_cast<std::int32_t>(std::floor(y));
    if (x0 < 0 || y0 < 0 || x0 + 1 >= im.width || y0 + 1 >= im.height) {
        return std::nan("");
    }
    const double fx = x - x0, fy = y - y0;
    return (im.at(x0, y0) * (1 - fx) + im.at(x0 + 1, y0) * fx) * (1 - fy) +
           (im.at(x0, y0 + 1) * (1 - fx) + im.at(x0 + 1, y0 + 1) * fx) * fy;
}

// NCC of A(pa + Minv u) with B(pb + u) over a (2 half + 1)^2 grid (both bilinear).
double nccAt(const ground::GreyImage& a, const ground::GreyImage& b, const Vec2& pa, const Vec2& pb, const Mat3& minv,
             int half) {
    double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
    int n = 0;
    for (int dy = -half; dy <= half; ++dy) {
        for (int dx = -half; dx <= half; ++dx) {
            const double ux = minv(0, 0) * dx + minv(0, 1) * dy, uy = minv(1, 0) * dx + minv(1, 1) * dy;
            const double va = bilinear(a, pa.x() + ux, pa.y() + uy), vb = bilinear(b, pb.x() + dx, pb.y() + dy);
            if (std::isnan(va) || std::isnan(vb)) {
                return std::nan("");
            }
            sa += va; sb += vb; saa += va * va; sbb += vb * vb; sab += va * vb; ++n;
        }
    }
    const double v = (n * saa - sa * sa) * (n * sbb - sb * sb);
    return v > 0 ? (n * sab - sa * sb) / std::sqrt(v) : 0.0;
}

double percentile(std::vector<double> v, double q) {
    if (v.empty()) {
        return std::nan("");
    }
    std::sort(v.begin(), v.end());
    const auto i = static_cast<std::size_t>(std::min<double>(static_cast<double>(v.size() - 1), q * static_cast<double>(v.size() - 1) + 0.5));
    return v[i];
}

}  // namespace

int main(int argc, char** argv) {
    using namespace vtm::features;
    std::string dir = "/tmp/wb/sim2";
    MatcherConfig mc;
    double margin_px = 60.0;
    bool use_normal = true, spoil = false, oracle = false, ceiling = false;
    int repeat = 1;
    double tilt = 0.0;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&]() { return (i + 1 < argc) ? std::string(argv[++i]) : std::string("0"); };
        if (a == "--window") {
            mc.template_window = static_cast<std::int32_t>(std::strtol(next().c_str(), nullptr, 10));
        } else if (a == "--levels") {
            mc.pyramid_levels = static_cast<std::int32_t>(std::strtol(next().c_str(), nullptr, 10));
        } else if (a == "--min-score") {
            mc.min_score = std::strtof(next().c_str(), nullptr);
        } else if (a == "--margin") {
            margin_px = std::strtod(next().c_str(), nullptr);
        } else if (a == "--no-normal") {
            use_normal = false;
        } else if (a == "--spoil") {
            spoil = true;
        } else if (a == "--tilt") {
            tilt = std::strtod(next().c_str(), nullptr);
        } else if (a == "--ceiling") {
            ceiling = true;
        } else if (a == "--oracle") {
            oracle = true;
        } else if (a == "--repeat") {
            repeat = std::max(1, static_cast<std::int32_t>(std::strtol(next().c_str(), nullptr, 10)));
        } else {
            dir = a;
        }
    }
    const auto ia = ground::loadGrey8(dir + "/mast_000.png");
    const auto ib = ground::loadGrey8(dir + "/mast_001.png");
    const auto ra = ground::readPfm(dir + "/mast_000_range.pfm");
    const auto rb = ground::readPfm(dir + "/mast_001_range.pfm");
    CameraModel cam;
    Pose pa, pb;
    if (!ia.ok || !ib.ok || !ra.ok || !rb.ok || !ground::readCameraModelFile(dir + "/mast.cmod", cam).ok ||
        !readPoses(dir + "/camera_poses.txt", pa, pb)) {
        std::fprintf(stderr, "cannot read the pair in %s\n", dir.c_str());
        return 1;
    }
    const Mat3 R_true = pb.R.transpose() * pa.R;
    const Vec3 t_true = pb.R.transpose() * (pa.t - pb.t);
    Pose pb_pred = pb;
    if (spoil) {
        const double h = 2.0 * vtm::math::kPi / 180.0;
        Mat3 Rz;
        Rz << std::cos(h), -std::sin(h), 0.0, std::sin(h), std::cos(h), 0.0, 0.0, 0.0, 1.0;
        pb_pred.R = Rz * pb.R;
        Vec3 base = pb.t - pa.t;
        base.z() = 0.0;
        const Vec3 side = Vec3(-base.y(), base.x(), 0.0).normalized();
        pb_pred.t = pb.t + 0.05 * (pb.t - pa.t).norm() * side;
    }

    DetectorConfig dc;
    dc.max_width = ia.value.width;
    dc.max_height = ia.value.height;
    mc.max_width = ia.value.width;
    mc.max_height = ia.value.height;
    std::vector<std::byte> pool(ForstnerDetector::workspaceBytes(dc) + TemplateMatcher::workspaceBytes(mc));
    Arena arena(pool.data(), pool.size());
    ForstnerDetector detector;
    TemplateMatcher matcher;
    if (!detector.init(dc, arena).isOk() || !matcher.init(mc, arena).isOk()) {
        std::fprintf(stderr, "init failed\n");
        return 1;
    }
    const auto fs = std::make_unique<FeatureSet>();
    const auto out = std::make_unique<MatchSet>();
    if (!detector.detect(ia.value.view(), *fs).isOk()) {
        return 1;
    }
    MatchPrediction p;
    p.pair.model_a = cam;
    p.pair.model_b = cam;
    p.pair.b_from_a.R = pb_pred.R.transpose() * pa.R;
    p.pair.b_from_a.t_m = pb_pred.R.transpose() * (pa.t - pb_pred.t);
    p.range_min_m = 1.0;
    p.range_max_m = 500.0;
    p.margin_px = margin_px;
    if (use_normal) {
        p.surface_normal_a = pa.R.transpose() * Vec3(0.0, 0.0, -1.0);  // site up (z is down)
        p.surface_normal_a = (p.surface_normal_a + tilt * Vec3(0.0, 0.0, -1.0)).normalized();
    }
    if (ceiling) {  // debug: NCC at the true match with square and with true-affine templates
        auto tr = [&](const Vec2& q, Vec2& out_b) {
            CameraRay ray;
            double rr = 0.0;
            return rangeAt(ra.value, q, rr) && backProjectPixel(cam, q, ray).isOk() &&
                   projectPoint(cam, R_true * (ray.origin_m + rr * ray.direction) + t_true, out_b).isOk();
        };
        const int half = mc.template_window / 2;
        int n = 0, sq8 = 0, aff8 = 0;
        for (std::int32_t i = 0; i < fs->count; ++i) {
            const Vec2 q = fs->items[i].pixel;
            Vec2 tb, x0, x1, y0, y1;
            const double h = 3.0;
            if (!tr(q, tb) || !tr(q + Vec2(-h, 0), x0) || !tr(q + Vec2(h, 0), x1) || !tr(q + Vec2(0, -h), y0) ||
                !tr(q + Vec2(0, h), y1) || tb.x() < 20 || tb.y() < 20 || tb.x() > 491 || tb.y() > 491) {
                continue;
            }
            Mat3 m = Mat3::Identity();
            m(0, 0) = (x1 - x0).x() / (2 * h); m(1, 0) = (x1 - x0).y() / (2 * h);
            m(0, 1) = (y1 - y0).x() / (2 * h); m(1, 1) = (y1 - y0).y() / (2 * h);
            const double s_sq = nccAt(ia.value, ib.value, q, tb, Mat3::Identity(), half);
            const double s_aff = nccAt(ia.value, ib.value, q, tb, m.inverse(), half);
            ++n;
            sq8 += s_sq >= 0.8 ? 1 : 0;
            aff8 += s_aff >= 0.8 ? 1 : 0;
            if (std::getenv("CEIL_VERBOSE") != nullptr) {
                std::printf("ceil p (%.1f %.1f) -> (%.1f %.1f) M [%.2f %.2f; %.2f %.2f] square %.3f affine %.3f\n", q.x(), q.y(), tb.x(), tb.y(), m(0, 0), m(0, 1), m(1, 0), m(1, 1), s_sq, s_aff);
            }
        }
        std::printf("ceiling: %d features with truth inside B; NCC >= 0.8 at the truth: square %d, true affine %d\n", n, sq8, aff8);
    }
    if (oracle) {  // debug: each feature alone, ranges +-3 % around its true range, margin 2 px
        MatchStats total;
        const auto one = std::make_unique<FeatureSet>();
        std::vector<double> scores;
        for (std::int32_t i = 0; i < fs->count; ++i) {
            double r = 0.0;
            if (!rangeAt(ra.value, fs->items[i].pixel, r)) {
                continue;
            }
            one->items[0] = fs->items[i];
            one->count = 1;
            MatchPrediction q = p;
            q.range_min_m = 0.97 * r;
            q.range_max_m = 1.03 * r;
            q.margin_px = 2.0;
            MatchStats s1;
            (void)matcher.match(ia.value.view(), ib.value.view(), *one, q, *out, &s1);
            total.attempted += s1.attempted;
            total.no_region += s1.no_region;
            total.low_score += s1.low_score;
            total.not_refined += s1.not_refined;
            total.not_mutual += s1.not_mutual;
            total.matched += s1.matched;
        }
        std::printf("oracle: attempted %d matched %d no_region %d low_score %d not_refined %d not_mutual %d\n",
                    total.attempted, total.matched, total.no_region, total.low_score, total.not_refined, total.not_mutual);
    }
    MatchStats st;
    double best_ms = 1e30;
    for (int r = 0; r < repeat; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        if (!matcher.match(ia.value.view(), ib.value.view(), *fs, p, *out, &st).isOk()) {
            std::fprintf(stderr, "match failed\n");
            return 1;
        }
        best_ms = std::min(best_ms, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    std::vector<double> errs;
    int occluded = 0, no_truth = 0;
    for (std::int32_t i = 0; i < out->count; ++i) {
        const Match& m = out->items[i];
        CameraRay ray;
        double range_m = 0.0;
        Vec2 truth;
        if (!rangeAt(ra.value, m.pixel_a, range_m) || !backProjectPixel(cam, m.pixel_a, ray).isOk()) {
            if (std::getenv("SIMPAIR_VERBOSE") != nullptr) {
                const auto x = static_cast<std::int32_t>(m.pixel_a.x()), y = static_cast<std::int32_t>(m.pixel_a.y());
                std::printf("no truth: a (%.1f %.1f) b (%.1f %.1f) ranges %.1f %.1f %.1f %.1f\n", m.pixel_a.x(), m.pixel_a.y(),
                            m.pixel_b.x(), m.pixel_b.y(), ra.value.at(x, y), ra.value.at(x + 1, y), ra.value.at(x, y + 1),
                            ra.value.at(x + 1, y + 1));
            }
            ++no_truth;
            continue;
        }
        const Vec3 xb = R_true * (ray.origin_m + range_m * ray.direction) + t_true;
        double range_b = 0.0;
        if (!projectPoint(cam, xb, truth).isOk() || !rangeAt(rb.value, truth, range_b)) {
            ++no_truth;
            continue;
        }
        if (range_b < 0.95 * xb.norm()) {
            ++occluded;
            continue;
        }
        errs.push_back((truth - m.pixel_b).norm());
    }
    const auto within1 = std::count_if(errs.begin(), errs.end(), [](double e) { return e <= 1.0; });
    std::printf("pair %s, %s prediction, normal %s, window %d, levels %d, min_score %.2f, margin %.0f px\n",
                dir.c_str(), spoil ? "SPOILED (2 deg heading, 5 % baseline sideways)" : "true", use_normal ? "site up" : "none",
                mc.template_window, mc.pyramid_levels, static_cast<double>(mc.min_score), margin_px);
    std::printf("features %d: matched %d (no_region %d, low_score %d, not_refined %d, not_mutual %d); match() %.1f ms (best of %d)\n",
                fs->count, st.matched, st.no_region, st.low_score, st.not_refined, st.not_mutual, best_ms, repeat);
    std::printf("vs truth (%zu checked, %d occluded in B, %d without truth): median %.3f px, p90 %.3f px, "
                "within 1 px %.1f %%, max %.2f px\n",
                errs.size(), occluded, no_truth, percentile(errs, 0.5), percentile(errs, 0.9),
                errs.empty() ? 0.0 : 100.0 * static_cast<double>(within1) / static_cast<double>(errs.size()),
                errs.empty() ? 0.0 : *std::max_element(errs.begin(), errs.end()));
    return 0;
}
