// Camera model files: format -> parse gives the same bits for every field (awkward values
// included), files written and read back, hand-written files read, errors name the
// file, line and field.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "ground_test_files.hpp"
#include "vtm/ground/camera_model_io.hpp"

namespace vtm::ground {
namespace {

using test::TempDir;
using test::textBytes;
using test::writeBytes;

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void expectSameBits(const CameraModel& a, const CameraModel& b) {
    EXPECT_EQ(a.kind, b.kind);
    EXPECT_EQ(a.width_px, b.width_px);
    EXPECT_EQ(a.height_px, b.height_px);
    const double* pa[] = {&a.fx_px, &a.fy_px, &a.cx_px, &a.cy_px, &a.k1, &a.k2, &a.k3, &a.p1, &a.p2};
    const double* pb[] = {&b.fx_px, &b.fy_px, &b.cx_px, &b.cy_px, &b.k1, &b.k2, &b.k3, &b.p1, &b.p2};
    for (int i = 0; i < 9; ++i) {
        EXPECT_TRUE(sameBits(*pa[i], *pb[i])) << "pinhole field " << i << ": " << *pa[i] << " vs " << *pb[i];
    }
    for (int i = 0; i < 3; ++i) {
        EXPECT_TRUE(sameBits(a.c[i], b.c[i]) && sameBits(a.a[i], b.a[i]) && sameBits(a.h[i], b.h[i]) &&
                    sameBits(a.v[i], b.v[i]) && sameBits(a.o[i], b.o[i]) && sameBits(a.r[i], b.r[i]))
            << "vector component " << i;
    }
}

// Values whose shortest decimal form needs all 17 digits, plus -0 and subnormals.
CameraModel awkwardPinhole() {
    CameraModel m = makePinhole(1024U, 768U, 45.0);
    m.fx_px = 1000.0 / 3.0 * 3.7;
    m.fy_px = std::nextafter(m.fx_px, 2000.0);
    m.cx_px = 511.5 + 1e-13;
    m.cy_px = -0.0 + 383.5;
    m.k1 = -0.2 - std::numeric_limits<double>::epsilon();
    m.k2 = -0.0;
    m.k3 = 4.9406564584124654e-324;  // smallest subnormal
    m.p1 = 2.2250738585072009e-308;  // largest subnormal
    m.p2 = -1.0 / 7.0 * 1e-3;
    return m;
}

CameraModel awkwardCahvor() {
    CameraModel m;
    m.kind = CameraModelKind::kCahvor;
    m.width_px = 65535U;
    m.height_px = 1U;
    const double s = 1.0 / std::sqrt(3.0);
    const double c[3] = {1e300, -1.0 / 3.0, 0.1};
    const double a[3] = {0.0, std::sin(0.3), std::cos(0.3)};
    const double h[3] = {1222.0 + 1.0 / 3.0, 0.1, 0.2};
    const double v[3] = {0.0, 1221.0 * std::cos(0.3), -1221.0 * std::sin(0.3) + 0.5};
    const double o[3] = {0.0, std::sin(0.3001), std::cos(0.3001)};
    const double r[3] = {1e-7 * s, -3.2e-3 * s, 7.5e-4 * s};
    for (int i = 0; i < 3; ++i) {
        m.c[i] = c[i];
        m.a[i] = a[i];
        m.h[i] = h[i];
        m.v[i] = v[i];
        m.o[i] = o[i];
        m.r[i] = r[i];
    }
    return m;
}

TEST(CameraModelIo, FormatThenParseIsBitExact) {
    CameraModel cahv = awkwardCahvor();
    cahv.kind = CameraModelKind::kCahv;
    cahv.o[0] = cahv.o[1] = cahv.o[2] = 0.0;  // not written for cahv: compare as zero
    cahv.r[0] = cahv.r[1] = cahv.r[2] = 0.0;
    for (const CameraModel& m : {awkwardPinhole(), awkwardCahvor(), cahv}) {
        ASSERT_TRUE(validateCameraModel(m).isOk()) << validateCameraModel(m).reason();
        const std::string text = formatCameraModel(m);
        CameraModel back;
        const Status s = parseCameraModel(text, back);
        ASSERT_TRUE(s.isOk()) << s.reason() << " line " << s.detail() << "\n" << text;
        expectSameBits(m, back);
    }
}

TEST(CameraModelIo, WritesAndReadsFiles) {
    TempDir dir;
    const CameraModel m = awkwardCahvor();
    ASSERT_TRUE(writeCameraModelFile(dir.file("a.cmod"), m).ok);
    CameraModel back;
    const Outcome got = readCameraModelFile(dir.file("a.cmod"), back);
    ASSERT_TRUE(got.ok) << got.error;
    expectSameBits(m, back);
}

TEST(CameraModelIo, ReadsAHandWrittenFile) {
    TempDir dir;
    writeBytes(dir.file("nav.cmod"), textBytes("vtm_camera_model 1\n# Navcam-like\nkind pinhole\nwidth_px 1024\n"
                                                "height_px 1024\nfx_px 1236.0773\nfy_px 1236.0773\ncx_px 511.5\n"
                                                "cy_px 511.5\nk1 -0.2\nk2 0.08\nk3 0\np1 0\np2 0\n"));
    CameraModel m;
    const Outcome got = readCameraModelFile(dir.file("nav.cmod"), m);
    ASSERT_TRUE(got.ok) << got.error;
    EXPECT_EQ(m.kind, CameraModelKind::kPinholeBrown);
    EXPECT_EQ(m.fx_px, 1236.0773);
    EXPECT_EQ(m.k2, 0.08);
}

TEST(CameraModelIo, ErrorsNameFileLineAndField) {
    TempDir dir;
    writeBytes(dir.file("bad.cmod"), textBytes("vtm_camera_model 1\nkind cahv\nwidth_px 4\nheight_px 3\n"
                                                "C 0 0 0\nA 0 0 1\nH 100 0 x\nV 0 100 1\n"));
    CameraModel m;
    m.width_px = 9U;
    Outcome got = readCameraModelFile(dir.file("bad.cmod"), m);
    EXPECT_FALSE(got.ok);
    EXPECT_EQ(got.error, dir.file("bad.cmod") + ": line 7: camera model text: H must be three finite numbers");
    EXPECT_EQ(m.width_px, 9U);

    writeBytes(dir.file("invalid.cmod"), textBytes("vtm_camera_model 1\nkind cahv\nwidth_px 4\nheight_px 3\n"
                                                    "C 0 0 0\nA 0 0 1\nH 0 0 7\nV 0 100 1\n"));
    got = readCameraModelFile(dir.file("invalid.cmod"), m);
    EXPECT_EQ(got.error, dir.file("invalid.cmod") + ": camera model: H is parallel to A");

    got = readCameraModelFile(dir.file("missing.cmod"), m);
    EXPECT_FALSE(got.ok);
    EXPECT_EQ(got.error.rfind(dir.file("missing.cmod") + ": cannot open", 0), 0U) << got.error;
}

}  // namespace
}  // namespace vtm::ground
