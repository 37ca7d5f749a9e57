// Evaluation harness of the wide-baseline front end: see wide_baseline_harness.hpp.
#include "wide_baseline_harness.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <random>
#include <sstream>
#include <utility>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "vtm/motion/motion_refiner.hpp"
#include "vtm/refine/pair_refiner.hpp"
#include "vtm/rectify/rectifier.hpp"
#include "vtm/stereo/ml_stereo.hpp"

namespace vtm::eval {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
// A match is "correct" within this distance of its true position (FrontEndResult,
// TrueLineCeiling).
constexpr double kCorrectMatch_px = 2.0;

double secondsSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Replaces the value of `key` in `section` ("" = the header before any section) of a
// scenario text; a key the file does not give is added at the top of its section.
bool setKey(std::string& text, const std::string& section, const std::string& key, const std::string& value) {
    std::istringstream in(text);
    std::ostringstream out;
    std::string line;
    std::string current;
    std::string prefix = key;
    prefix += ' ';
    bool done = false;
    while (std::getline(in, line)) {
        if (!line.empty() && line[0] == '[') {
            current = line.substr(1, line.find(']') - 1);
        } else if (!done && current == section && line.rfind(prefix, 0) == 0) {
            line = prefix;
            line += value;
            done = true;
        }
        out << line << '\n';
    }
    if (!done && !section.empty()) {  // a key the file does not give: append it to its section
        std::istringstream again(out.str());
        std::ostringstream with;
        current.clear();
        while (std::getline(again, line)) {
            with << line << '\n';
            if (!done && line == "[" + section + "]") {
                with << key << ' ' << value << '\n';
                done = true;
            }
        }
        text = with.str();
        return done;
    }
    text = out.str();
    return done;
}

std::string num(double v) {
    std::ostringstream s;
    s.precision(17);
    s << v;
    return s.str();
}

Mat3 rotationAbout(const Vec3& axis, double angle_rad) {
    return Eigen::AngleAxisd(angle_rad, axis.normalized()).toRotationMatrix();
}

// Bilinear sample of a float image (channels per pixel, channel c); false if any of the
// four neighbours is NaN or outside.
bool bilinear(const std::vector<float>& img, int w, int h, int channels, int c, const Vec2& p, double& value) {
    const double fx = std::floor(p.x());
    const double fy = std::floor(p.y());
    const int x0 = static_cast<int>(fx);
    const int y0 = static_cast<int>(fy);
    if (x0 < 0 || y0 < 0 || x0 + 1 >= w || y0 + 1 >= h) {
        return false;
    }
    const double ax = p.x() - fx;
    const double ay = p.y() - fy;
    const auto at = [&](int x, int y) {
        return static_cast<double>(img[(static_cast<std::size_t>(y) * static_cast<std::size_t>(w) +
                                         static_cast<std::size_t>(x)) * static_cast<std::size_t>(channels) +
                                        static_cast<std::size_t>(c)]);
    };
    const double v00 = at(x0, y0), v10 = at(x0 + 1, y0), v01 = at(x0, y0 + 1), v11 = at(x0 + 1, y0 + 1);
    if (!std::isfinite(v00) || !std::isfinite(v10) || !std::isfinite(v01) || !std::isfinite(v11)) {
        return false;
    }
    value = (1 - ay) * ((1 - ax) * v00 + ax * v10) + ay * ((1 - ax) * v01 + ax * v11);
    return true;
}

// Bilinear range with a smoothness check: the four neighbours within `tolerance`
// (relative) of each other, so that a sample never straddles a depth edge.
bool smoothRange(const std::vector<float>& range, int w, int h, const Vec2& p, double tolerance, double& value) {
    if (!bilinear(range, w, h, 1, 0, p, value)) {
        return false;
    }
    const int x0 = static_cast<int>(std::floor(p.x()));
    const int y0 = static_cast<int>(std::floor(p.y()));
    double lo = 1e300, hi = -1e300;
    for (int dy = 0; dy < 2; ++dy) {
        for (int dx = 0; dx < 2; ++dx) {
            const double v = range[static_cast<std::size_t>(y0 + dy) * static_cast<std::size_t>(w) +
                                   static_cast<std::size_t>(x0 + dx)];
            lo = std::min(lo, v);
            hi = std::max(hi, v);
        }
    }
    return hi - lo <= tolerance * lo;
}

cv::Mat cameraMatrix(const CameraModel& m) {
    return (cv::Mat_<double>(3, 3) << m.fx_px, 0.0, m.cx_px, 0.0, m.fy_px, m.cy_px, 0.0, 0.0, 1.0);
}

cv::Mat toCv(const Mat3& r) {
    cv::Mat out(3, 3, CV_64F);
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            out.at<double>(i, j) = r(i, j);
        }
    }
    return out;
}

VerticalDisparity summarise(const std::vector<double>& dy) {
    VerticalDisparity v;
    if (dy.empty()) {
        v.error = "no correspondences";
        return v;
    }
    double sum2 = 0.0;
    for (const double d : dy) {
        sum2 += d * d;
        v.max_abs_px = std::max(v.max_abs_px, std::fabs(d));
    }
    v.ok = true;
    v.count = static_cast<int>(dy.size());
    v.rms_px = std::sqrt(sum2 / static_cast<double>(dy.size()));
    return v;
}

double median(std::vector<double> v) {
    if (v.empty()) {
        return std::nan("");
    }
    const std::size_t mid = v.size() / 2U;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
    return v[mid];
}

}  // namespace

RelativePose relativePose(const RigidPose& a, const RigidPose& b) {
    RelativePose p;
    p.R_b_from_a = b.R.transpose() * a.R;
    p.t_b_from_a_m = b.R.transpose() * (a.t_m - b.t_m);
    return p;
}

double rotationErrorDeg(const Mat3& estimate, const Mat3& truth) {
    const Mat3 d = estimate * truth.transpose();
    const double c = std::clamp(0.5 * (d.trace() - 1.0), -1.0, 1.0);
    // acos loses precision near 0: use the skew part as well.
    const Vec3 s(d(2, 1) - d(1, 2), d(0, 2) - d(2, 0), d(1, 0) - d(0, 1));
    return std::atan2(0.5 * s.norm(), c) / kDeg;
}

double directionErrorDeg(const Vec3& estimate, const Vec3& truth) {
    return std::atan2(estimate.cross(truth).norm(), estimate.dot(truth)) / kDeg;
}

// ---- world and pairs ------------------------------------------------------------------

bool buildWorld(const std::string& scn_path, const WorldSpec& spec, World& world, std::string& error) {
    std::ifstream in(scn_path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    std::string text = s.str();
    if (text.empty()) {
        error = "cannot read " + scn_path;
        return false;
    }
    bool ok = setKey(text, "", "seed", std::to_string(spec.seed));
    ok = ok && setKey(text, "terrain", "samples_log2", std::to_string(spec.samples_log2));
    ok = ok && setKey(text, "terrain", "levels", std::to_string(spec.levels));
    ok = ok && setKey(text, "terrain", "finest_cell_m", num(spec.finest_cell_m));
    if (spec.hillside) {
        ok = ok && setKey(text, "terrain", "hills_start_m", num(kHillsideStart_m));
        ok = ok && setKey(text, "terrain", "hills_full_m", num(kHillsideFull_m));
        ok = ok && setKey(text, "terrain", "hills_amplitude_m", num(kHillsideAmplitude_m));
        ok = ok && setKey(text, "terrain", "hills_wavelength_m", num(kHillsideWavelength_m));
    }
    if (!ok) {
        error = "scenario text: a key to override is missing";
        return false;
    }
    world.base_text = text;
    Status st = sim::parseScenario(text, world.scenario);
    if (!st.isOk()) {
        error = std::string("parseScenario: ") + st.reason() + " line " + std::to_string(st.detail());
        return false;
    }
    const auto t0 = std::chrono::steady_clock::now();
    world.pool.assign(sim::scenarioTerrainBytes(world.scenario) + 64U, std::byte{0});
    world.arena = std::make_unique<Arena>(world.pool.data(), world.pool.size());
    st = sim::buildScenarioTerrain(world.scenario, *world.arena, world.terrain);
    world.build_seconds = secondsSince(t0);
    if (!st.isOk()) {
        error = std::string("buildScenarioTerrain: ") + st.reason();
        return false;
    }
    return true;
}

double aimedTiltDeg(const PairSpec& spec) {
    constexpr double kMastHeightM = 1.9;  // rover_wide_baseline.scn mount_position_m
    double d = (spec.convergence_deg > 0.0)
                   ? 0.5 * spec.baseline_m / std::tan(0.5 * spec.convergence_deg * kDeg)
                   : 4.0 * spec.baseline_m;
    d = std::min(80.0, std::max(5.0, d));
    return -std::atan(kMastHeightM / d) / kDeg;
}

bool renderPair(const World& world, const PairSpec& spec, RenderedPair& pair, std::string& error) {
    std::string text = world.base_text;
    bool ok = setKey(text, "camera", "width_px", std::to_string(spec.size_px));
    if (spec.aim_at_convergence) {
        ok = ok && setKey(text, "camera", "mount_tilt_deg", num(aimedTiltDeg(spec)));
    }
    ok = ok && setKey(text, "camera", "height_px", std::to_string(spec.size_px));
    ok = ok && setKey(text, "motion", "baseline_m", num(spec.baseline_m));
    ok = ok && setKey(text, "motion", "convergence_deg", num(spec.convergence_deg));
    ok = ok && setKey(text, "lighting", "shadows", spec.shadows ? "true" : "false");
    if (!ok) {
        error = "scenario text: a key to override is missing";
        return false;
    }
    sim::Scenario sc;
    Status st = sim::parseScenario(text, sc);
    if (!st.isOk()) {
        error = std::string("parseScenario: ") + st.reason() + " line " + std::to_string(st.detail());
        return false;
    }
    auto frames = std::make_unique<sim::ScenarioFrames>();
    st = sim::buildScenarioFrames(sc, world.terrain, *frames);
    if (!st.isOk()) {
        error = std::string("buildScenarioFrames: ") + st.reason();
        return false;
    }
    const sim::ScenarioFrame& fa = frames->frames[0];
    const sim::ScenarioFrame& fb = frames->frames[1];
    pair.spec = spec;
    pair.model = fa.model;
    pair.pose_a = fa.camera_pose;
    pair.pose_b = fb.camera_pose;
    pair.truth = eval::relativePose(pair.pose_a, pair.pose_b);
    pair.width = fa.model.width_px;
    pair.height = fa.model.height_px;
    const std::size_t n = static_cast<std::size_t>(pair.width) * static_cast<std::size_t>(pair.height);
    pair.image_a.assign(n, 0U);
    pair.image_b.assign(n, 0U);
    pair.range_a_m.assign(n, 0.0f);
    pair.range_b_m.assign(n, 0.0f);
    pair.point_a_site_m.assign(3U * n, 0.0f);
    const auto t0 = std::chrono::steady_clock::now();
    sim::FrameOutput oa;
    oa.image8 = ImageView<std::uint8_t>(pair.image_a.data(), pair.width, pair.height);
    oa.truth.range_m = ImageView<float>(pair.range_a_m.data(), pair.width, pair.height);
    oa.truth.point_site_m = ImageView<float>(pair.point_a_site_m.data(), 3 * pair.width, pair.height);
    sim::FrameOutput ob;
    ob.image8 = ImageView<std::uint8_t>(pair.image_b.data(), pair.width, pair.height);
    ob.truth.range_m = ImageView<float>(pair.range_b_m.data(), pair.width, pair.height);
    st = sim::renderFrame(sim::scenarioFrameRequest(sc, world.terrain, fa), oa, nullptr);
    if (st.isOk()) {
        st = sim::renderFrame(sim::scenarioFrameRequest(sc, world.terrain, fb), ob, nullptr);
    }
    pair.render_seconds = secondsSince(t0);
    if (!st.isOk()) {
        error = std::string("renderFrame: ") + st.reason();
        return false;
    }
    return true;
}

// ---- odometry -------------------------------------------------------------------------

OdometryCase perturbedOdometry(const RenderedPair& pair, const OdometryErrorSpec& spec, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    std::normal_distribution<double> n01(0.0, 1.0);
    const auto magnitude = [&](double max) {
        const double m = max * (spec.min_scale + (1.0 - spec.min_scale) * u01(rng));
        return (u01(rng) < 0.5) ? -m : m;
    };
    Vec3 dir;
    do {  // bound: expected 1 iteration (a normal 3-vector is almost never tiny)
        const double x = n01(rng);
        const double y = n01(rng);
        const double z = n01(rng);
        dir = Vec3(x, y, z);
    } while (dir.norm() < 1e-6);
    dir.normalize();
    OdometryCase out;
    const double distance_m = (pair.pose_b.t_m - pair.pose_a.t_m).norm();
    out.translation_error_fraction = std::fabs(magnitude(spec.translation_fraction));
    out.heading_error_deg = magnitude(spec.heading_deg);
    out.tilt_error_deg = magnitude(spec.tilt_deg);
    const double tilt_axis_angle = 2.0 * kPi * u01(rng);
    const Vec3 tilt_axis(std::cos(tilt_axis_angle), std::sin(tilt_axis_angle), 0.0);  // horizontal, site
    RigidPose b = pair.pose_b;
    b.t_m += out.translation_error_fraction * distance_m * dir;
    b.R = rotationAbout(Vec3::UnitZ(), out.heading_error_deg * kDeg) *
          rotationAbout(tilt_axis, out.tilt_error_deg * kDeg) * b.R;
    out.pose = eval::relativePose(pair.pose_a, b);
    return out;
}

// ---- truth correspondences ------------------------------------------------------------

std::vector<Correspondence> trueCorrespondences(const RenderedPair& pair, int step_px, double occlusion_tolerance) {
    std::vector<Correspondence> out;
    const Mat3 R_b_from_site = pair.pose_b.R.transpose();
    for (int y = step_px / 2; y < pair.height; y += step_px) {
        for (int x = step_px / 2; x < pair.width; x += step_px) {
            const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(pair.width) +
                                  static_cast<std::size_t>(x);
            const float* p = &pair.point_a_site_m[3U * i];
            if (!std::isfinite(p[0]) || !std::isfinite(pair.range_a_m[i])) {
                continue;  // sky
            }
            const Vec3 point_site(p[0], p[1], p[2]);
            const Vec3 X_b = R_b_from_site * (point_site - pair.pose_b.t_m);
            Vec2 pb;
            if (!projectPoint(pair.model, X_b, pb).isOk() || pb.x() < 1.0 || pb.y() < 1.0 ||
                pb.x() > pair.width - 2.0 || pb.y() > pair.height - 2.0) {
                continue;
            }
            double range_b = 0.0;
            if (!bilinear(pair.range_b_m, pair.width, pair.height, 1, 0, pb, range_b) ||
                std::fabs(range_b - X_b.norm()) > occlusion_tolerance * X_b.norm()) {
                continue;  // hidden from B (or at a depth edge of B's view)
            }
            Correspondence c;
            c.pixel_a = Vec2(x, y);
            c.pixel_b = pb;
            c.range_a_m = pair.range_a_m[i];
            out.push_back(c);
        }
    }
    return out;
}

bool truthMatch(const RenderedPair& pair, const Vec2& pixel_a, Vec2& pixel_b, bool require_visible) {
    double range = 0.0;
    if (!smoothRange(pair.range_a_m, pair.width, pair.height, pixel_a, 0.02, range)) {
        return false;
    }
    Vec3 site;
    for (int c = 0; c < 3; ++c) {
        if (!bilinear(pair.point_a_site_m, pair.width, pair.height, 3, c, pixel_a, site[c])) {
            return false;
        }
    }
    const Vec3 X_b = pair.pose_b.R.transpose() * (site - pair.pose_b.t_m);
    if (!projectPoint(pair.model, X_b, pixel_b).isOk()) {
        return false;
    }
    if (!require_visible) {
        return true;
    }
    double range_b = 0.0;
    return bilinear(pair.range_b_m, pair.width, pair.height, 1, 0, pixel_b, range_b) &&
           std::fabs(range_b - X_b.norm()) <= 0.01 * X_b.norm();
}

namespace {

// Bilinear grey level of B (or A) at (x, y); NaN outside.
double bilinear(const std::vector<std::uint8_t>& im, int w, int h, double x, double y) {
    const int x0 = static_cast<int>(std::floor(x));
    const int y0 = static_cast<int>(std::floor(y));
    if (x0 < 0 || y0 < 0 || x0 + 1 >= w || y0 + 1 >= h) {
        return std::nan("");
    }
    const double fx = x - x0, fy = y - y0;
    const auto px = [&](int xx, int yy) {
        return static_cast<double>(im[static_cast<std::size_t>(yy) * static_cast<std::size_t>(w) +
                                      static_cast<std::size_t>(xx)]);
    };
    return (1 - fy) * ((1 - fx) * px(x0, y0) + fx * px(x0 + 1, y0)) +
           fy * ((1 - fx) * px(x0, y0 + 1) + fx * px(x0 + 1, y0 + 1));
}

// Sums of a normalised correlation of two windows, one pair of grey levels at a time.
struct NccSums {
    double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0, n = 0;
    void add(double a, double b) {
        sa += a;
        sb += b;
        saa += a * a;
        sbb += b * b;
        sab += a * b;
        n += 1.0;
    }
    // NaN when either window is flat.
    [[nodiscard]] double value() const {
        const double va = saa - sa * sa / n, vb = sbb - sb * sb / n;
        return (va > 0 && vb > 0) ? (sab - sa * sb / n) / std::sqrt(va * vb) : std::nan("");
    }
};

}  // namespace

double nccAt(const RenderedPair& pair, const Vec2& pixel_a, const Vec2& pixel_b, int window) {
    const int h = window / 2;
    const int xa = static_cast<int>(std::lround(pixel_a.x()));
    const int ya = static_cast<int>(std::lround(pixel_a.y()));
    if (xa - h < 0 || ya - h < 0 || xa + h >= pair.width || ya + h >= pair.height || pixel_b.x() - h < 0 ||
        pixel_b.y() - h < 0 || pixel_b.x() + h + 1 >= pair.width || pixel_b.y() + h + 1 >= pair.height) {
        return std::nan("");
    }
    const Vec2 shift = pixel_b - Vec2(xa, ya);
    NccSums sums;
    for (int dy = -h; dy <= h; ++dy) {
        for (int dx = -h; dx <= h; ++dx) {
            const double a = pair.image_a[static_cast<std::size_t>(ya + dy) * static_cast<std::size_t>(pair.width) +
                                          static_cast<std::size_t>(xa + dx)];
            const Vec2 p = Vec2(xa + dx, ya + dy) + shift;
            sums.add(a, bilinear(pair.image_b, pair.width, pair.height, p.x(), p.y()));
        }
    }
    return sums.value();
}

TrueLineCeiling bestNccOnTrueLine(const RenderedPair& pair, const std::vector<Vec2>& pixels_a, double range_min_m,
                                  double range_max_m) {
    constexpr int kWindow = 11;
    // Inverse-range steps about half a pixel apart (the image of A's ray moves by at most
    // fx |t| per unit of inverse range).
    const double span = pair.model.fx_px * pair.truth.t_b_from_a_m.norm() * (1.0 / range_min_m - 1.0 / range_max_m);
    const int steps = static_cast<int>(std::clamp(2.0 * span, 100.0, 200000.0));
    TrueLineCeiling r;
    std::vector<std::pair<int, int>> cand;
    for (const Vec2& f : pixels_a) {
        const Vec2 a(std::round(f.x()), std::round(f.y()));
        Vec2 truth_b;
        CameraRay ray;
        if (!truthMatch(pair, a, truth_b, true) || !backProjectPixel(pair.model, a, ray).isOk()) {
            continue;
        }
        ++r.visible;
        cand.clear();
        for (int k = 0; k <= steps; ++k) {
            const double inv = (1.0 / range_min_m) + (1.0 / range_max_m - 1.0 / range_min_m) * k / steps;
            const Vec3 x = pair.truth.R_b_from_a * (ray.origin_m + ray.direction / inv) + pair.truth.t_b_from_a_m;
            Vec2 px;
            if (!projectPoint(pair.model, x, px).isOk()) {
                continue;
            }
            for (int dy = -1; dy <= 1; ++dy) {
                cand.emplace_back(static_cast<int>(std::lround(px.x())), static_cast<int>(std::lround(px.y())) + dy);
            }
        }
        std::sort(cand.begin(), cand.end());
        cand.erase(std::unique(cand.begin(), cand.end()), cand.end());
        double best = -2.0;
        Vec2 best_b = Vec2::Zero();
        for (const auto& [x, y] : cand) {
            const double v = nccAt(pair, a, Vec2(x, y), kWindow);
            if (!std::isnan(v) && v > best) {
                best = v;
                best_b = Vec2(x, y);
            }
        }
        r.correct += (best > -2.0 && (best_b - truth_b).norm() <= kCorrectMatch_px) ? 1 : 0;
    }
    return r;
}

// ---- VTM front end ----------------------------------------------------------------------

namespace {

// Each match's error against the truth (A's pixel's true point visible in B).
void scoreMatches(const RenderedPair& pair, const refine::Result& res, FrontEndResult& r) {
    std::vector<double> errs;
    r.matches = static_cast<std::int32_t>(res.pixels_a.size());
    for (std::size_t i = 0; i < res.pixels_a.size(); ++i) {
        r.pixels_a.push_back(res.pixels_a[i]);
        r.pixels_b.push_back(res.pixels_b[i]);
        Vec2 truth_b;
        bool correct = false;
        if (truthMatch(pair, res.pixels_a[i], truth_b, true)) {
            const double e = (truth_b - res.pixels_b[i]).norm();
            errs.push_back(e);
            correct = e <= kCorrectMatch_px;
            r.correct_matches += correct ? 1 : 0;
        }
        r.correct.push_back(correct ? 1U : 0U);
        r.truth_b.push_back(correct ? truth_b : Vec2::Constant(NAN));
    }
    r.match_error_median_px = median(errs);
}

}  // namespace

refine::Config frontEndConfig(const RenderedPair& pair, const FrontEndSpec& spec) {
    refine::Config c;
    c.max_width = pair.width;
    c.max_height = pair.height;
    c.matcher.min_score = spec.min_score;
    c.matcher.template_window = spec.template_window;
    c.matcher.pyramid_levels = spec.pyramid_levels;
    // Odometry error bound (2 deg heading + 0.3 deg tilt) seen at the focal length, with
    // 50 % margin, unless given.
    c.match_margin_px = spec.margin_px > 0.0 ? spec.margin_px : 1.5 * pair.model.fx_px * 2.3 * kDeg;
    return c;
}

refine::Request frontEndRequest(const RenderedPair& pair, const RelativePose& odometry, const FrontEndSpec& spec) {
    refine::Request rq;
    rq.prior.model_a = pair.model;
    rq.prior.model_b = pair.model;
    rq.prior.b_from_a.R = odometry.R_b_from_a;
    rq.prior.b_from_a.t_m = odometry.t_b_from_a_m;
    rq.image_a = ImageView<const std::uint8_t>(pair.image_a.data(), pair.width, pair.height);
    rq.image_b = ImageView<const std::uint8_t>(pair.image_b.data(), pair.width, pair.height);
    rq.range_min_m = spec.range_min_m;
    rq.range_max_m = spec.range_max_m;
    if (spec.camera_height_m > 0.0) {
        // The site's "up" (-z) in A's frame, from A's attitude (the odometry errors are
        // applied to B; a rover knows its tilt well): ground plane of the visibility mask
        // and of the template warp.
        rq.scene = refine::Scene::kGround;
        rq.up_a = pair.pose_a.R.transpose() * Vec3(0.0, 0.0, -1.0);
        rq.camera_height_m = spec.camera_height_m;
    } else {
        rq.scene = refine::Scene::kGeneral;
    }
    return rq;
}

FrontEndResult runVtmFrontEnd(const RenderedPair& pair, const RelativePose& odometry, const FrontEndSpec& spec) {
    FrontEndResult r;
    const refine::Config config = frontEndConfig(pair, spec);
    std::vector<std::byte> pool(refine::PairRefiner::workspaceBytes(config));
    Arena arena(pool.data(), pool.size());
    auto refiner = std::make_unique<refine::PairRefiner>();
    Status st = refiner->init(config, arena);
    if (!st.isOk()) {
        r.error = std::string("PairRefiner::init: ") + st.reason();
        return r;
    }
    auto res = std::make_unique<refine::Result>();
    const auto t0 = std::chrono::steady_clock::now();
    st = refiner->refine(frontEndRequest(pair, odometry, spec), *res);
    r.seconds = secondsSince(t0);
    r.features = static_cast<std::int32_t>(res->features.size());
    for (const features::Feature& f : res->features) {
        r.feature_pixels.push_back(f.pixel);
    }
    r.match_stats = res->matching;
    scoreMatches(pair, *res, r);
    if (!st.isOk()) {
        r.error = std::string("PairRefiner::refine: ") + st.reason();
        return r;
    }
    r.inliers = res->motion.inliers;
    r.refine_rms_px = res->motion.rms_px;
    r.refine_epipolar_sigma_px = res->motion.epipolar_sigma_px;
    r.refined.R_b_from_a = res->refined.b_from_a.R;
    r.refined.t_b_from_a_m = res->refined.b_from_a.t_m;
    r.ok = true;
    return r;
}

RefineResult refinePose(const RenderedPair& pair, const RelativePose& odometry, const std::vector<Vec2>& pixels_a,
                        const std::vector<Vec2>& pixels_b) {
    RefineResult r;
    motion::MotionInput in;
    in.pair.model_a = pair.model;
    in.pair.model_b = pair.model;
    in.pair.b_from_a.R = odometry.R_b_from_a;
    in.pair.b_from_a.t_m = odometry.t_b_from_a_m;
    in.pixels_a = Span<const Vec2>(pixels_a.data(), pixels_a.size());
    in.pixels_b = Span<const Vec2>(pixels_b.data(), pixels_b.size());
    const motion::Config cfg;
    auto refiner = std::make_unique<motion::MotionRefiner>();
    motion::MotionResult res;
    const Status st = refiner->refine(in, cfg, res);
    if (!st.isOk()) {
        r.error = std::string("refine: ") + st.reason();
        return r;
    }
    r.inliers = res.inliers;
    r.rms_px = res.rms_px;
    r.epipolar_sigma_px = res.epipolar_sigma_px;
    r.pose.R_b_from_a = res.R_b_from_a;
    r.pose.t_b_from_a_m = res.t_b_from_a_m;
    r.ok = true;
    return r;
}

void noisyTrueMatches(const std::vector<Correspondence>& corr, std::size_t count, double sigma_px,
                      std::uint64_t seed, std::vector<Vec2>& pixels_a, std::vector<Vec2>& pixels_b) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> noise(0.0, sigma_px);
    std::vector<std::size_t> order(corr.size());
    for (std::size_t i = 0; i < order.size(); ++i) {
        order[i] = i;
    }
    std::shuffle(order.begin(), order.end(), rng);
    order.resize(std::min(count, order.size()));
    std::sort(order.begin(), order.end());
    pixels_a.clear();
    pixels_b.clear();
    for (const std::size_t i : order) {
        pixels_a.push_back(corr[i].pixel_a);
        const double nx = noise(rng);
        const double ny = noise(rng);
        pixels_b.push_back(corr[i].pixel_b + Vec2(nx, ny));
    }
}

// ---- OpenCV peers ---------------------------------------------------------------------

PeerPoseResult opencvRelativePose(const CameraModel& pinhole, const std::vector<Vec2>& pixels_a,
                                  const std::vector<Vec2>& pixels_b) {
    PeerPoseResult r;
    if (pixels_a.size() < 5U || pixels_a.size() != pixels_b.size()) {
        return r;
    }
    std::vector<cv::Point2d> pa, pb;
    for (std::size_t i = 0; i < pixels_a.size(); ++i) {
        pa.emplace_back(pixels_a[i].x(), pixels_a[i].y());
        pb.emplace_back(pixels_b[i].x(), pixels_b[i].y());
    }
    const cv::Mat K = cameraMatrix(pinhole);
    cv::Mat mask;
    cv::theRNG().state = 0x12345678ULL;  // RANSAC draws from OpenCV's global generator: fix it
    const cv::Mat E = cv::findEssentialMat(pa, pb, K, cv::RANSAC, 0.999, 1.0, 1000, mask);
    if (E.rows != 3 || E.cols != 3) {
        return r;  // none, or several stacked solutions left unresolved
    }
    cv::Mat R, t;
    r.inliers = cv::recoverPose(E, pa, pb, K, R, t, mask);
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            r.pose.R_b_from_a(i, j) = R.at<double>(i, j);
        }
        r.pose.t_b_from_a_m[i] = t.at<double>(i);
    }
    r.ok = r.inliers >= 5;
    return r;
}

VerticalDisparity vtmVerticalDisparity(const RenderedPair& pair, const RelativePose& pose,
                                       const std::vector<Correspondence>& corr) {
    rectify::Config cfg;
    cfg.max_width = pair.width;
    cfg.max_height = pair.height;
    std::vector<std::byte> pool(rectify::Rectifier::workspaceBytes(cfg) + 64U);
    Arena arena(pool.data(), pool.size());
    auto rectifier = std::make_unique<rectify::Rectifier>();
    rectify::RectifiedPair out;
    rectify::RectifyInput in;
    in.pair.model_a = pair.model;
    in.pair.model_b = pair.model;
    in.pair.b_from_a.R = pose.R_b_from_a;
    in.pair.b_from_a.t_m = pose.t_b_from_a_m;
    Status st = rectifier->init(cfg, arena);
    if (st.isOk()) {
        st = rectifier->compute(in, out);
    }
    VerticalDisparity v;
    if (!st.isOk()) {
        v.error = std::string("rectify: ") + st.reason();
        return v;
    }
    std::vector<double> dy;
    for (const Correspondence& c : corr) {
        Vec2 ra, rb;
        if (rectifier->rectifyPixel(rectify::Rectifier::Side::kA, c.pixel_a, ra).isOk() &&
            rectifier->rectifyPixel(rectify::Rectifier::Side::kB, c.pixel_b, rb).isOk()) {
            dy.push_back(ra.y() - rb.y());
        }
    }
    return summarise(dy);
}

VerticalDisparity opencvVerticalDisparity(const RenderedPair& pair, const RelativePose& pose,
                                          const std::vector<Correspondence>& corr) {
    const cv::Mat K = cameraMatrix(pair.model);
    const cv::Mat D = cv::Mat::zeros(1, 5, CV_64F);
    const cv::Mat T = (cv::Mat_<double>(3, 1) << pose.t_b_from_a_m.x(), pose.t_b_from_a_m.y(), pose.t_b_from_a_m.z());
    cv::Mat R1, R2, P1, P2, Q;
    cv::stereoRectify(K, D, K, D, cv::Size(pair.width, pair.height), toCv(pose.R_b_from_a), T, R1, R2, P1, P2, Q,
                      cv::CALIB_ZERO_DISPARITY, -1.0);
    std::vector<cv::Point2d> pa, pb, ra, rb;
    for (const Correspondence& c : corr) {
        pa.emplace_back(c.pixel_a.x(), c.pixel_a.y());
        pb.emplace_back(c.pixel_b.x(), c.pixel_b.y());
    }
    VerticalDisparity v;
    if (pa.empty()) {
        v.error = "no correspondences";
        return v;
    }
    cv::undistortPoints(pa, ra, K, D, R1, P1);
    cv::undistortPoints(pb, rb, K, D, R2, P2);
    std::vector<double> dy;
    const bool vertical = std::fabs(P2.at<double>(1, 3)) > std::fabs(P2.at<double>(0, 3));
    for (std::size_t i = 0; i < ra.size(); ++i) {
        // stereoRectify picks a vertical layout when |t_y| > |t_x|: then x is the "row".
        dy.push_back(vertical ? ra[i].x - rb[i].x : ra[i].y - rb[i].y);
    }
    return summarise(dy);
}

// ---- full chain ------------------------------------------------------------------------

namespace {

struct ChainImages {
    std::vector<std::uint8_t> rect_a, rect_b;
    std::vector<std::int16_t> disparity_px16;
    int w = 0, h = 0;
};

Status rectifyAndMatch(const RenderedPair& pair, const RelativePose& refined, rectify::Rectifier& rectifier,
                       rectify::RectifiedPair& rp, ChainImages& im, ChainResult& r) {
    rectify::RectifyInput in;
    in.pair.model_a = pair.model;
    in.pair.model_b = pair.model;
    in.pair.b_from_a.R = refined.R_b_from_a;
    in.pair.b_from_a.t_m = refined.t_b_from_a_m;
    auto t0 = std::chrono::steady_clock::now();
    VTM_RETURN_IF_ERROR(rectifier.compute(in, rp));
    im.w = rp.model_a.width_px;
    im.h = rp.model_a.height_px;
    const std::size_t n = static_cast<std::size_t>(im.w) * static_cast<std::size_t>(im.h);
    im.rect_a.assign(n, 0U);
    im.rect_b.assign(n, 0U);
    const ImageView<const std::uint8_t> ia(pair.image_a.data(), pair.width, pair.height);
    const ImageView<const std::uint8_t> ib(pair.image_b.data(), pair.width, pair.height);
    VTM_RETURN_IF_ERROR(rectifier.remap(rectify::Rectifier::Side::kA, ia,
                                        ImageView<std::uint8_t>(im.rect_a.data(), im.w, im.h)));
    VTM_RETURN_IF_ERROR(rectifier.remap(rectify::Rectifier::Side::kB, ib,
                                        ImageView<std::uint8_t>(im.rect_b.data(), im.w, im.h)));
    r.seconds_rectify = secondsSince(t0);
    r.d_min = rp.d_min;
    r.d_max = rp.d_max;

    stereo::Config sc;
    sc.max_width = im.w;
    sc.max_height = im.h;
    sc.d_min = rp.d_min;
    sc.d_max = std::min(rp.d_max, rp.d_min + 1023);  // the matcher's largest range
    std::vector<std::byte> pool(stereo::MlStereo::workspaceBytes(sc) + 64U);
    Arena arena(pool.data(), pool.size());
    auto ml = std::make_unique<stereo::MlStereo>();
    VTM_RETURN_IF_ERROR(ml->init(sc, arena));
    im.disparity_px16.assign(n, stereo::kNoDisparity);
    const stereo::DisparityOutput out{ImageView<std::int16_t>(im.disparity_px16.data(), im.w, im.h), {}, {}};
    t0 = std::chrono::steady_clock::now();
    const Status st = ml->compute(ImageView<const std::uint8_t>(im.rect_a.data(), im.w, im.h),
                                  ImageView<const std::uint8_t>(im.rect_b.data(), im.w, im.h), out);
    r.seconds_stereo = secondsSince(t0);
    return st;
}

// True disparity of rectified A pixel `rect_a` (input pixel `input_a`): A's truth point
// seen by B, rectified on B's side.
bool trueDisparity(const RenderedPair& pair, const rectify::Rectifier& rectifier, const Vec2& input_a,
                   const Vec2& rect_a, double& d_true) {
    Vec2 input_b, rect_b;
    if (!truthMatch(pair, input_a, input_b, true) ||
        !rectifier.rectifyPixel(rectify::Rectifier::Side::kB, input_b, rect_b).isOk()) {
        return false;
    }
    d_true = rect_a.x() - rect_b.x();
    return true;
}

// Per valid disparity of the rectified A image whose true point B sees: relative range
// error (odometry and true baseline length) and disparity error. Returns the number of
// evaluated pixels (true point visible in B).
struct ChainErrors {
    std::vector<double> rel, rel_true, derr;
    double baseline_scale_error = 0.0;
};
long chainErrors(const RenderedPair& pair, const RelativePose& refined, const rectify::Rectifier& rectifier,
                 const rectify::RectifiedPair& rp, const ChainImages& im, ChainErrors& e) {
    const double fx = rp.model_a.fx_px, fy = rp.model_a.fy_px;
    const double cx_a = rp.model_a.cx_px, cx_b = rp.model_b.cx_px, cy = rp.model_a.cy_px;
    const double bx = rp.centre_b_rect_m.x();  // signed baseline along the rectified x axis
    const double true_scale = pair.truth.t_b_from_a_m.norm() / refined.t_b_from_a_m.norm();
    e.baseline_scale_error = 1.0 / true_scale - 1.0;
    long evaluated = 0;
    for (int y = 0; y < im.h; ++y) {
        for (int x = 0; x < im.w; ++x) {
            Vec2 input;
            double truth = 0.0;
            double d_true = 0.0;
            if (!rectifier.unrectifyPixel(rectify::Rectifier::Side::kA, Vec2(x, y), input).isOk() ||
                !smoothRange(pair.range_a_m, pair.width, pair.height, input, 0.02, truth) ||
                !trueDisparity(pair, rectifier, input, Vec2(x, y), d_true)) {
                continue;  // no truth, or not visible in B: no disparity to find
            }
            ++evaluated;
            const std::int16_t d16 = im.disparity_px16[static_cast<std::size_t>(y) * static_cast<std::size_t>(im.w) +
                                                       static_cast<std::size_t>(x)];
            if (d16 == stereo::kNoDisparity) {
                continue;
            }
            const double d = static_cast<double>(d16) / stereo::kDisparityScale;
            e.derr.push_back(std::fabs(d - d_true));
            const double z = fx * bx / (d - (cx_a - cx_b));
            if (!(z > 0.0)) {
                e.rel.push_back(1.0);  // behind the camera: a wrong disparity, counted as 100 % off
                e.rel_true.push_back(1.0);
                continue;
            }
            const double range = z * Vec3((x - cx_a) / fx, (y - cy) / fy, 1.0).norm();
            e.rel.push_back(std::fabs(range - truth) / truth);
            e.rel_true.push_back(std::fabs(range * true_scale - truth) / truth);
        }
    }
    return evaluated;
}

}  // namespace

ChainResult runFullChain(const RenderedPair& pair, const RelativePose& refined, double range_min_m,
                         double range_max_m) {
    ChainResult r;
    rectify::Config cfg;
    cfg.max_width = pair.width;
    cfg.max_height = pair.height;
    cfg.range_min_m = range_min_m;
    cfg.range_max_m = range_max_m;
    std::vector<std::byte> pool(rectify::Rectifier::workspaceBytes(cfg) + 64U);
    Arena arena(pool.data(), pool.size());
    auto rectifier = std::make_unique<rectify::Rectifier>();
    rectify::RectifiedPair rp;
    ChainImages im;
    Status st = rectifier->init(cfg, arena);
    if (st.isOk()) {
        st = rectifyAndMatch(pair, refined, *rectifier, rp, im, r);
    }
    if (!st.isOk()) {
        r.error = std::string("chain: ") + st.reason();
        return r;
    }
    ChainErrors e;
    const long evaluated = chainErrors(pair, refined, *rectifier, rp, im, e);
    r.baseline_scale_error = e.baseline_scale_error;
    const std::vector<double>& rel = e.rel;
    const std::vector<double>& rel_true = e.rel_true;
    const std::vector<double>& derr = e.derr;
    if (evaluated == 0 || rel.empty()) {
        r.error = "chain: no evaluated pixel";
        return r;
    }
    const auto within = [](const std::vector<double>& v) {
        return static_cast<double>(std::count_if(v.begin(), v.end(), [](double e) { return e <= 0.05; })) /
               static_cast<double>(v.size());
    };
    r.evaluated_fraction = static_cast<double>(evaluated) / (static_cast<double>(im.w) * im.h);
    r.valid_fraction = static_cast<double>(rel.size()) / static_cast<double>(evaluated);
    r.median_disparity_error_px = median(derr);
    r.within1px_fraction = derr.empty() ? 0.0
                                        : static_cast<double>(std::count_if(derr.begin(), derr.end(),
                                                                            [](double e) { return e <= 1.0; })) /
                                              static_cast<double>(derr.size());
    r.median_rel_error = median(rel);
    r.within5_fraction = within(rel);
    r.median_rel_error_true_scale = median(rel_true);
    r.within5_fraction_true_scale = within(rel_true);
    r.ok = true;
    return r;
}

}  // namespace vtm::eval
