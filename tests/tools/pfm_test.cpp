// PFM: bytes written by hand in this file, in Middlebury's layout (header "Pf\nW H\n-1\n",
// bottom row first, float32 little endian, +inf = no value), parsed and produced
// exactly; big-endian files (positive scale) read; malformed files refused by name.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "ground_test_files.hpp"
#include "vtm/ground/pfm.hpp"

namespace vtm::ground {
namespace {

using test::Bytes;
using test::textBytes;

constexpr float kInf = std::numeric_limits<float>::infinity();

// IEEE-754 single bit patterns, little-endian byte order.
const Bytes kOneLE = {0x00, 0x00, 0x80, 0x3F};       // 1.0
const Bytes kTwoLE = {0x00, 0x00, 0x00, 0x40};       // 2.0
const Bytes kMinusHalfLE = {0x00, 0x00, 0x00, 0xBF};  // -0.5
const Bytes kInfLE = {0x00, 0x00, 0x80, 0x7F};       // +inf

Bytes concat(std::initializer_list<Bytes> parts) {
    Bytes out;
    for (const Bytes& p : parts) {
        out.insert(out.end(), p.begin(), p.end());
    }
    return out;
}

// The 2x2 image  top row:    1.0   2.0
//                bottom row: +inf -0.5   as Middlebury writes it (bottom row first).
Bytes handWritten2x2() {
    return concat({textBytes("Pf\n2 2\n-1\n"), kInfLE, kMinusHalfLE, kOneLE, kTwoLE});
}

FloatImage image2x2() {
    FloatImage img(2, 2);
    img.at(0, 0) = 1.0F;
    img.at(1, 0) = 2.0F;
    img.at(0, 1) = kInf;
    img.at(1, 1) = -0.5F;
    return img;
}

TEST(Pfm, ParsesHandWrittenLittleEndianBottomRowFirst) {
    const Result<FloatImage> r = decodePfm(handWritten2x2(), "hand.pfm");
    ASSERT_TRUE(r.ok) << r.error;
    ASSERT_EQ(r.value.width, 2);
    ASSERT_EQ(r.value.height, 2);
    EXPECT_EQ(r.value.at(0, 0), 1.0F);  // top-left comes from the LAST row in the file
    EXPECT_EQ(r.value.at(1, 0), 2.0F);
    EXPECT_EQ(r.value.at(0, 1), kInf);
    EXPECT_EQ(r.value.at(1, 1), -0.5F);
}

TEST(Pfm, WritesExactlyMiddleburyBytes) {
    EXPECT_EQ(encodePfm(image2x2()), handWritten2x2());
}

TEST(Pfm, ParsesBigEndianWhenScaleIsPositive) {
    const Bytes be = concat({textBytes("Pf\n2 1\n1.0\n"), {0x3F, 0x80, 0x00, 0x00}, {0x40, 0x00, 0x00, 0x00}});
    const Result<FloatImage> r = decodePfm(be, "be.pfm");
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_EQ(r.value.at(0, 0), 1.0F);
    EXPECT_EQ(r.value.at(1, 0), 2.0F);
}

TEST(Pfm, AcceptsOtherWhiteSpaceInHeader) {
    // Netpbm-style writers put the size on one line with the scale, separated by spaces.
    const Bytes b = concat({textBytes("Pf 1 1 -1.0\n"), kTwoLE});
    const Result<FloatImage> r = decodePfm(b, "spaces.pfm");
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_EQ(r.value.at(0, 0), 2.0F);
}

TEST(Pfm, FileRoundTripKeepsValuesOrientationAndInfinity) {
    test::TempDir dir;
    FloatImage img(3, 2);
    const float values[] = {0.0F, 1.0625F, -3.5F, 52.75F, kInf, 1e-7F};
    for (std::size_t i = 0; i < 6; ++i) {
        img.pixels[i] = values[i];
    }
    const std::string path = dir.file("rt.pfm");
    const Outcome w = writePfm(path, img);
    ASSERT_TRUE(w.ok) << w.error;
    EXPECT_TRUE(looksLikePfm(path));
    const Result<FloatImage> r = readPfm(path);
    ASSERT_TRUE(r.ok) << r.error;
    ASSERT_EQ(r.value.width, 3);
    ASSERT_EQ(r.value.height, 2);
    for (std::size_t i = 0; i < 6; ++i) {
        EXPECT_EQ(r.value.pixels[i], values[i]) << "pixel " << i;
    }
}

TEST(Pfm, RefusesMalformedFilesNamingThem) {
    const Bytes truncated = concat({textBytes("Pf\n2 2\n-1\n"), kOneLE});
    Result<FloatImage> r = decodePfm(truncated, "short.pfm");
    EXPECT_FALSE(r.ok);
    EXPECT_NE(r.error.find("short.pfm: truncated PFM"), std::string::npos) << r.error;

    r = decodePfm(textBytes("P5\n1 1\n255\nA"), "grey.pgm");
    EXPECT_FALSE(r.ok);
    EXPECT_NE(r.error.find("grey.pgm: not a PFM"), std::string::npos) << r.error;

    r = decodePfm(concat({textBytes("PF\n1 1\n-1\n"), kOneLE, kOneLE, kOneLE}), "colour.pfm");
    EXPECT_FALSE(r.ok);
    EXPECT_NE(r.error.find("colour PFM"), std::string::npos) << r.error;

    r = decodePfm(concat({textBytes("Pf\n1 1\n0\n"), kOneLE}), "zero.pfm");
    EXPECT_FALSE(r.ok);
    EXPECT_NE(r.error.find("bad scale"), std::string::npos) << r.error;

    r = decodePfm(concat({textBytes("Pf\n-1 1\n-1\n"), kOneLE}), "neg.pfm");
    EXPECT_FALSE(r.ok);
    EXPECT_NE(r.error.find("bad size"), std::string::npos) << r.error;
}

TEST(Pfm, MissingFileNamesPathAndReason) {
    const Result<FloatImage> r = readPfm("/nonexistent/disp.pfm");
    EXPECT_FALSE(r.ok);
    EXPECT_NE(r.error.find("/nonexistent/disp.pfm: cannot open: No such file or directory"), std::string::npos)
        << r.error;
}

}  // namespace
}  // namespace vtm::ground
