// The PDS3 reader on the real MER-B Opportunity frames (../shared/data/mer_opportunity,
// README there): every frame reads; the samples agree with the label's own statistics
// (byte order); the CAHVOR models satisfy the CAHV identities and the label's field of
// view; the rover pose carries the label's rover-frame pointing onto its site-frame
// pointing (the quaternion convention, against the label's own numbers); the first two
// Navcam frames overlap in the narrow strip the README describes. Skipped when the data
// directory is absent.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "ground_test_files.hpp"
#include "vtm/ground/pds_image.hpp"
#include "vtm/ground/pds_label.hpp"

namespace vtm::ground {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

// The five Navcam-left frames of the pointing sequence, left to right.
const char* const kNavcam[5] = {"1N491020376ILFCNY9P0706L0M1.IMG", "1N491020519ILFCNY9P0706L0M1.IMG",
                                "1N491020834ILFCNY9P0706L0M1.IMG", "1N491020993ILFCNY9P0706L0M1.IMG",
                                "1N491021154ILFCNY9P0706L0M1.IMG"};
const char* const kPancam = "1P491287702ILFCNY9P2584L2M1.IMG";
const char* const kHazcam = "1F490747543EFFCNY9P1214L0M1.IMG";

std::string dataDir() { return test::testDataSet("mer_opportunity"); }

#define SKIP_WITHOUT_DATA() VTM_REQUIRE_TEST_DATA(dataDir() + kNavcam[0])

PdsImage load(const std::string& file) {
    const Result<PdsImage> r = readPdsImage(dataDir() + file);
    EXPECT_TRUE(r.ok) << r.error;
    return r.value;
}

PdsLabel labelOf(const std::string& file) {
    const std::string text = test::slurp(dataDir() + file);
    const Result<PdsLabel> r = parsePdsLabel(std::vector<unsigned char>(text.begin(), text.end()), file);
    EXPECT_TRUE(r.ok) << r.error;
    return r.value;
}

double labelReal(const PdsLabel& label, const std::string& scope, const std::string& key) {
    const PdsStatement* s = label.find(scope, key);
    double v = std::nan("");
    EXPECT_TRUE(s != nullptr && pdsReal(s->value, v)) << key;
    return v;
}

Vec3 vec(const double v[3]) { return Vec3(v[0], v[1], v[2]); }

// A direction from the label's azimuth (clockwise from +x towards +y) and elevation
// (positive towards +z, i.e. DOWN in the z-down rover and site frames: see docs/pds.md).
Vec3 direction(double azimuth_deg, double elevation_deg) {
    const double az = azimuth_deg * kDeg, el = elevation_deg * kDeg;
    return Vec3(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
}
double azimuthDeg(const Vec3& d) { return std::atan2(d.y(), d.x()) / kDeg; }
double elevationDeg(const Vec3& d) { return std::asin(d.z() / d.norm()) / kDeg; }
double wrapDeg(double a) { return a - 360.0 * std::floor((a + 180.0) / 360.0); }

TEST(PdsMer, EveryFrameReadsWithTheLabelsSizes) {
    SKIP_WITHOUT_DATA();
    std::vector<std::string> files(kNavcam, kNavcam + 5);
    files.push_back(kPancam);
    for (const std::string& f : files) {
        const PdsImage im = load(f);
        EXPECT_EQ(im.info.lines, 1024) << f;
        EXPECT_EQ(im.info.line_samples, 1024) << f;
        EXPECT_EQ(im.pixels.width, 1024) << f;
        EXPECT_EQ(im.pixels.height, 1024) << f;
        EXPECT_EQ(im.info.sample_bits, 16) << f;
        EXPECT_EQ(im.info.sample_type, "MSB_INTEGER") << f;
        EXPECT_EQ(im.info.image_offset, (22U - 1U) * 2048U) << f;  // ^IMAGE = 22, RECORD_BYTES = 2048
        EXPECT_EQ(im.info.instrument_id, f[1] == 'N' ? "NAVCAM_LEFT" : "PANCAM_LEFT") << f;
        EXPECT_EQ(im.info.model_type, "CAHVOR") << f;
        EXPECT_TRUE(im.has_camera_model && im.has_rover_pose) << f;
        EXPECT_EQ(im.info.product_id + ".IMG", f);
    }
    // The front Hazcam's model is CAHVORE: refused by name, read without it when allowed.
    const Result<PdsImage> refused = readPdsImage(dataDir() + kHazcam);
    ASSERT_FALSE(refused.ok);
    EXPECT_NE(refused.error.find("MODEL_TYPE in GEOMETRIC_CAMERA_MODEL is not read (CAHV and CAHVOR are), got "
                                 "\"CAHVORE\""), std::string::npos) << refused.error;
    PdsReadOptions options;
    options.require_camera_model = false;
    const Result<PdsImage> hazcam = readPdsImage(dataDir() + kHazcam, options);
    ASSERT_TRUE(hazcam.ok) << hazcam.error;
    EXPECT_EQ(hazcam.value.info.instrument_id, "FRONT_HAZCAM_LEFT");
    EXPECT_EQ(hazcam.value.info.image_offset, (21U - 1U) * 2048U);
    EXPECT_FALSE(hazcam.value.has_camera_model);
    EXPECT_FALSE(hazcam.value.info.site_pointing.valid);  // "NULL" in its label
}

// MINIMUM, MAXIMUM, MEAN, STANDARD_DEVIATION of the label's OBJECT IMAGE, printed with 6
// digits: a wrong byte order or offset would miss them by hundreds of grey levels. Navcam
// only: the Pancam frame was sent through an 8-bit look-up table (SAMPLE_BIT_MODE_ID LUT3,
// INVERSE_LUT_FILE_NAME) and its label keeps the 8-bit source's statistics (MAXIMUM 254).
TEST(PdsMer, SamplesAgreeWithTheLabelsStatistics) {
    SKIP_WITHOUT_DATA();
    for (const std::string f : kNavcam) {
        const PdsImage im = load(f);
        const PdsLabel label = labelOf(f);
        double sum = 0.0, sum2 = 0.0;
        std::uint16_t lo = 65535, hi = 0;
        for (const std::uint16_t v : im.pixels.pixels) {
            sum += v;
            sum2 += static_cast<double>(v) * v;
            lo = std::min(lo, v);
            hi = std::max(hi, v);
        }
        const double n = static_cast<double>(im.pixels.pixels.size());
        const double mean = sum / n;
        const double sd = std::sqrt(sum2 / n - mean * mean);
        EXPECT_EQ(lo, labelReal(label, "IMAGE", "MINIMUM")) << f;
        EXPECT_EQ(hi, labelReal(label, "IMAGE", "MAXIMUM")) << f;
        EXPECT_NEAR(mean, labelReal(label, "IMAGE", "MEAN"), 0.01) << f;
        EXPECT_NEAR(sd, labelReal(label, "IMAGE", "STANDARD_DEVIATION"), 0.01) << f;
        EXPECT_LE(hi, 4095) << f;  // SAMPLE_BIT_MASK 2#0000111111111111#: 12-bit data
    }
}

// CAHV identities: A unit; hc = H.A and vc = V.A (the image point of the axis) near the
// image centre; H' = H - hc A and V' = V - vc A perpendicular, of nearly equal length (the
// focal lengths in pixels: square pixels), giving the label's AZIMUTH_FOV; O near A.
TEST(PdsMer, CahvorModelsSatisfyTheCahvIdentities) {
    SKIP_WITHOUT_DATA();
    std::vector<std::string> files(kNavcam, kNavcam + 5);
    files.push_back(kPancam);
    for (const std::string& f : files) {
        const CameraModel m = load(f).camera_model;
        ASSERT_TRUE(validateCameraModel(m).isOk()) << f;
        const Vec3 a = vec(m.a), h = vec(m.h), v = vec(m.v), o = vec(m.o);
        EXPECT_NEAR(a.norm(), 1.0, 1e-12) << f;
        const double hc = h.dot(a), vc = v.dot(a);
        EXPECT_NEAR(hc, 511.5, 25.0) << f;
        EXPECT_NEAR(vc, 511.5, 25.0) << f;
        const Vec3 hp = h - hc * a, vp = v - vc * a;
        const double hs = hp.norm(), vs = vp.norm();
        EXPECT_LT(std::fabs(hs - vs) / hs, 0.01) << f;
        EXPECT_LT(std::fabs(hp.dot(vp)) / (hs * vs), 0.01) << f;
        const double fov_deg = 2.0 * std::atan(512.0 / hs) / kDeg;
        EXPECT_NEAR(fov_deg, labelReal(labelOf(f), "INSTRUMENT_STATE_PARMS", "AZIMUTH_FOV"), 0.3) << f;
        EXPECT_LT(std::acos(std::min(1.0, o.normalized().dot(a))) / kDeg, 2.0) << f;
        // Corners: back-projection and projection are inverses.
        for (const Vec2& corner : {Vec2(0, 0), Vec2(1023, 0), Vec2(0, 1023), Vec2(1023, 1023)}) {
            CameraRay ray;
            Vec2 back;
            ASSERT_TRUE(backProjectPixel(m, corner, ray).isOk()) << f;
            ASSERT_TRUE(projectPoint(m, ray.origin_m + 20.0 * ray.direction, back).isOk()) << f;
            EXPECT_LT((back - corner).norm(), 1e-6) << f;
        }
    }
}

// The label gives the instrument's pointing twice: in the rover frame and in the site
// frame. site_from_rover must carry one onto the other; the transposed rotation (the other
// reading of "rotating rover frame into the site frame") misses by degrees.
TEST(PdsMer, RoverPoseCarriesTheLabelsRoverPointingOntoItsSitePointing) {
    SKIP_WITHOUT_DATA();
    std::vector<std::string> files(kNavcam, kNavcam + 5);
    files.push_back(kPancam);
    for (const std::string& f : files) {
        const PdsImage im = load(f);
        ASSERT_TRUE(im.info.rover_pointing.valid && im.info.site_pointing.valid) << f;
        const Vec3 rover = direction(im.info.rover_pointing.azimuth_deg, im.info.rover_pointing.elevation_deg);
        const Vec3 site = im.site_from_rover.R * rover;
        // 6 printed digits: 0.001 deg.
        EXPECT_NEAR(wrapDeg(azimuthDeg(site) - im.info.site_pointing.azimuth_deg), 0.0, 0.002) << f;
        EXPECT_NEAR(elevationDeg(site) - im.info.site_pointing.elevation_deg, 0.0, 0.002) << f;
        const Vec3 transposed = im.site_from_rover.R.transpose() * rover;
        const double miss = std::acos(std::min(1.0, transposed.dot(direction(im.info.site_pointing.azimuth_deg,
                                                                              im.info.site_pointing.elevation_deg))));
        EXPECT_GT(miss / kDeg, 5.0) << f;
    }
}

// The camera's axis A, carried into the site frame by the pose, points where the label
// says the instrument points: azimuth within 0.7 deg (Navcam; the label's pointing is the
// mast's, 0.55-0.64 deg from the Navcam's A) or 1.5 deg (Pancam: 1.27), elevation within
// 0.15 deg. The sequence's site azimuths step by 36, 72, 36, 36 deg at a constant 17 deg down.
TEST(PdsMer, CameraAxisThroughThePosePointsWhereTheLabelSays) {
    SKIP_WITHOUT_DATA();
    std::vector<std::string> files(kNavcam, kNavcam + 5);
    files.push_back(kPancam);
    for (const std::string& f : files) {
        const PdsImage im = load(f);
        const Vec3 a_site = im.site_from_rover.R * vec(im.camera_model.a);
        const double az_tolerance = f[1] == 'N' ? 0.7 : 1.5;
        EXPECT_NEAR(wrapDeg(azimuthDeg(a_site) - im.info.site_pointing.azimuth_deg), 0.0, az_tolerance) << f;
        EXPECT_NEAR(elevationDeg(a_site) - im.info.site_pointing.elevation_deg, 0.0, 0.15) << f;
    }
    const double steps_deg[4] = {36.0, 72.0, 36.0, 36.0};  // frames 2 and 3 do not overlap
    for (int k = 0; k + 1 < 5; ++k) {
        const PdsImage a = load(kNavcam[k]), b = load(kNavcam[k + 1]);
        EXPECT_NEAR(wrapDeg(b.info.site_pointing.azimuth_deg - a.info.site_pointing.azimuth_deg), steps_deg[k], 0.01);
        EXPECT_NEAR(b.info.site_pointing.elevation_deg, 17.0, 0.02);
    }
}

struct Landing {
    int inside = 0, above = 0, other = 0;  // above: within B's columns, above its first row
    double min_x = 1e9, max_x = -1e9;      // of the points inside
};

// Pixels of column x of frame A, back-projected, met on a sphere of radius_m about A's
// projection centre, carried through the site frame into frame B (both frames share one
// rover pose) and projected there.
Landing landColumn(const PdsImage& a, const PdsImage& b, double x, double radius_m) {
    Landing out;
    for (int y = 16; y < 1024; y += 32) {
        CameraRay ray;
        EXPECT_TRUE(backProjectPixel(a.camera_model, Vec2(x, y), ray).isOk());
        const Vec3 site = transformPoint(a.site_from_rover, ray.origin_m + radius_m * ray.direction);
        const Vec3 rover_b = b.site_from_rover.R.transpose() * (site - b.site_from_rover.t_m);
        Vec2 px;
        const bool projects = projectPoint(b.camera_model, rover_b, px).isOk();
        const bool columns = projects && px.x() >= 0.0 && px.x() <= 1023.0;
        if (columns && px.y() >= 0.0 && px.y() <= 1023.0) {
            ++out.inside;
            out.min_x = std::min(out.min_x, px.x());
            out.max_x = std::max(out.max_x, px.x());
        } else if (columns && px.y() < 0.0) {
            ++out.above;
        } else {
            ++out.other;
        }
    }
    return out;
}

// README: neighbours overlap by about 10 deg. Frame 2 looks 5.7 deg lower than frame 1 in
// the rover frame (the rover is tilted), so frame 1's right edge (32 rows sampled) lands in
// frame 2's left part except for its top rows, which pass above frame 2; its left edge
// lands nowhere in frame 2. The strip is 238-283 px from frame 2's left edge and hardly
// moves with the assumed range (5-100 m: the Navcam's centres move a few cm between
// frames); its angular width (frame 2's rays at x = 0 and at the strip) is 8-14 deg.
TEST(PdsMer, FirstTwoNavcamFramesOverlapInANarrowStrip) {
    SKIP_WITHOUT_DATA();
    const PdsImage a = load(kNavcam[0]), b = load(kNavcam[1]);
    ASSERT_TRUE((a.site_from_rover.R - b.site_from_rover.R).norm() == 0.0 &&
                (a.site_from_rover.t_m - b.site_from_rover.t_m).norm() == 0.0);
    for (const double radius : {5.0, 20.0, 100.0}) {
        const Landing right = landColumn(a, b, 1023.0, radius);
        EXPECT_EQ(right.other, 0) << radius;
        EXPECT_GE(right.inside, 26) << radius;
        EXPECT_GT(right.min_x, 200.0) << radius;
        EXPECT_LT(right.max_x, 320.0) << radius;
        EXPECT_LT(right.max_x - right.min_x, 60.0) << radius;  // a near-vertical strip
        const Landing left = landColumn(a, b, 0.0, radius);
        EXPECT_EQ(left.inside, 0) << radius;
    }
    const Landing right = landColumn(a, b, 1023.0, 20.0);
    const double x_land = 0.5 * (right.min_x + right.max_x);
    CameraRay edge, land;
    ASSERT_TRUE(backProjectPixel(b.camera_model, Vec2(0.0, 511.5), edge).isOk());
    ASSERT_TRUE(backProjectPixel(b.camera_model, Vec2(x_land, 511.5), land).isOk());
    const double overlap_deg = std::acos(edge.direction.dot(land.direction)) / kDeg;
    EXPECT_GT(overlap_deg, 8.0);
    EXPECT_LT(overlap_deg, 14.0);
    // Frames 2 and 3 (72 deg apart) share nothing.
    const PdsImage c = load(kNavcam[2]);
    for (const double x : {0.0, 511.5, 1023.0}) EXPECT_EQ(landColumn(b, c, x, 20.0).inside, 0) << x;
}

}  // namespace
}  // namespace vtm::ground
