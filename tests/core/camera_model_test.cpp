// Camera models: analytic projections, round trips over the whole image (corners
// included) for realistic Navcam/Hazcam-like models, CAHV from pinhole, points behind the
// camera, validation and text parsing naming the bad field, no heap.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "assert_capture.hpp"
#include "no_heap_guard.hpp"
#include "vtm/core/camera_model.hpp"

namespace vtm {
namespace {

constexpr double kPi = 3.14159265358979323846;

// ------------------------------------------------------------------------ test models --

// A Navcam-like pinhole (1024 x 1024, 45 deg) with strong Brown distortion (k1 = -0.2).
CameraModel brownNavcam() {
    CameraModel m = makePinhole(1024U, 1024U, 45.0);
    m.fx_px *= 1.002;  // slightly non-square pixels, off-centre principal point
    m.cx_px += 3.25;
    m.cy_px -= 2.5;
    m.k1 = -0.2;
    m.k2 = 0.08;
    m.k3 = -0.01;
    m.p1 = 1.2e-3;
    m.p2 = -6e-4;
    return m;
}

struct Intrinsics {
    double hs, vs, hc, vc;  // focal lengths and image centre, pixels
};

// A CAHV(OR) model as calibration delivers it: the camera looks along A = R z (here
// forward and 30 deg down in a rover mast frame), C off the origin, H = hs R x + hc A,
// V = vs R y + vc A, O a few mrad from A.
CameraModel cahvorFrom(const Intrinsics& in, const Vec3& r_terms, bool with_distortion) {
    const Mat3 rot = (Eigen::AngleAxisd(0.4, Vec3::UnitZ()) * Eigen::AngleAxisd(-kPi / 6.0, Vec3::UnitX()) *
                      Eigen::AngleAxisd(0.02, Vec3::UnitY()))
                         .toRotationMatrix();
    const Vec3 a = rot * Vec3::UnitZ();
    const Vec3 h = in.hs * (rot * Vec3::UnitX()) + in.hc * a;
    const Vec3 v = in.vs * (rot * Vec3::UnitY()) + in.vc * a;
    const Vec3 o = (a + 0.004 * (rot * Vec3::UnitX()) - 0.002 * (rot * Vec3::UnitY())).normalized();
    CameraModel m;
    m.kind = with_distortion ? CameraModelKind::kCahvor : CameraModelKind::kCahv;
    m.width_px = 1024U;
    m.height_px = 1024U;
    const Vec3 c(0.452, -0.118, -1.273);
    for (int i = 0; i < 3; ++i) {
        m.c[i] = c[i];
        m.a[i] = a[i];
        m.h[i] = h[i];
        m.v[i] = v[i];
        m.o[i] = with_distortion ? o[i] : 0.0;
        m.r[i] = with_distortion ? r_terms[i] : 0.0;
    }
    return m;
}

// Navcam-like: 14.67 mm lens, 12 um pixels (hs ~ 1222 px, 45 deg), low distortion.
CameraModel cahvorNavcam() { return cahvorFrom({1222.6, 1221.9, 510.8, 513.4}, Vec3(2.0e-6, -3.2e-3, 7.5e-4), true); }
// Hazcam-like: 5.58 mm lens (hs ~ 465 px, about 120 deg diagonal), strong barrel distortion.
CameraModel cahvorHazcam() { return cahvorFrom({465.2, 464.7, 498.4, 525.5}, Vec3(-3.0e-3, -0.08, 0.01), true); }
CameraModel cahvGeneral() { return cahvorFrom({1222.6, 1221.9, 510.8, 513.4}, Vec3::Zero(), false); }

// Pixels over the whole image: a 33 x 33 grid from edge to edge, so the four outer
// corners (-0.5, -0.5) ... (w - 0.5, h - 0.5) are included.
std::vector<Vec2> imagePixels(const CameraModel& m) {
    std::vector<Vec2> px;
    for (int j = 0; j <= 32; ++j) {
        for (int i = 0; i <= 32; ++i) {
            px.emplace_back(-0.5 + m.width_px * (i / 32.0), -0.5 + m.height_px * (j / 32.0));
        }
    }
    return px;
}

Vec3 vec(const double (&v)[3]) { return Vec3(v[0], v[1], v[2]); }

double angleBetween(const Vec3& a, const Vec3& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); }

// ------------------------------------------------------------------------- analytic --

TEST(CameraModelAnalytic, MakePinholeEdgesAreHalfTheFieldOfView) {
    const CameraModel m = makePinhole(1024U, 768U, 45.0);
    EXPECT_EQ(m.cx_px, 511.5);
    EXPECT_EQ(m.cy_px, 383.5);
    CameraRay left, right;
    ASSERT_TRUE(backProjectPixel(m, Vec2(-0.5, m.cy_px), left).isOk());
    ASSERT_TRUE(backProjectPixel(m, Vec2(1023.5, m.cy_px), right).isOk());
    EXPECT_NEAR(angleBetween(left.direction, Vec3::UnitZ()), 22.5 * kPi / 180.0, 1e-13);
    EXPECT_NEAR(angleBetween(left.direction, right.direction), 45.0 * kPi / 180.0, 1e-13);
    EXPECT_LT(left.direction.x(), 0.0);  // column 0 is towards -x
}

TEST(CameraModelAnalytic, BrownOnTheXAxisFollowsTheFormula) {
    const CameraModel m = brownNavcam();
    const double a = 0.3;  // point (0.3 Z, 0, Z): b = 0, r2 = a^2
    Vec2 px;
    ASSERT_TRUE(projectPoint(m, Vec3(0.3 * 4.0, 0.0, 4.0), px).isOk());
    const double r2 = a * a;
    const double radial = 1.0 + m.k1 * r2 + m.k2 * r2 * r2 + m.k3 * r2 * r2 * r2;
    EXPECT_NEAR(px.x(), m.fx_px * (a * radial + m.p2 * 3.0 * r2) + m.cx_px, 1e-9);
    EXPECT_NEAR(px.y(), m.fy_px * (m.p1 * r2) + m.cy_px, 1e-9);
}

TEST(CameraModelAnalytic, CahvorMovesPointsRadiallyAboutO) {
    // O = A: a point at angle theta from the axis lands at radius hs tan(theta) (1 + mu).
    CameraModel m = cahvorFrom({1000.0, 1000.0, 512.0, 512.0}, Vec3(1e-4, -0.02, 0.004), true);
    for (int i = 0; i < 3; ++i) {
        m.o[i] = m.a[i];
    }
    const Vec3 a = vec(m.a);
    const Vec3 x_dir = (vec(m.h) - 512.0 * a) / 1000.0;  // unit image x direction
    const double theta = 0.35;
    const Vec3 p = vec(m.c) + 6.0 * (std::cos(theta) * a + std::sin(theta) * x_dir);
    Vec2 px;
    ASSERT_TRUE(projectPoint(m, p, px).isOk());
    const double tau = std::tan(theta) * std::tan(theta);
    const double mu = m.r[0] + m.r[1] * tau + m.r[2] * tau * tau;
    EXPECT_NEAR(px.x(), 512.0 + 1000.0 * std::tan(theta) * (1.0 + mu), 1e-9);
    EXPECT_NEAR(px.y(), 512.0, 1e-9);
}

// --------------------------------------------------------------------- round trips --

struct NamedModel {
    const char* name;
    CameraModel model;
};

std::vector<NamedModel> roundTripModels() {
    return {{"brown", brownNavcam()},
            {"pinhole", makePinhole(640U, 480U, 60.0)},
            {"cahv", cahvGeneral()},
            {"cahvor navcam", cahvorNavcam()},
            {"cahvor hazcam", cahvorHazcam()}};
}

TEST(CameraModelRoundTrip, ProjectOfBackProjectIsThePixel) {
    for (const NamedModel& nm : roundTripModels()) {
        SCOPED_TRACE(nm.name);
        ASSERT_TRUE(validateCameraModel(nm.model).isOk()) << validateCameraModel(nm.model).reason();
        double worst_px = 0.0;
        for (const Vec2& px : imagePixels(nm.model)) {
            CameraRay ray;
            ASSERT_TRUE(backProjectPixel(nm.model, px, ray).isOk()) << px.transpose();
            EXPECT_NEAR(ray.direction.norm(), 1.0, 1e-15);
            for (double range_m : {0.7, 13.0, 900.0}) {
                Vec2 back;
                ASSERT_TRUE(projectPoint(nm.model, ray.origin_m + range_m * ray.direction, back).isOk());
                worst_px = std::fmax(worst_px, (back - px).norm());
            }
        }
        EXPECT_LT(worst_px, 1e-9);
        std::printf("[ figure ] %s: worst |project(backProject(px)) - px| = %.3g px\n", nm.name, worst_px);
    }
}

// Points spread over the field of view, built from the camera's own axes (not from the
// model's projection): directions A + u x^ + v y^ with |u|, |v| up to tan(half fov).
TEST(CameraModelRoundTrip, BackProjectOfProjectIsTheRay) {
    for (const NamedModel& nm : roundTripModels()) {
        SCOPED_TRACE(nm.name);
        const CameraModel& m = nm.model;
        Vec3 centre = Vec3::Zero(), axis = Vec3::UnitZ(), x_dir = Vec3::UnitX(), y_dir = Vec3::UnitY();
        double half_tan = 0.5 * m.width_px / m.fx_px * 0.97;
        if (m.kind != CameraModelKind::kPinholeBrown) {
            centre = vec(m.c);
            axis = vec(m.a);
            x_dir = (vec(m.h) - vec(m.h).dot(axis) * axis).normalized();
            y_dir = (vec(m.v) - vec(m.v).dot(axis) * axis).normalized();
            half_tan = 0.5 * m.width_px / (vec(m.h) - vec(m.h).dot(axis) * axis).norm() * 0.97;
        }
        double worst_rad = 0.0;
        int checked = 0;
        for (int j = -10; j <= 10; ++j) {
            for (int i = -10; i <= 10; ++i) {
                const Vec3 d = axis + half_tan * (i / 10.0) * x_dir + half_tan * (j / 10.0) * y_dir;
                const Vec3 p = centre + 5.5 * d;
                Vec2 px;
                ASSERT_TRUE(projectPoint(m, p, px).isOk()) << i << " " << j;
                CameraRay ray;
                ASSERT_TRUE(backProjectPixel(m, px, ray).isOk()) << px.transpose();
                EXPECT_NEAR((ray.origin_m - centre).norm(), 0.0, 0.0);
                worst_rad = std::fmax(worst_rad, angleBetween(ray.direction, p - centre));
                ++checked;
            }
        }
        EXPECT_EQ(checked, 441);
        EXPECT_LT(worst_rad, 1e-12);
        std::printf("[ figure ] %s: worst angle(backProject(project(P)), P - C) = %.3g rad\n", nm.name, worst_rad);
    }
}

TEST(CameraModelRoundTrip, CahvFromPinholeProjectsLikeThePinhole) {
    CameraModel pinhole = makePinhole(1024U, 1024U, 45.0);
    pinhole.fy_px *= 0.999;
    pinhole.cx_px += 7.0;
    const CameraModel cahv = cahvFromPinhole(pinhole);
    ASSERT_TRUE(validateCameraModel(cahv).isOk());
    double worst_px = 0.0;
    for (int j = -8; j <= 8; ++j) {
        for (int i = -8; i <= 8; ++i) {
            const Vec3 p(0.45 * i / 8.0 * 3.0, 0.45 * j / 8.0 * 3.0, 3.0 + 0.1 * i);
            Vec2 a, b;
            ASSERT_TRUE(projectPoint(pinhole, p, a).isOk());
            ASSERT_TRUE(projectPoint(cahv, p, b).isOk());
            worst_px = std::fmax(worst_px, (a - b).norm());
        }
    }
    EXPECT_LT(worst_px, 1e-9);
}

// ------------------------------------------------------------------- degenerate cases --

TEST(CameraModelDegenerate, PointsAtOrBehindTheCameraAreDegenerate) {
    Vec2 px(7.0, 7.0);
    const CameraModel brown = brownNavcam();
    EXPECT_EQ(projectPoint(brown, Vec3(0.1, 0.2, -1.0), px).code(), StatusCode::kDegenerate);
    EXPECT_EQ(projectPoint(brown, Vec3(0.1, 0.2, 0.0), px).code(), StatusCode::kDegenerate);
    for (const CameraModel& m : {cahvGeneral(), cahvorNavcam()}) {
        const Vec3 behind = vec(m.c) - 2.0 * vec(m.a) + 0.1 * Vec3::UnitX();
        EXPECT_EQ(projectPoint(m, behind, px).code(), StatusCode::kDegenerate);
        EXPECT_EQ(projectPoint(m, vec(m.c), px).code(), StatusCode::kDegenerate);
    }
    EXPECT_EQ(px, Vec2(7.0, 7.0));  // untouched on failure
}

TEST(CameraModelDegenerate, PointsBeyondTheDistortionFoldAreDegenerate) {
    // k1 = -0.2 alone folds at r = 1/sqrt(0.6) (about 52 deg off axis).
    CameraModel m = makePinhole(1024U, 1024U, 45.0);
    m.k1 = -0.2;
    Vec2 px;
    EXPECT_TRUE(projectPoint(m, Vec3(1.2, 0.0, 1.0), px).isOk());
    EXPECT_EQ(projectPoint(m, Vec3(1.4, 0.0, 1.0), px).code(), StatusCode::kDegenerate);
}

TEST(CameraModelDegenerate, PixelFarOutsideTheFoldDoesNotBackProject) {
    CameraModel m = makePinhole(1024U, 1024U, 45.0);
    m.k1 = -0.2;  // the distorted radius never exceeds 0.86 (its maximum, at the fold)
    CameraRay ray;
    const Status s = backProjectPixel(m, Vec2(511.5 + 1.0 * m.fx_px, 511.5), ray);
    EXPECT_EQ(s.code(), StatusCode::kDegenerate);
}

// ----------------------------------------------------------------------- validation --

struct ValidationCase {
    const char* name;
    CameraModel model;
    const char* reason;
};

TEST(CameraModelValidation, EachFailureNamesItsField) {
    const CameraModel brown = brownNavcam();
    const CameraModel cahvor = cahvorNavcam();
    std::vector<ValidationCase> cases;
    auto add = [&](const char* name, CameraModel m, const char* reason) { cases.push_back({name, m, reason}); };
    CameraModel m = brown;
    m.kind = CameraModelKind::kNone;
    add("kind none", m, "camera model: kind is not pinhole, cahv or cahvor");
    m = brown;
    m.kind = static_cast<CameraModelKind>(9);
    add("kind 9", m, "camera model: kind is not pinhole, cahv or cahvor");
    m = brown;
    m.width_px = 0U;
    add("width 0", m, "camera model: width_px is zero");
    m = cahvor;
    m.height_px = 0U;
    add("height 0", m, "camera model: height_px is zero");
    m = brown;
    m.fx_px = NAN;
    add("fx nan", m, "camera model: fx_px is not finite");
    m = brown;
    m.p2 = INFINITY;
    add("p2 inf", m, "camera model: p2 is not finite");
    m = brown;
    m.fy_px = 0.0;
    add("fy 0", m, "camera model: fy_px must be positive");
    m = brown;
    m.fx_px = -100.0;
    add("fx < 0", m, "camera model: fx_px must be positive");
    m = brown;
    m.k1 = -0.9;
    add("k1 folds", m, "camera model: k1 k2 k3 fold the image over (radial distortion not invertible to the corners)");
    m = cahvor;
    m.v[1] = NAN;
    add("V nan", m, "camera model: V is not finite");
    m = cahvor;
    m.r[2] = INFINITY;
    add("R inf", m, "camera model: R is not finite");
    m = cahvor;
    m.a[0] *= 1.01;
    add("A not unit", m, "camera model: A is not a unit vector");
    m = cahvor;
    for (int i = 0; i < 3; ++i) m.h[i] = 3.0 * m.a[i];
    add("H parallel", m, "camera model: H is parallel to A");
    m = cahvor;
    for (int i = 0; i < 3; ++i) m.v[i] = -2.0 * m.a[i];
    add("V parallel", m, "camera model: V is parallel to A");
    m = cahvor;
    for (int i = 0; i < 3; ++i) m.v[i] = m.h[i] + 5.0 * m.a[i];
    add("H V coplanar", m, "camera model: H and V are coplanar with A");
    m = cahvor;
    m.o[2] += 0.01;
    add("O not unit", m, "camera model: O is not a unit vector");
    m = cahvor;
    for (int i = 0; i < 3; ++i) m.o[i] = -m.a[i];
    add("O backwards", m, "camera model: O is 90 degrees or more from a corner's ray");
    m = cahvor;
    m.r[1] = -0.6;
    add("R folds", m, "camera model: R folds the image over (radial distortion not invertible to the corners)");
    m = cahvor;
    m.r[0] = -1.0;  // 1 + r0 = 0: every point collapses onto the axis
    add("r0 -1", m, "camera model: R folds the image over (radial distortion not invertible to the corners)");
    for (const ValidationCase& c : cases) {
        SCOPED_TRACE(c.name);
        const Status s = validateCameraModel(c.model);
        EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
        EXPECT_STREQ(s.reason(), c.reason);
    }
    // Fields of other kinds are not looked at.
    m = cahvGeneral();
    m.fx_px = NAN;
    m.o[0] = NAN;
    EXPECT_TRUE(validateCameraModel(m).isOk());
}

// --------------------------------------------------------------------------- parsing --

const char* const kCahvorText =
    "vtm_camera_model 1\n"
    "# MER-like Navcam, hand written\n"
    "kind cahvor\r\n"
    "width_px 1024\n"
    "\n"
    "height_px 1024\n"
    "C 0.5 -0.25 -1.25\n"
    "A\t0 0 1\n"
    "H 1222.5 0 511.5\n"
    "V 0 1222.5 0x1.ffp+8\n"
    "  O 0 0 1\n"
    "R 1e-6 -0.0032 7.5e-4\n";

TEST(CameraModelText, ParsesTheDocumentedForm) {
    CameraModel m;
    const Status s = parseCameraModel(kCahvorText, m);
    ASSERT_TRUE(s.isOk()) << s.reason() << " line " << s.detail();
    EXPECT_EQ(m.kind, CameraModelKind::kCahvor);
    EXPECT_EQ(m.width_px, 1024U);
    EXPECT_EQ(m.height_px, 1024U);
    EXPECT_EQ(m.c[1], -0.25);
    EXPECT_EQ(m.h[0], 1222.5);
    EXPECT_EQ(m.v[2], 511.0);  // 0x1.ffp+8
    EXPECT_EQ(m.r[1], -0.0032);

    const std::string pinhole =
        "vtm_camera_model 1\nkind pinhole\nwidth_px 640\nheight_px 480\nk3 0\nfx_px 500\nfy_px 501\n"
        "cx_px 319.5\ncy_px 239.5\nk1 -0.2\nk2 0.05\np1 0.001\np2 -0.0005";  // no final newline
    ASSERT_TRUE(parseCameraModel(pinhole, m).isOk());
    EXPECT_EQ(m.kind, CameraModelKind::kPinholeBrown);
    EXPECT_EQ(m.fy_px, 501.0);
    EXPECT_EQ(m.k1, -0.2);
    EXPECT_EQ(m.p2, -0.0005);
}

struct ParseCase {
    const char* name;
    std::string text;
    const char* reason;
    std::int64_t line;
};

std::string replaced(std::string text, const std::string& from, const std::string& to) {
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return text.replace(at, from.size(), to);
}

TEST(CameraModelText, ErrorsNameTheFieldAndLine) {
    const std::string ok = kCahvorText;
    const std::vector<ParseCase> cases = {
        {"empty", "", "camera model text: first line must be 'vtm_camera_model 1'", 1},
        {"header", replaced(ok, "vtm_camera_model 1", "vtm_camera_model 2"),
         "camera model text: first line must be 'vtm_camera_model 1'", 1},
        {"unknown key", replaced(ok, "kind cahvor", "kind cahvor\nE 1 2 3"), "camera model text: unknown key", 4},
        {"kind", replaced(ok, "kind cahvor", "kind cahvore"),
         "camera model text: kind must be one of pinhole, cahv, cahvor", 3},
        {"kind twice", replaced(ok, "width_px", "kind cahv\nwidth_px"), "camera model text: kind given twice", 4},
        {"width 0", replaced(ok, "width_px 1024", "width_px 0"),
         "camera model text: width_px must be one integer 1..65535", 4},
        {"width big", replaced(ok, "width_px 1024", "width_px 65536"),
         "camera model text: width_px must be one integer 1..65535", 4},
        {"height text", replaced(ok, "height_px 1024", "height_px 1O24"),
         "camera model text: height_px must be one integer 1..65535", 6},
        {"height twice", replaced(ok, "C 0.5", "height_px 3\nC 0.5"), "camera model text: height_px given twice", 7},
        {"C two values", replaced(ok, "C 0.5 -0.25 -1.25", "C 0.5 -0.25"),
         "camera model text: C must be three finite numbers", 7},
        {"C four values", replaced(ok, "C 0.5 -0.25 -1.25", "C 0.5 -0.25 1 2"),
         "camera model text: C must be three finite numbers", 7},
        {"A nan", replaced(ok, "A\t0 0 1", "A 0 nan 1"), "camera model text: A must be three finite numbers", 8},
        {"H inf", replaced(ok, "H 1222.5", "H inf"), "camera model text: H must be three finite numbers", 9},
        {"R text", replaced(ok, "R 1e-6", "R 1e-6x"), "camera model text: R must be three finite numbers", 12},
        {"V twice", ok + "V 0 1 2\n", "camera model text: field given twice", 13},
        {"O missing", replaced(ok, "  O 0 0 1\n", ""), "camera model text: O missing", 0},
        {"kind missing", replaced(ok, "kind cahvor\r\n", ""), "camera model text: kind missing", 0},
        {"width missing", replaced(ok, "width_px 1024\n", ""), "camera model text: width_px missing", 0},
        {"foreign", ok + "fx_px 100\n", "camera model text: fx_px is not a field of this kind", 13},
        {"foreign R", replaced(ok, "kind cahvor", "kind cahv"), "camera model text: O is not a field of this kind", 11},
        {"invalid model", replaced(ok, "A\t0 0 1", "A 0 0 2"), "camera model: A is not a unit vector", 0},
    };
    for (const ParseCase& c : cases) {
        SCOPED_TRACE(c.name);
        CameraModel m;
        m.width_px = 77U;
        const Status s = parseCameraModel(c.text, m);
        EXPECT_EQ(s.code(), StatusCode::kCorruptData);
        EXPECT_STREQ(s.reason(), c.reason);
        EXPECT_EQ(s.detail(), c.line);
        EXPECT_EQ(m.width_px, 77U);  // untouched on failure
    }
}

// ---------------------------------------------------------------------------- memory --

TEST(CameraModelMemory, ProjectBackProjectValidateAndParseTouchNoHeap) {
    const CameraModel models[] = {brownNavcam(), cahvGeneral(), cahvorHazcam()};
    const std::string_view text = kCahvorText;
    test::NoHeapScope scope;
    for (const CameraModel& m : models) {
        CameraRay ray;
        Vec2 px;
        EXPECT_TRUE(validateCameraModel(m).isOk());
        EXPECT_TRUE(backProjectPixel(m, Vec2(3.0, 1000.0), ray).isOk());
        EXPECT_TRUE(projectPoint(m, ray.origin_m + 2.0 * ray.direction, px).isOk());
    }
    CameraModel parsed;
    EXPECT_TRUE(parseCameraModel(text, parsed).isOk());
    EXPECT_EQ(scope.heapCalls(), 0U);
}

}  // namespace
}  // namespace vtm
