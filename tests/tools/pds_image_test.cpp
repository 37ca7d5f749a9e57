// PDS3 reader on labels written by hand in this test: the fields, the samples in either
// byte order, the CAHV(OR) model and the rover pose come out as written; every malformed
// file is refused with one line naming the file, the field and the reason.
// (The real MER frames: pds_mer_test.cpp.)
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "ground_test_files.hpp"
#include "vtm/ground/pds_image.hpp"

namespace vtm::ground {
namespace {

using test::Bytes;

constexpr int kWidth = 8;
constexpr int kHeight = 6;
constexpr int kRecordBytes = 64;

// A CAHVOR camera looking along the rover's +x: f = 10 px, centre (3.5, 2.5), no distortion.
const char* const kLabel =
    "PDS_VERSION_ID = PDS3\r\n"
    "/* FILE DATA ELEMENTS */\r\n"
    "RECORD_BYTES = 64\r\n"
    "^IMAGE = IMAGE_RECORD\r\n"
    "INSTRUMENT_ID = NAVCAM_LEFT\r\n"
    "START_TIME = \"2015-07-24T14:28:03.539Z\"\r\n"
    "PRODUCER_INSTITUTION_NAME = \"MULTIMISSION IMAGE PROCESSING \r\n"
    "                             SUBSYSTEM, JET PROPULSION LAB\"\r\n"
    "SPICE_FILE_NAME = \r\n"
    "       \"/naif/chronos.mer\"\r\n"
    "GROUP = ROVER_COORDINATE_SYSTEM\r\n"
    "  COORDINATE_SYSTEM_NAME = ROVER_FRAME\r\n"
    "  ORIGIN_OFFSET_VECTOR = (73.9193,65.9703,6.56288)\r\n"
    "  ORIGIN_ROTATION_QUATERNION = (0.70710678,0.0,0.0,\r\n"
    "                                0.70710678)\r\n"
    "  REFERENCE_COORD_SYSTEM_NAME = SITE_FRAME\r\n"
    "END_GROUP = ROVER_COORDINATE_SYSTEM\r\n"
    "GROUP = PMA_COORDINATE_SYSTEM\r\n"
    "  COORDINATE_SYSTEM_NAME = MAST_FRAME\r\n"
    "  ORIGIN_OFFSET_VECTOR = (0.45729,0.02605,-1.0962)\r\n"
    "  ORIGIN_ROTATION_QUATERNION = (1.0,0.0,0.0,0.0)\r\n"
    "  REFERENCE_COORD_SYSTEM_NAME = ROVER_FRAME\r\n"
    "END_GROUP = PMA_COORDINATE_SYSTEM\r\n"
    "GROUP = THUMBNAIL_REQUEST_PARMS\r\n"
    "  LINES = 64\r\n"
    "  LINE_SAMPLES = 64\r\n"
    "END_GROUP = THUMBNAIL_REQUEST_PARMS\r\n"
    "GROUP = ROVER_DERIVED_GEOMETRY_PARMS\r\n"
    "  INSTRUMENT_AZIMUTH = -19.2395 <deg>\r\n"
    "  INSTRUMENT_ELEVATION = 2.69079 <deg>\r\n"
    "END_GROUP = ROVER_DERIVED_GEOMETRY_PARMS\r\n"
    "OBJECT = IMAGE\r\n"
    "  INTERCHANGE_FORMAT = BINARY\r\n"
    "  LINES = 6\r\n"
    "  LINE_SAMPLES = 8\r\n"
    "  SAMPLE_TYPE = MSB_INTEGER\r\n"
    "  SAMPLE_BITS = 16\r\n"
    "  BANDS = 1\r\n"
    "  SAMPLE_BIT_MASK = 2#0000111111111111#\r\n"
    "END_OBJECT = IMAGE\r\n"
    "GROUP = GEOMETRIC_CAMERA_MODEL\r\n"
    "  MODEL_TYPE = CAHVOR\r\n"
    "  MODEL_COMPONENT_1 = (0.5,0.0,-1.25)\r\n"
    "  MODEL_COMPONENT_2 = (1.0,0.0,0.0)\r\n"
    "  MODEL_COMPONENT_3 = (3.5,10.0,0.0)\r\n"
    "  MODEL_COMPONENT_4 = (2.5,0.0,10.0)\r\n"
    "  MODEL_COMPONENT_5 = (1.0,0.0,0.0)\r\n"
    "  MODEL_COMPONENT_6 = (0.0,0.0,0.0)\r\n"
    "  REFERENCE_COORD_SYSTEM_NAME = ROVER_FRAME\r\n"
    "END_GROUP = GEOMETRIC_CAMERA_MODEL\r\n"
    "END\r\n";

std::string replaced(std::string text, const std::string& from, const std::string& to) {
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    return text;
}

std::uint16_t sampleAt(int x, int y) { return static_cast<std::uint16_t>(100 * y + x + 3000); }

// The label padded to whole records, ^IMAGE pointing after it, then the samples (2 bytes
// each, big endian unless lsb), written byte by byte.
Bytes pdsFile(std::string label, bool lsb = false) {
    const std::size_t records = (label.size() + 16U) / kRecordBytes + 1U;  // room for the pointer's digits
    label = replaced(label, "IMAGE_RECORD", std::to_string(records + 1U));
    label.resize(records * kRecordBytes, ' ');
    Bytes b = test::textBytes(label);
    for (int y = 0; y < kHeight; ++y) {
        for (int x = 0; x < kWidth; ++x) {
            const std::uint16_t v = sampleAt(x, y);
            const auto hi = static_cast<unsigned char>(v >> 8U);
            const auto lo = static_cast<unsigned char>(v & 0xFFU);
            b.push_back(lsb ? lo : hi);
            b.push_back(lsb ? hi : lo);
        }
    }
    return b;
}

std::string errorOf(const Bytes& bytes, const PdsReadOptions& options = PdsReadOptions{}) {
    const Result<PdsImage> r = decodePdsImage(bytes, "x.IMG", options);
    EXPECT_FALSE(r.ok);
    return r.error;
}

std::string errorOfLabel(const std::string& label) { return errorOf(pdsFile(label)); }

TEST(PdsImage, ReadsTheFieldsTheSamplesTheModelAndThePose) {
    const Result<PdsImage> r = decodePdsImage(pdsFile(kLabel), "x.IMG");
    ASSERT_TRUE(r.ok) << r.error;
    const PdsImage& im = r.value;
    EXPECT_EQ(im.info.lines, kHeight);  // OBJECT IMAGE's, not THUMBNAIL_REQUEST_PARMS' 64
    EXPECT_EQ(im.info.line_samples, kWidth);
    EXPECT_EQ(im.info.sample_bits, 16);
    EXPECT_EQ(im.info.sample_type, "MSB_INTEGER");
    EXPECT_EQ(im.info.record_bytes, 64U);
    EXPECT_EQ(im.info.image_offset % kRecordBytes, 0U);
    EXPECT_EQ(im.info.instrument_id, "NAVCAM_LEFT");
    EXPECT_EQ(im.info.start_time, "2015-07-24T14:28:03.539Z");
    EXPECT_EQ(im.info.model_type, "CAHVOR");
    EXPECT_TRUE(im.info.rover_pointing.valid);
    EXPECT_EQ(im.info.rover_pointing.azimuth_deg, -19.2395);
    EXPECT_FALSE(im.info.site_pointing.valid);  // no SITE_DERIVED_GEOMETRY_PARMS group
    ASSERT_EQ(im.pixels.width, kWidth);
    ASSERT_EQ(im.pixels.height, kHeight);
    for (int y = 0; y < kHeight; ++y) {
        for (int x = 0; x < kWidth; ++x) EXPECT_EQ(im.pixels.at(x, y), sampleAt(x, y)) << x << "," << y;
    }
    ASSERT_TRUE(im.has_camera_model);
    EXPECT_EQ(im.camera_model.kind, CameraModelKind::kCahvor);
    EXPECT_EQ(im.camera_model.width_px, kWidth);
    EXPECT_EQ(im.camera_model.height_px, kHeight);
    // C A H V in that order: a point 10 m ahead of C, 1 m right, 0.5 m up (z down).
    Vec2 px;
    ASSERT_TRUE(projectPoint(im.camera_model, Vec3(10.5, 1.0, -1.75), px).isOk());
    EXPECT_NEAR(px.x(), 3.5 + 10.0 * 1.0 / 10.0, 1e-12);
    EXPECT_NEAR(px.y(), 2.5 - 10.0 * 0.5 / 10.0, 1e-12);
    // ROVER_FRAME -> SITE_FRAME group (not MAST_FRAME's): 90 deg about z takes rover +x to site +y.
    ASSERT_TRUE(im.has_rover_pose);
    const Vec3 x_site = im.site_from_rover.R * Vec3::UnitX();
    EXPECT_NEAR((x_site - Vec3::UnitY()).norm(), 0.0, 1e-8);
    EXPECT_NEAR((im.site_from_rover.t_m - Vec3(73.9193, 65.9703, 6.56288)).norm(), 0.0, 1e-12);
}

TEST(PdsImage, LittleEndianSamplesGiveTheSameImage) {
    const std::string lsb = replaced(kLabel, "MSB_INTEGER", "LSB_INTEGER");
    const Result<PdsImage> a = decodePdsImage(pdsFile(kLabel), "msb.IMG");
    const Result<PdsImage> b = decodePdsImage(pdsFile(lsb, true), "lsb.IMG");
    ASSERT_TRUE(a.ok && b.ok) << a.error << b.error;
    EXPECT_EQ(a.value.pixels.pixels, b.value.pixels.pixels);
}

TEST(PdsImage, AxisScaledOffUnitProjectsAsBefore) {
    // |A| = 1.0004 with H and V as printed: dividing A, H, V by |A| keeps every pixel.
    const std::string scaled = replaced(kLabel, "(1.0,0.0,0.0)\r\n  MODEL_COMPONENT_3", "(1.0004,0.0,0.0)\r\n  MODEL_COMPONENT_3");
    const Result<PdsImage> r = decodePdsImage(pdsFile(scaled), "x.IMG");
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_NEAR(r.value.camera_model.a[0], 1.0, 1e-15);
    Vec2 px;
    ASSERT_TRUE(projectPoint(r.value.camera_model, Vec3(10.5, 1.0, -1.75), px).isOk());
    EXPECT_NEAR(px.x(), (3.5 * 10.0 + 10.0) / (10.0 * 1.0004), 1e-12);
    EXPECT_NEAR(px.y(), (2.5 * 10.0 - 5.0) / (10.0 * 1.0004), 1e-12);
}

TEST(PdsImage, StretchMapsTheQuantilesToTheEnds) {
    Grey16Image g(100, 1);
    for (int x = 0; x < 100; ++x) g.at(x, 0) = static_cast<std::uint16_t>(1000 + 10 * x);
    const GreyImage s = pdsStretchToGrey8(g, 0.1, 0.9);
    EXPECT_EQ(s.at(0, 0), 0);     // below the 10 % quantile (1100)
    EXPECT_EQ(s.at(10, 0), 0);    // the quantile itself
    EXPECT_EQ(s.at(89, 0), 255);  // the 90 % quantile (1890)
    EXPECT_EQ(s.at(99, 0), 255);
    EXPECT_EQ(s.at(50, 0), 129);  // 400 of 790 levels up: 129.11 rounded
}

TEST(PdsImage, MalformedFilesAreRefusedNamingFieldAndReason) {
    const auto contains = [](const std::string& error, const std::string& part) {
        EXPECT_NE(error.find(part), std::string::npos) << "error: " << error << "\nexpected: " << part;
        EXPECT_EQ(error.rfind("x.IMG: ", 0), 0U) << error;
    };
    Bytes truncated = pdsFile(kLabel);
    truncated.resize(truncated.size() - 1U);
    contains(errorOf(truncated), "truncated PDS image: the 8 x 6 samples need bytes");
    contains(errorOfLabel(replaced(kLabel, "^IMAGE = IMAGE_RECORD\r\n", "IMAGE_RECORD_GONE = 1\r\n")), "no ^IMAGE");
    contains(errorOfLabel(replaced(kLabel, "  LINES = 6\r\n", "  LINES = 6.5\r\n")),
             "LINES in IMAGE must be an integer 1..16384, got \"6.5\"");
    contains(errorOfLabel(replaced(kLabel, "SAMPLE_BITS = 16", "SAMPLE_BITS = 12")),
             "SAMPLE_TYPE in IMAGE with SAMPLE_BITS 12 is not read");
    contains(errorOfLabel(replaced(kLabel, "MSB_INTEGER", "IEEE_REAL")), "SAMPLE_TYPE in IMAGE with SAMPLE_BITS 16");
    contains(errorOfLabel(replaced(kLabel, "BANDS = 1", "BANDS = 3")), "BANDS in IMAGE must be an integer 1..1");
    contains(errorOfLabel(replaced(kLabel, "PDS_VERSION_ID = PDS3", "PDS_VERSION_ID = PDS4")), "not a PDS3 label");
    contains(errorOfLabel(replaced(kLabel, "END\r\n", "ENDS = 1\r\n")), "is not text (no END line before it)");
    contains(errorOfLabel(replaced(kLabel, "(0.5,0.0,-1.25)", "(0.5,0.0,-1.25")),
             "line 43: byte ");  // the list's line, not the line where the bytes stop being text
    contains(errorOfLabel(replaced(kLabel, "(0.5,0.0,-1.25)", "(0.5,0.0,-1.25")), "is not text (list not closed before it)");
    contains(errorOf(test::textBytes(std::string(kLabel).substr(0, std::string(kLabel).find("GROUP = ROVER")))), "PDS label has no END line");
    contains(errorOfLabel(replaced(kLabel, "(0.5,0.0,-1.25)", "(0.5,zero,-1.25)")),
             "MODEL_COMPONENT_1 in GEOMETRIC_CAMERA_MODEL must be a list of 3 finite numbers");
    contains(errorOfLabel(replaced(kLabel, "END_OBJECT = IMAGE\r\n", "")), "END inside GROUP/OBJECT IMAGE");
    contains(errorOfLabel(replaced(kLabel, "END_GROUP = ROVER_DERIVED_GEOMETRY_PARMS", "END_GROUP = IMAGE")),
             "END_GROUP = IMAGE closes ROVER_DERIVED_GEOMETRY_PARMS");
    contains(errorOfLabel(replaced(kLabel, "INSTRUMENT_ID =", "INSTRUMENT_ID")), "line 5: no '=' after INSTRUMENT_ID");
    contains(errorOfLabel(replaced(kLabel, "START_TIME = \"", "START_TIME = \"\x01")), "line 6: byte ");
    contains(errorOfLabel(replaced(kLabel, "START_TIME = \"", "START_TIME = \"\x01")),
             " (1) is not text (string not closed before it)");
    contains(errorOfLabel(replaced(kLabel, "^IMAGE = IMAGE_RECORD", "^IMAGE = (\"X.DAT\",IMAGE_RECORD)")),
             "names a separate file");
    // H parallel to A: the model cannot project; validateCameraModel's reason is passed on.
    contains(errorOfLabel(replaced(kLabel, "(3.5,10.0,0.0)", "(3.5,0.0,0.0)")),
             "PDS camera model (CAHVOR in GROUP GEOMETRIC_CAMERA_MODEL) fails validation: camera model: ");
    contains(errorOfLabel(replaced(kLabel, "(1.0,0.0,0.0)\r\n  MODEL_COMPONENT_3", "(1.1,0.0,0.0)\r\n  MODEL_COMPONENT_3")),
             "MODEL_COMPONENT_2 in GEOMETRIC_CAMERA_MODEL (A) must be a unit vector");
    contains(errorOfLabel(replaced(kLabel, "(0.70710678,0.0,0.0,\r\n", "(0.8,0.0,0.0,\r\n")),
             "ORIGIN_ROTATION_QUATERNION in ROVER_COORDINATE_SYSTEM must be a unit quaternion");
    contains(errorOfLabel(replaced(kLabel, "ROVER_FRAME\r\n  ORIGIN", "MAST_FRAME\r\n  ORIGIN")),
             "no group with COORDINATE_SYSTEM_NAME = ROVER_FRAME and REFERENCE_COORD_SYSTEM_NAME = SITE_FRAME");
    contains(errorOfLabel(replaced(kLabel, "MODEL_TYPE = CAHVOR", "MODEL_TYPE = CAHVORE")),
             "MODEL_TYPE in GEOMETRIC_CAMERA_MODEL is not read (CAHV and CAHVOR are), got \"CAHVORE\"");
}

TEST(PdsImage, OptionalModelAndPoseMayBeAbsentWhenNotRequired) {
    const std::string cahvore = replaced(kLabel, "MODEL_TYPE = CAHVOR", "MODEL_TYPE = CAHVORE");
    PdsReadOptions options;
    options.require_camera_model = false;
    const Result<PdsImage> r = decodePdsImage(pdsFile(cahvore), "x.IMG", options);
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_FALSE(r.value.has_camera_model);
    EXPECT_EQ(r.value.info.model_type, "CAHVORE");
    EXPECT_TRUE(r.value.has_rover_pose);
}

TEST(PdsImage, NegativeSignedSampleIsRefusedNamingThePixel) {
    Bytes b = pdsFile(kLabel);
    const std::size_t first = b.size() - static_cast<std::size_t>(2 * kWidth * kHeight);
    b[first + 2U * 9U] = 0xFFU;  // line 2, sample 2
    EXPECT_NE(errorOf(b).find("sample at line 2, sample 2 is negative"), std::string::npos) << errorOf(b);
    // The same bytes as unsigned samples are read.
    const std::string unsigned_label = replaced(kLabel, "MSB_INTEGER", "MSB_UNSIGNED_INTEGER");
    Bytes u = pdsFile(unsigned_label);
    u[u.size() - static_cast<std::size_t>(2 * kWidth * kHeight) + 2U * 9U] = 0xFFU;
    const Result<PdsImage> r = decodePdsImage(u, "u.IMG");
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_EQ(r.value.pixels.at(1, 1), 0xFF00U | (sampleAt(1, 1) & 0xFFU));
}

}  // namespace
}  // namespace vtm::ground
