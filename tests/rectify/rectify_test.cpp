// fsw/rectify unit tests against analytic truth: linear reduction of known cameras,
// row alignment of true correspondences in synthetic verged pairs (pinhole + Brown and
// CAHVOR), the reported disparity range, the point maps' round trip, remap accuracy on a
// known image function, content kept, error paths, no heap. Runs on every target.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "no_heap_guard.hpp"
#include "vtm/core/random.hpp"
#include "vtm/rectify/linear_camera.hpp"
#include "vtm/rectify/rectifier.hpp"

namespace vtm::rectify {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr std::uint16_t kW = 320;
constexpr std::uint16_t kH = 240;

Mat3 rotation(const Vec3& axis, double deg) {
    return Eigen::AngleAxisd(deg * kPi / 180.0, axis.normalized()).toRotationMatrix();
}

// Optical frame (rows x, y, z; y down) of a camera at `centre` looking at `target`,
// rolled about its axis by roll_deg.
Mat3 lookAt(const Vec3& centre, const Vec3& target, double roll_deg) {
    const Vec3 z = (target - centre).normalized();
    const Vec3 x = Vec3::UnitY().cross(z).normalized();
    const Vec3 y = z.cross(x);
    Mat3 r;
    r.row(0) = x.transpose();
    r.row(1) = y.transpose();
    r.row(2) = z.transpose();
    return rotation(Vec3::UnitZ(), roll_deg) * r;
}

void put(double (&dst)[3], const Vec3& v) {
    dst[0] = v.x();
    dst[1] = v.y();
    dst[2] = v.z();
}

enum class Kind { kBrown, kCahvor };

// A synthetic pair with known truth, world frame W (y down). Brown cameras: each model's
// reference frame is its optical frame. CAHVOR: A's model in W, B's in a "rover" frame
// X_rb = R_rover X_w + t_rover. Baseline mostly along A's x (side = +1: B to the right).
struct Scene {
    CameraModel a{}, b{};
    Mat3 R_a_w, R_b_w;  // optical frames
    Vec3 c_a_w = Vec3::Zero(), c_b_w = Vec3::Zero();
    Mat3 R_rover = Mat3::Identity();
    Vec3 t_rover = Vec3::Zero();
    Kind kind = Kind::kBrown;
    RectifyInput input{};

    // World point -> model reference frame of A / B.
    Vec3 toRefA(const Vec3& x_w) const { return kind == Kind::kBrown ? Vec3(R_a_w * (x_w - c_a_w)) : x_w; }
    Vec3 toRefB(const Vec3& x_w) const {
        return kind == Kind::kBrown ? Vec3(R_b_w * (x_w - c_b_w)) : Vec3(R_rover * x_w + t_rover);
    }
    Vec3 dirAToWorld(const Vec3& d) const { return kind == Kind::kBrown ? Vec3(R_a_w.transpose() * d) : d; }
};

CameraModel brown(double scale) {
    CameraModel m = makePinhole(kW, kH, 60.0);
    m.fx_px *= scale;
    m.fy_px *= scale * 1.002;
    m.k1 = -0.08;
    m.k2 = 0.01;
    m.p1 = 5e-4;
    m.p2 = -3e-4;
    return m;
}

// CAHVOR of a camera with optical frame R (rows) at centre c, pinhole intrinsics of p,
// expressed in a frame X_f = R_f X_w + t_f.
CameraModel cahvor(const CameraModel& p, const Mat3& R, const Vec3& c, const Mat3& R_f, const Vec3& t_f) {
    CameraModel m;
    m.kind = CameraModelKind::kCahvor;
    m.width_px = p.width_px;
    m.height_px = p.height_px;
    const Vec3 x = R_f * R.row(0).transpose();
    const Vec3 y = R_f * R.row(1).transpose();
    const Vec3 z = R_f * R.row(2).transpose();
    put(m.c, R_f * c + t_f);
    put(m.a, z);
    put(m.h, p.fx_px * x + p.cx_px * z);
    put(m.v, p.fy_px * y + p.cy_px * z);
    put(m.o, (z + 0.02 * x - 0.01 * y).normalized());
    put(m.r, Vec3(0.0, -0.03, 0.004));
    return m;
}

// convergence_deg: toe-in of the two axes towards a common point; side: +1 B right of A.
Scene makeScene(Kind kind, double baseline_m, double convergence_deg, double side) {
    Scene s;
    s.kind = kind;
    s.c_b_w = Vec3(side * baseline_m, 0.03 * baseline_m, 0.02 * baseline_m);
    const Vec3 mid = 0.5 * (s.c_a_w + s.c_b_w);
    Vec3 target_a = s.c_a_w + Vec3(0.0, 0.05, 1.0);
    Vec3 target_b = s.c_b_w + Vec3(0.0, 0.03, 1.0);
    if (convergence_deg > 0.0) {
        const double d = 0.5 * baseline_m / std::tan(0.5 * convergence_deg * kPi / 180.0);
        target_a = mid + Vec3(0.0, 0.05 * d, d);
        target_b = mid + Vec3(0.0, 0.03 * d, d);
    }
    s.R_a_w = lookAt(s.c_a_w, target_a, 0.0);
    s.R_b_w = lookAt(s.c_b_w, target_b, 1.5);
    const CameraModel pa = brown(1.0);
    const CameraModel pb = brown(1.01);
    if (kind == Kind::kBrown) {
        s.a = pa;
        s.b = pb;
        s.input.pair.b_from_a.R = s.R_b_w * s.R_a_w.transpose();
        s.input.pair.b_from_a.t_m = s.R_b_w * (s.c_a_w - s.c_b_w);
    } else {
        s.R_rover = rotation(Vec3(0.2, 1.0, 0.1), 30.0);
        s.t_rover = Vec3(1.0, 2.0, -0.5);
        s.a = cahvor(pa, s.R_a_w, s.c_a_w, Mat3::Identity(), Vec3::Zero());
        s.b = cahvor(pb, s.R_b_w, s.c_b_w, s.R_rover, s.t_rover);
        s.input.pair.b_from_a.R = s.R_rover;
        s.input.pair.b_from_a.t_m = s.t_rover;
    }
    s.input.pair.model_a = s.a;
    s.input.pair.model_b = s.b;
    return s;
}

// A rectifier with its own heap-backed pool (test code; flight code uses a StaticArena).
struct Harness {
    explicit Harness(const Config& config)
        : pool(Rectifier::workspaceBytes(config)), arena(pool.data(), pool.size()) {
        init_status = rect.init(config, arena);
    }
    std::vector<std::byte> pool;
    Arena arena;
    Rectifier rect;
    Status init_status;
};

Config smallConfig(double range_min_m, double range_max_m) {
    Config c;
    c.max_width = kW;
    c.max_height = kH;
    c.range_min_m = range_min_m;
    c.range_max_m = range_max_m;
    return c;
}

bool insideImage(const Vec2& p, double w, double h) {
    return p.x() >= -0.5 && p.y() >= -0.5 && p.x() <= w - 0.5 && p.y() <= h - 0.5;
}

struct PairCheck {
    int points = 0;           // true correspondences seen by both
    int in_range = 0;         // of which inside A's rectified image (d checked against the range)
    double max_dy_px = 0.0;   // |y_a - y_b| after rectification
    int wrong_sign = 0;
    int outside_range = 0;
};

// True correspondences: A pixel, range in [rmin, rmax] (uniform in 1/r), world point,
// full-model projection into B; rectified rows must agree and d must lie in the range.
PairCheck checkPair(const Scene& s, const Rectifier& rect, const RectifiedPair& pair, double rmin, double rmax,
                    double side) {
    PairCheck out;
    Random rng(42U);
    for (int i = 0; i < 600; ++i) {
        const double u = rng.uniform01() * (kW - 1);
        const double v = rng.uniform01() * (kH - 1);
        const double t = rng.uniform01();
        const double range = 1.0 / (1.0 / rmin + t * (1.0 / rmax - 1.0 / rmin));
        CameraRay ray;
        if (!backProjectPixel(s.a, Vec2(u, v), ray).isOk()) {
            continue;
        }
        const Vec3 x_w = s.c_a_w + range * s.dirAToWorld(ray.direction);
        Vec2 pa, pb, ra, rb;
        if (!projectPoint(s.a, s.toRefA(x_w), pa).isOk() || !projectPoint(s.b, s.toRefB(x_w), pb).isOk() ||
            !insideImage(pb, kW, kH)) {
            continue;
        }
        if (!rect.rectifyPixel(Rectifier::Side::kA, pa, ra).isOk() ||
            !rect.rectifyPixel(Rectifier::Side::kB, pb, rb).isOk()) {
            ADD_FAILURE() << "rectifyPixel failed on a visible point";
            continue;
        }
        ++out.points;
        out.max_dy_px = std::max(out.max_dy_px, std::fabs(ra.y() - rb.y()));
        // d = (cx_a - cx_b) + s fx B / Z: the depth term has the side's sign (verged
        // pairs shift the principal points apart, so d itself may have either sign).
        const double d = ra.x() - rb.x();
        out.wrong_sign += ((d - (pair.model_a.cx_px - pair.model_b.cx_px)) * side > 0.0) ? 0 : 1;
        if (insideImage(ra, pair.model_a.width_px, pair.model_a.height_px)) {
            ++out.in_range;
            out.outside_range += (d >= pair.d_min && d <= pair.d_max) ? 0 : 1;
        }
    }
    return out;
}

// ------------------------------------------------------------------ linearizeCamera --

TEST(LinearizeCamera, PinholeGivesItsIntrinsics) {
    const CameraModel m = brown(1.0);
    LinearCamera lin;
    ASSERT_TRUE(linearizeCamera(m, lin).isOk());
    EXPECT_EQ(lin.K(0, 0), m.fx_px);
    EXPECT_EQ(lin.K(1, 1), m.fy_px);
    EXPECT_EQ(lin.K(0, 2), m.cx_px);
    EXPECT_EQ(lin.K(1, 2), m.cy_px);
    EXPECT_EQ(lin.K(0, 1), 0.0);
    EXPECT_TRUE(lin.R_cam_from_ref.isIdentity(0.0));
    EXPECT_EQ(lin.width_px, kW);
    EXPECT_EQ(lin.height_px, kH);
}

TEST(LinearizeCamera, CahvFromPinholeGivesBackKRC) {
    CameraModel p = makePinhole(kW, kH, 50.0);
    p.fy_px = p.fx_px * 1.03;
    p.cx_px = 161.25;
    p.cy_px = 117.5;
    LinearCamera lin;
    ASSERT_TRUE(linearizeCamera(cahvFromPinhole(p), lin).isOk());
    Mat3 k_true;
    k_true << p.fx_px, 0.0, p.cx_px, 0.0, p.fy_px, p.cy_px, 0.0, 0.0, 1.0;
    EXPECT_LE((lin.K - k_true).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LE((lin.R_cam_from_ref - Mat3::Identity()).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LE(lin.centre_ref_m.norm(), 1e-12);
}

// CAHV built as [H; V; A] = K R from a known K (with skew), rotation and centre.
CameraModel cahvOf(const Mat3& K, const Mat3& R, const Vec3& c) {
    const Mat3 m = K * R;
    CameraModel cahv;
    cahv.kind = CameraModelKind::kCahv;
    cahv.width_px = kW;
    cahv.height_px = kH;
    put(cahv.c, c);
    put(cahv.h, m.row(0).transpose());
    put(cahv.v, m.row(1).transpose());
    put(cahv.a, m.row(2).transpose());
    return cahv;
}

TEST(LinearizeCamera, RotatedCahvWithSkewAndCentre) {
    Mat3 K;
    K << 512.0, 2.5, 150.0, 0.0, 488.0, 110.0, 0.0, 0.0, 1.0;
    const Mat3 R = rotation(Vec3(0.3, -1.0, 0.4), 37.0);
    const Vec3 c(1.25, -2.0, 0.5);
    const CameraModel cahv = cahvOf(K, R, c);
    LinearCamera lin;
    ASSERT_TRUE(linearizeCamera(cahv, lin).isOk());
    EXPECT_LE((lin.K - K).cwiseAbs().maxCoeff(), 1e-9);  // pixel-sized entries: 1e-12 relative
    EXPECT_LE((lin.R_cam_from_ref - R).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LE((lin.centre_ref_m - c).cwiseAbs().maxCoeff(), 1e-12);
    // The linear camera projects like the model.
    Random rng(7U);
    for (int i = 0; i < 50; ++i) {
        const double px = rng.uniform01();
        const double py = rng.uniform01();
        const Vec3 p_cam(px - 0.5, py - 0.5, 2.0);
        const Vec3 x_ref = R.transpose() * p_cam + c;
        Vec2 pixel;
        ASSERT_TRUE(projectPoint(cahv, x_ref, pixel).isOk());
        const Vec3 h = lin.K * (lin.R_cam_from_ref * (x_ref - lin.centre_ref_m));
        EXPECT_NEAR(h.x() / h.z(), pixel.x(), 1e-9);
        EXPECT_NEAR(h.y() / h.z(), pixel.y(), 1e-9);
    }
}

TEST(LinearizeCamera, CahvorReducesToItsCahvPart) {
    const Scene s = makeScene(Kind::kCahvor, 1.0, 10.0, 1.0);
    CameraModel cahv = s.b;
    cahv.kind = CameraModelKind::kCahv;
    LinearCamera from_cahvor, from_cahv;
    ASSERT_TRUE(linearizeCamera(s.b, from_cahvor).isOk());
    ASSERT_TRUE(linearizeCamera(cahv, from_cahv).isOk());
    EXPECT_TRUE(from_cahvor.K == from_cahv.K);
    EXPECT_TRUE(from_cahvor.R_cam_from_ref == from_cahv.R_cam_from_ref);
    EXPECT_TRUE(from_cahvor.centre_ref_m == from_cahv.centre_ref_m);
    // ... which is the camera it was built from (optical frame in the rover frame).
    EXPECT_LE((from_cahvor.R_cam_from_ref - s.R_b_w * s.R_rover.transpose()).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LE((from_cahvor.centre_ref_m - (s.R_rover * s.c_b_w + s.t_rover)).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(LinearizeCamera, RejectsInvalidAndMirroredModels) {
    LinearCamera lin;
    lin.width_px = 99;
    EXPECT_EQ(linearizeCamera(CameraModel{}, lin).code(), StatusCode::kInvalidArgument);
    CameraModel bad = cahvFromPinhole(makePinhole(kW, kH, 60.0));
    bad.a[2] = 1.5;  // A not a unit vector
    EXPECT_EQ(linearizeCamera(bad, lin).code(), StatusCode::kInvalidArgument);
    CameraModel mirrored = cahvFromPinhole(makePinhole(kW, kH, 60.0));
    mirrored.h[0] = -mirrored.h[0];  // H x V against A: a mirror image
    const Status st = linearizeCamera(mirrored, lin);
    EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
    EXPECT_NE(std::string(st.reason()).find("mirrored"), std::string::npos) << st.reason();
    EXPECT_EQ(lin.width_px, 99);  // untouched on failure
}

// ---------------------------------------------------------------- verged pairs --

struct PairCase {
    Kind kind;
    double baseline_m;
    double convergence_deg;
    double side;
};

// Printed by name, not as raw bytes (gtest's fallback would read the struct's padding).
void PrintTo(const PairCase& pc, std::ostream* os) {
    *os << "kind " << static_cast<int>(pc.kind) << ", baseline " << pc.baseline_m << " m, convergence "
        << pc.convergence_deg << " deg, side " << pc.side;
}

class VergedPair : public ::testing::TestWithParam<PairCase> {};

TEST_P(VergedPair, TrueMatchesShareRowsAndDisparityRange) {
    const PairCase pc = GetParam();
    const Scene s = makeScene(pc.kind, pc.baseline_m, pc.convergence_deg, pc.side);
    const double rmin = 3.0 * pc.baseline_m;
    const double rmax = 60.0 * pc.baseline_m;
    Harness h(smallConfig(rmin, rmax));
    ASSERT_TRUE(h.init_status.isOk());
    RectifiedPair pair;
    vtm::test::NoHeapScope guard;
    const Status st = h.rect.compute(s.input, pair);
    EXPECT_EQ(guard.heapCalls(), 0U);
    ASSERT_TRUE(st.isOk()) << st.reason();

    // Baseline and B's rectified centre from the true centres (A's reference frame).
    const Vec3 cb_in_a = s.toRefA(s.c_b_w) - s.toRefA(s.c_a_w);
    EXPECT_NEAR(pair.baseline_m, pc.baseline_m * std::sqrt(1.0 + 0.03 * 0.03 + 0.02 * 0.02), 1e-12 * pc.baseline_m);
    EXPECT_LE((pair.R_rect_from_a * cb_in_a - Vec3(pc.side * pair.baseline_m, 0, 0)).norm(), 1e-12 * pc.baseline_m);
    EXPECT_LE((pair.centre_b_rect_m - Vec3(pc.side * pair.baseline_m, 0, 0)).norm(), 1e-12 * pc.baseline_m);
    const Vec3 za = s.R_a_w.row(2).transpose();
    const Vec3 zb = s.R_b_w.row(2).transpose();
    EXPECT_NEAR(pair.convergence_deg, std::acos(std::min(1.0, za.dot(zb))) * 180.0 / kPi, 1e-6);
    // Rectified cameras: undistorted pinholes sharing fx, fy, cy.
    EXPECT_EQ(pair.model_a.kind, CameraModelKind::kPinholeBrown);
    EXPECT_EQ(pair.model_a.fx_px, pair.model_b.fx_px);
    EXPECT_EQ(pair.model_a.cy_px, pair.model_b.cy_px);
    EXPECT_EQ(pair.model_b.k1, 0.0);
    EXPECT_LE(pair.d_min, pair.d_max);

    const PairCheck c = checkPair(s, h.rect, pair, rmin, rmax, pc.side);
    EXPECT_GE(c.points, 100);
    EXPECT_GE(c.in_range, 80);
    EXPECT_LT(c.max_dy_px, 1e-6);
    EXPECT_EQ(c.wrong_sign, 0);
    EXPECT_EQ(c.outside_range, 0) << "d range [" << pair.d_min << ", " << pair.d_max << "]";
}

std::vector<PairCase> pairCases() {
    std::vector<PairCase> cases;
    for (Kind k : {Kind::kBrown, Kind::kCahvor}) {
        for (double b : {0.2, 20.0}) {
            for (double conv : {0.0, 10.0, 20.0, 30.0}) {
                for (double side : {1.0, -1.0}) {
                    cases.push_back({k, b, conv, side});
                }
            }
        }
    }
    return cases;
}

std::string caseName(const ::testing::TestParamInfo<PairCase>& info) {
    const PairCase& p = info.param;
    char buf[64];
    std::snprintf(buf, sizeof buf, "%s_b%dcm_conv%d_%s", p.kind == Kind::kBrown ? "brown" : "cahvor",
                  static_cast<int>(p.baseline_m * 100.0), static_cast<int>(p.convergence_deg),
                  p.side > 0 ? "Bright" : "Bleft");
    return buf;
}

INSTANTIATE_TEST_SUITE_P(Rectify, VergedPair, ::testing::ValuesIn(pairCases()), caseName);

// The principal-point shift keeps each image's content: the centre of each input image
// (distortion-free there: principal point = centre) lands on its rectified image's
// centre column; rows get the mean of the two vertical shifts.
TEST(Rectifier, ImageCentresMapToRectifiedCentres) {
    const Scene s = makeScene(Kind::kBrown, 1.0, 20.0, 1.0);
    Harness h(smallConfig(2.0, 100.0));
    RectifiedPair pair;
    ASSERT_TRUE(h.rect.compute(s.input, pair).isOk());
    const Vec2 centre(0.5 * (kW - 1), 0.5 * (kH - 1));
    Vec2 ra, rb;
    ASSERT_TRUE(h.rect.rectifyPixel(Rectifier::Side::kA, centre, ra).isOk());
    ASSERT_TRUE(h.rect.rectifyPixel(Rectifier::Side::kB, centre, rb).isOk());
    EXPECT_NEAR(ra.x(), 0.5 * (kW - 1), 1e-9);
    EXPECT_NEAR(rb.x(), 0.5 * (kW - 1), 1e-9);
    EXPECT_NEAR(ra.y() + rb.y(), kH - 1.0, 1e-9);
    // Toed in by 10 degrees each (B right): A's centre ray points 10 degrees to the
    // rectified +x, B's 10 degrees to -x, so cx_a - cx_b = -2 fx tan(10 deg) (the small
    // tilts of the scene move it by a fraction of a pixel); far points get d < 0.
    EXPECT_NEAR(pair.model_a.cx_px - pair.model_b.cx_px, -2.0 * pair.model_a.fx_px * std::tan(10.0 * kPi / 180.0),
                1.0);
    EXPECT_LT(pair.d_min, 0);
}

// The pair publishes A's projection centre in A's reference frame (the rectified frame's
// origin): what linearizeCamera gives, bit for bit, and the true centre; a point of A's
// frame lands, through it and R_rect_from_a, on the rectified pixel that the point map
// gives for its image in A.
TEST(Rectifier, PublishesCameraACentreInItsReferenceFrame) {
    for (Kind kind : {Kind::kBrown, Kind::kCahvor}) {
        Scene s = makeScene(kind, 1.5, 10.0, 1.0);
        // CAHVOR: camera A moved inside its reference frame, so that its centre is not the
        // frame's origin (B and both frames stay: b_from_a is unchanged).
        const Vec3 c_true = kind == Kind::kBrown ? Vec3::Zero() : Vec3(0.3, -0.2, 0.1);
        if (kind == Kind::kCahvor) {
            put(s.a.c, c_true);
            s.input.pair.model_a = s.a;
        }
        Harness h(smallConfig(2.0, 100.0));
        RectifiedPair pair;
        ASSERT_TRUE(h.rect.compute(s.input, pair).isOk());
        LinearCamera lin;
        ASSERT_TRUE(linearizeCamera(s.a, lin).isOk());
        EXPECT_TRUE(pair.centre_a_ref_m == lin.centre_ref_m);  // bit for bit
        EXPECT_LE((pair.centre_a_ref_m - c_true).cwiseAbs().maxCoeff(), 1e-15);
        std::int32_t tested = 0;
        for (int i = 0; i < 20; ++i) {
            const Vec3 dir(0.04 * (i % 5) - 0.08, 0.03 * (i / 5) - 0.05, 1.0);
            const Vec3 x_a = c_true + (kind == Kind::kBrown ? dir : Vec3(s.R_a_w.transpose() * dir)) * (3.0 + i);
            Vec2 pa;
            Vec2 ra;
            if (!projectPoint(s.a, x_a, pa).isOk() || !h.rect.rectifyPixel(Rectifier::Side::kA, pa, ra).isOk()) {
                continue;
            }
            const Vec3 x_rect = pair.R_rect_from_a * (x_a - pair.centre_a_ref_m);
            EXPECT_NEAR(pair.model_a.fx_px * x_rect.x() / x_rect.z() + pair.model_a.cx_px, ra.x(), 1e-6);
            EXPECT_NEAR(pair.model_a.fy_px * x_rect.y() / x_rect.z() + pair.model_a.cy_px, ra.y(), 1e-6);
            ++tested;
        }
        EXPECT_GT(tested, 15);
    }
}

TEST(Rectifier, UnrectifyThenRectifyIsIdentity) {
    for (Kind kind : {Kind::kBrown, Kind::kCahvor}) {
        const Scene s = makeScene(kind, 2.0, 15.0, -1.0);
        Harness h(smallConfig(4.0, 100.0));
        RectifiedPair pair;
        ASSERT_TRUE(h.rect.compute(s.input, pair).isOk());
        double worst = 0.0;
        int mapped = 0;
        for (Rectifier::Side side : {Rectifier::Side::kA, Rectifier::Side::kB}) {
            for (int y = 0; y < kH; y += 7) {
                for (int x = 0; x < kW; x += 7) {
                    const Vec2 p(x + 0.25, y + 0.75);
                    Vec2 in, back;
                    if (!h.rect.unrectifyPixel(side, p, in).isOk()) {
                        continue;
                    }
                    ASSERT_TRUE(h.rect.rectifyPixel(side, in, back).isOk());
                    worst = std::max(worst, (back - p).cwiseAbs().maxCoeff());
                    ++mapped;
                }
            }
        }
        EXPECT_GT(mapped, 2 * 46 * 35 * 9 / 10);
        EXPECT_LT(worst, 1e-9);
    }
}

// ---------------------------------------------------------------------- remap --

double pattern(double u, double v) { return 128.0 + 50.0 * std::sin(u / 13.0 + 0.3) * std::cos(v / 11.0 - 0.2); }

struct RemapFigures {
    double max_err = 0.0, mean_err = 0.0, max_table_err = 0.0, inside_fraction = 0.0;
    int fill_wrong = 0, outside_but_inside = 0;
};

RemapFigures remapFigures(const Rectifier& rect, Rectifier::Side side, const CameraModel& model,
                          const RectifiedPair& pair) {
    std::vector<std::uint8_t> in(static_cast<std::size_t>(model.width_px) * model.height_px);
    for (int y = 0; y < model.height_px; ++y) {
        for (int x = 0; x < model.width_px; ++x) {
            in[static_cast<std::size_t>(y * model.width_px + x)] = static_cast<std::uint8_t>(pattern(x, y) + 0.5);
        }
    }
    const int w = pair.model_a.width_px;
    const int hh = pair.model_a.height_px;
    std::vector<std::uint8_t> out(static_cast<std::size_t>(w * hh), 0U);
    constexpr std::uint8_t kFill = 7U;
    vtm::test::NoHeapScope guard;
    const Status st = rect.remap(side, ImageView<const std::uint8_t>(in.data(), model.width_px, model.height_px),
                                 ImageView<std::uint8_t>(out.data(), w, hh), kFill);
    EXPECT_EQ(guard.heapCalls(), 0U);
    EXPECT_TRUE(st.isOk()) << st.reason();
    RemapFigures f;
    const double scale = static_cast<double>(1 << rect.fractionBits());
    int inside = 0;
    for (int y = 0; y < hh; ++y) {
        for (int x = 0; x < w; ++x) {
            std::int16_t qx = 0, qy = 0;
            EXPECT_TRUE(rect.tableEntry(side, x, y, qx, qy).isOk());
            Vec2 p;
            const bool mapped = rect.unrectifyPixel(side, Vec2(x, y), p).isOk();
            const std::uint8_t o = out[static_cast<std::size_t>(y * w + x)];
            if (qx == kOutsideInput) {
                f.fill_wrong += (o == kFill) ? 0 : 1;
                // Outside: the exact position is outside too (up to the rounding slack).
                const double slack = 0.5 / scale;
                f.outside_but_inside += (mapped && p.x() >= slack && p.y() >= slack &&
                                         p.x() <= model.width_px - 1 - slack && p.y() <= model.height_px - 1 - slack)
                                            ? 1
                                            : 0;
                continue;
            }
            ++inside;
            EXPECT_TRUE(mapped);
            f.max_table_err = std::max(f.max_table_err, std::fabs(qx / scale - p.x()));
            f.max_table_err = std::max(f.max_table_err, std::fabs(qy / scale - p.y()));
            const double err = std::fabs(o - pattern(p.x(), p.y()));
            f.max_err = std::max(f.max_err, err);
            f.mean_err += err;
        }
    }
    f.mean_err /= std::max(inside, 1);
    f.inside_fraction = static_cast<double>(inside) / (w * hh);
    return f;
}

TEST(Rectifier, RemapMatchesTheImageFunctionAtTheExactPosition) {
    for (Kind kind : {Kind::kBrown, Kind::kCahvor}) {
        const Scene s = makeScene(kind, 1.0, 10.0, 1.0);
        Harness h(smallConfig(2.0, 100.0));
        RectifiedPair pair;
        ASSERT_TRUE(h.rect.compute(s.input, pair).isOk());
        EXPECT_EQ(h.rect.fractionBits(), 5);  // (320 + 1) << 5 <= 32767
        for (Rectifier::Side side : {Rectifier::Side::kA, Rectifier::Side::kB}) {
            const RemapFigures f = remapFigures(h.rect, side, side == Rectifier::Side::kA ? s.a : s.b, pair);
            // Input quantisation (0.5) + output rounding (0.5) + interpolation and the
            // 1/64 px position rounding (< 0.1 for this pattern): at most ~1.1 levels.
            EXPECT_LT(f.max_err, 1.1);
            EXPECT_LT(f.mean_err, 0.4);
            // Table positions: rounded to nearest 1/32 px, so within 1/64 px of exact.
            EXPECT_LE(f.max_table_err, 0.5 / 32.0 + 1e-9);
            EXPECT_EQ(f.fill_wrong, 0);
            EXPECT_EQ(f.outside_but_inside, 0);
            // Content kept for a 10 degree verged pair (measured: see docs/rectify.md).
            EXPECT_GE(f.inside_fraction, 0.90);
            std::printf("[ figures  ] %s side %c: inside %.4f, max err %.3f, mean err %.3f, table err %.5f px\n",
                        kind == Kind::kBrown ? "brown" : "cahvor", side == Rectifier::Side::kA ? 'A' : 'B',
                        f.inside_fraction, f.max_err, f.mean_err, f.max_table_err);
        }
    }
}

TEST(Rectifier, FractionBitsFollowTheInputSize) {
    Config c = smallConfig(2.0, 100.0);
    c.out_width = 64;
    c.out_height = 48;
    Harness h(c);
    for (std::uint16_t side : {std::uint16_t{1022}, std::uint16_t{1023}, std::uint16_t{2046}, std::uint16_t{2047}}) {
        CameraModel m = makePinhole(side, 48, 60.0);
        RectifyInput in;
        in.pair.model_a = m;
        in.pair.model_b = m;
        in.pair.b_from_a.t_m = Vec3(-0.5, 0.0, 0.0);
        RectifiedPair pair;
        ASSERT_TRUE(h.rect.compute(in, pair).isOk());
        const int expected = side <= 1022 ? 5 : (side <= 2046 ? 4 : 3);
        EXPECT_EQ(h.rect.fractionBits(), expected) << side;
    }
}

// ------------------------------------------------------------------- bad inputs --

TEST(Rectifier, ConfigValidationNamesTheField) {
    const auto reasonOf = [](Config c) { return std::string(c.validate().reason()); };
    Config c;
    EXPECT_TRUE(c.validate().isOk());
    c.max_width = 0;
    EXPECT_NE(reasonOf(c).find("max_width"), std::string::npos);
    c = Config{};
    c.max_height = 5000;
    EXPECT_NE(reasonOf(c).find("max_height"), std::string::npos);
    c = Config{};
    c.out_width = 2000;
    EXPECT_NE(reasonOf(c).find("out_width"), std::string::npos);
    c = Config{};
    c.out_width = 100;
    EXPECT_EQ(c.validate().code(), StatusCode::kInvalidConfig);  // out_height still 0
    c = Config{};
    c.range_min_m = 0.0;
    EXPECT_NE(reasonOf(c).find("range_min_m"), std::string::npos);
    c = Config{};
    c.range_max_m = 1.0;
    EXPECT_NE(reasonOf(c).find("range_max_m"), std::string::npos);
    c = Config{};
    c.min_baseline_angle_deg = 90.0;
    EXPECT_NE(reasonOf(c).find("min_baseline_angle_deg"), std::string::npos);
    EXPECT_EQ(Rectifier::workspaceBytes(c), 0U);
    Rectifier r;
    std::byte pool[64];
    Arena arena(pool, sizeof pool);
    EXPECT_EQ(r.init(c, arena).code(), StatusCode::kInvalidConfig);
}

TEST(Rectifier, ArenaTooSmall) {
    const Config c = smallConfig(2.0, 100.0);
    const std::size_t need = Rectifier::workspaceBytes(c);
    EXPECT_GE(need, 2U * 2U * kW * kH * sizeof(std::int16_t));
    std::vector<std::byte> pool(need);
    Rectifier r;
    Arena small(pool.data(), need / 2U);
    EXPECT_EQ(r.init(c, small).code(), StatusCode::kOutOfMemory);
    Arena exact(pool.data(), need);
    EXPECT_TRUE(r.init(c, exact).isOk());
}

TEST(Rectifier, BadInputsGiveDocumentedStatus) {
    Scene s = makeScene(Kind::kBrown, 1.0, 10.0, 1.0);
    RectifiedPair pair;
    Rectifier uninit;
    EXPECT_EQ(uninit.compute(s.input, pair).code(), StatusCode::kNotInitialized);
    Harness h(smallConfig(2.0, 100.0));
    Vec2 p;
    EXPECT_EQ(h.rect.rectifyPixel(Rectifier::Side::kA, Vec2(1, 1), p).code(), StatusCode::kNotInitialized);

    RectifyInput in = s.input;
    CameraModel bad = s.b;
    bad.fx_px = -1.0;
    in = s.input;
    in.pair.model_b = bad;
    EXPECT_EQ(h.rect.compute(in, pair).code(), StatusCode::kInvalidArgument);
    in = s.input;
    in.pair.b_from_a.R(0, 0) += 1e-6;
    EXPECT_EQ(h.rect.compute(in, pair).code(), StatusCode::kInvalidArgument);
    in = s.input;
    in.pair.b_from_a.R = -Mat3::Identity();  // orthonormal but a reflection
    EXPECT_EQ(h.rect.compute(in, pair).code(), StatusCode::kInvalidArgument);
    in = s.input;
    in.pair.b_from_a.t_m.y() = std::nan("");
    EXPECT_EQ(h.rect.compute(in, pair).code(), StatusCode::kInvalidArgument);

    // Zero baseline; baseline along A's optical axis (a forward drive).
    const CameraModel pin = brown(1.0);
    in = RectifyInput{};
    in.pair.model_a = pin;
    in.pair.model_b = pin;
    EXPECT_EQ(h.rect.compute(in, pair).code(), StatusCode::kDegenerate);
    in.pair.b_from_a.t_m = Vec3(0.3, 0.0, -1.0);  // B 1 m ahead, 0.3 m aside: 17 deg off the axis
    EXPECT_EQ(h.rect.compute(in, pair).code(), StatusCode::kDegenerate);
    in.pair.b_from_a.t_m = Vec3(-1.0, 0.0, -1.0);  // 45 deg: allowed by the default 30 deg
    EXPECT_TRUE(h.rect.compute(in, pair).isOk());

    // Rectified size above the capacity.
    const CameraModel big = makePinhole(640, 240, 60.0);
    in.pair.model_a = big;
    EXPECT_EQ(h.rect.compute(in, pair).code(), StatusCode::kSizeMismatch);
    // After a failed compute the maps answer kNotInitialized.
    EXPECT_EQ(h.rect.unrectifyPixel(Rectifier::Side::kB, Vec2(1, 1), p).code(), StatusCode::kNotInitialized);

    // remap size checks.
    ASSERT_TRUE(h.rect.compute(s.input, pair).isOk());
    std::vector<std::uint8_t> img(kW * kH);
    const ImageView<const std::uint8_t> good_in(img.data(), kW, kH);
    const ImageView<std::uint8_t> good_out(img.data(), kW, kH);
    EXPECT_EQ(h.rect.remap(Rectifier::Side::kA, ImageView<const std::uint8_t>(img.data(), kW - 1, kH), good_out)
                  .code(),
              StatusCode::kSizeMismatch);
    EXPECT_EQ(h.rect.remap(Rectifier::Side::kA, good_in, ImageView<std::uint8_t>(img.data(), kW, kH - 1)).code(),
              StatusCode::kSizeMismatch);
    EXPECT_EQ(h.rect.remap(Rectifier::Side::kA, ImageView<const std::uint8_t>(), good_out).code(),
              StatusCode::kInvalidArgument);
    std::int16_t qx = 0, qy = 0;
    EXPECT_EQ(h.rect.tableEntry(Rectifier::Side::kA, kW, 0, qx, qy).code(), StatusCode::kInvalidArgument);
}

// Host timing for the report (docs/rectify.md): not a pass/fail test.
// Run: vtm_rectify_tests --gtest_also_run_disabled_tests --gtest_filter='*Timing*'
TEST(Rectifier, DISABLED_Timing1024) {
    Config c;
    Harness h(c);
    ASSERT_TRUE(h.init_status.isOk());
    for (Kind kind : {Kind::kBrown, Kind::kCahvor}) {
        Scene s = makeScene(kind, 1.0, 10.0, 1.0);
        for (CameraModel* m : {&s.a, &s.b}) {
            const double scale = 1024.0 / kW;
            m->width_px = 1024;
            m->height_px = 1024;
            for (double* v : {m->h, m->v}) {
                for (int i = 0; i < 3; ++i) {
                    v[i] *= scale;
                }
            }
            m->fx_px *= scale;
            m->fy_px *= scale;
            m->cx_px = m->cy_px = 511.5;
            if (kind == Kind::kCahvor) {
                const Vec3 a(m->a[0], m->a[1], m->a[2]);
                for (int i = 0; i < 3; ++i) {  // re-centre: H, V principal point 511.5
                    m->h[i] += (511.5 - scale * 159.5) * a[i];
                    m->v[i] += (511.5 - scale * 119.5) * a[i];
                }
            }
        }
        RectifiedPair pair;
        const auto t0 = std::chrono::steady_clock::now();
        const Status st = h.rect.compute(s.input, pair);
        const auto t1 = std::chrono::steady_clock::now();
        ASSERT_TRUE(st.isOk()) << st.reason();
        std::vector<std::uint8_t> in(1024U * 1024U, 100U), out(1024U * 1024U);
        const auto t2 = std::chrono::steady_clock::now();
        ASSERT_TRUE(h.rect.remap(Rectifier::Side::kA, ImageView<const std::uint8_t>(in.data(), 1024, 1024),
                                 ImageView<std::uint8_t>(out.data(), 1024, 1024))
                        .isOk());
        const auto t3 = std::chrono::steady_clock::now();
        std::printf("[ timing   ] %s 1024x1024: compute (2 tables) %.1f ms, remap (1 image) %.2f ms\n",
                    kind == Kind::kBrown ? "brown" : "cahvor",
                    std::chrono::duration<double, std::milli>(t1 - t0).count(),
                    std::chrono::duration<double, std::milli>(t3 - t2).count());
    }
}

}  // namespace
}  // namespace vtm::rectify
