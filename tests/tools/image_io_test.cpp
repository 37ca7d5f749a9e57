// Image files: grey levels and colour conversion checked against PGM/PPM bytes written
// by hand and values computed by hand; PNG written by stb_image_write and read back;
// every refusal names the file.
#include <gtest/gtest.h>

#include "ground_test_files.hpp"
#include "vtm/ground/image_io.hpp"

namespace vtm::ground {
namespace {

TEST(ImageIo, ReadsGreyPgm) {
    test::TempDir dir;
    const std::string path = dir.file("g.pgm");
    test::writeBytes(path, test::pgmBytes(3, 2, {0, 1, 2, 100, 254, 255}));
    const Result<GreyImage> r = loadGrey8(path);
    ASSERT_TRUE(r.ok) << r.error;
    ASSERT_EQ(r.value.width, 3);
    ASSERT_EQ(r.value.height, 2);
    EXPECT_EQ(r.value.at(0, 0), 0);
    EXPECT_EQ(r.value.at(2, 0), 2);
    EXPECT_EQ(r.value.at(0, 1), 100);  // row 1 = second row in the file (top to bottom)
    EXPECT_EQ(r.value.at(2, 1), 255);
}

TEST(ImageIo, ReadsPgmWithHeaderComments) {
    test::TempDir dir;
    const std::string path = dir.file("comment.pgm");
    test::Bytes b = test::textBytes("P5\n# written by hand\n2 1 # size\n255\n");
    b.insert(b.end(), {7, 9});
    test::writeBytes(path, b);
    const Result<GreyImage> r = loadGrey8(path);
    ASSERT_TRUE(r.ok) << r.error;
    ASSERT_EQ(r.value.width, 2);
    EXPECT_EQ(r.value.at(0, 0), 7);
    EXPECT_EQ(r.value.at(1, 0), 9);
}

TEST(ImageIo, ConvertsRgbWithIntegerLuma) {
    test::TempDir dir;
    const std::string path = dir.file("c.ppm");
    test::writeBytes(path, test::ppmBytes(3, 1, {200, 100, 50, 255, 255, 255, 0, 0, 1}));
    const Result<GreyImage> r = loadGrey8(path);
    ASSERT_TRUE(r.ok) << r.error;
    // (77*200 + 150*100 + 29*50 + 128) >> 8 = 31978 >> 8 = 124 (124.9 truncated after the +128)
    EXPECT_EQ(r.value.at(0, 0), 124);
    EXPECT_EQ(r.value.at(1, 0), 255);  // weights sum to 256: white stays white
    EXPECT_EQ(r.value.at(2, 0), 0);    // (29 + 128) >> 8 = 0
}

TEST(ImageIo, PngRoundTripGreyAndRgb) {
    test::TempDir dir;
    GreyImage grey(4, 3);
    for (std::size_t i = 0; i < grey.pixels.size(); ++i) {
        grey.pixels[i] = static_cast<std::uint8_t>(i * 20);
    }
    const Outcome w = writePng(dir.file("g.png"), grey);
    ASSERT_TRUE(w.ok) << w.error;
    const Result<GreyImage> r = loadGrey8(dir.file("g.png"));
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_EQ(r.value.pixels, grey.pixels);

    GreyImage rgb(1, 1, 3);
    rgb.pixels = {200, 100, 50};
    ASSERT_TRUE(writePng(dir.file("c.png"), rgb).ok);
    const Result<GreyImage> c = loadGrey8(dir.file("c.png"));
    ASSERT_TRUE(c.ok) << c.error;
    EXPECT_EQ(c.value.at(0, 0), 124);
}

// 16-bit PGM samples are big endian (Netpbm): 4000 = 0x0FA0 is stored 0F A0.
TEST(ImageIo, Grey16KeepsRawLevelsOf8And16BitFiles) {
    test::TempDir dir;
    test::writeBytes(dir.file("a.pgm"), test::pgmBytes(2, 1, {0, 211}));
    test::writeBytes(dir.file("b.pgm"), test::pgmBytes(2, 1, {0, 4000}, 65535));
    const Result<Grey16Image> a = loadGrey16(dir.file("a.pgm"));
    const Result<Grey16Image> b = loadGrey16(dir.file("b.pgm"));
    ASSERT_TRUE(a.ok) << a.error;
    ASSERT_TRUE(b.ok) << b.error;
    EXPECT_EQ(a.value.at(1, 0), 211);
    EXPECT_EQ(b.value.at(1, 0), 4000);
}

TEST(ImageIo, RefusalsNameTheFileAndReason) {
    test::TempDir dir;
    Result<GreyImage> r = loadGrey8(dir.file("missing.png"));
    EXPECT_FALSE(r.ok);
    EXPECT_NE(r.error.find("missing.png: cannot open: No such file or directory"), std::string::npos) << r.error;

    test::writeBytes(dir.file("notes.txt"), test::textBytes("not an image\n"));
    r = loadGrey8(dir.file("notes.txt"));
    EXPECT_FALSE(r.ok);
    EXPECT_NE(r.error.find("notes.txt: not a readable PNG, PGM/PPM (P5/P6), JPEG or BMP image"), std::string::npos)
        << r.error;

    test::Bytes cut = test::pgmBytes(4, 4, {1, 2, 3});
    test::writeBytes(dir.file("cut.pgm"), cut);
    r = loadGrey8(dir.file("cut.pgm"));
    EXPECT_FALSE(r.ok);
    EXPECT_NE(r.error.find("cut.pgm: truncated: 16 bytes of pixels expected, 3 found"), std::string::npos) << r.error;

    test::writeBytes(dir.file("deep.pgm"), test::pgmBytes(1, 1, {4000}, 65535));
    r = loadGrey8(dir.file("deep.pgm"));
    EXPECT_FALSE(r.ok);
    EXPECT_NE(r.error.find("deep.pgm: 16-bit image"), std::string::npos) << r.error;

    test::writeBytes(dir.file("c.ppm"), test::ppmBytes(1, 1, {1, 2, 3}));
    const Result<Grey16Image> g = loadGrey16(dir.file("c.ppm"));
    EXPECT_FALSE(g.ok);
    EXPECT_NE(g.error.find("c.ppm: 3 channels"), std::string::npos) << g.error;

    const Outcome w = writePng(dir.file("no/such/dir/x.png"), GreyImage(1, 1));
    EXPECT_FALSE(w.ok);
    EXPECT_NE(w.error.find("x.png: cannot create"), std::string::npos) << w.error;
}

}  // namespace
}  // namespace vtm::ground
