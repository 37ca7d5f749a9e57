#include <gtest/gtest.h>

#include <cstdint>

#include "assert_capture.hpp"
#include "vtm/core/image.hpp"

namespace vtm {
namespace {

TEST(ImageView, StrideSeparatesRows) {
    std::uint8_t pixels[4 * 6] = {};
    const ImageView<std::uint8_t> view(pixels, 3, 4, 6);
    view.at(2, 1) = 9;
    EXPECT_EQ(pixels[1 * 6 + 2], 9);
    EXPECT_EQ(view.row(3), pixels + 18);
    EXPECT_TRUE(view.valid());
    EXPECT_EQ(view.pixelCount(), 12U);
}

TEST(ImageView, SubViewSharesPixelsAndStride) {
    std::uint16_t pixels[5 * 5] = {};
    const ImageView<std::uint16_t> view(pixels, 5, 5);
    const ImageView<std::uint16_t> sub = view.subView(1, 2, 3, 2);
    ASSERT_TRUE(sub.valid());
    sub.fill(7);
    int sevens = 0;
    for (const std::uint16_t p : pixels) {
        sevens += (p == 7) ? 1 : 0;
    }
    EXPECT_EQ(sevens, 6);
    EXPECT_EQ(view.at(1, 2), 7);
    EXPECT_EQ(view.at(3, 3), 7);
    EXPECT_EQ(view.at(4, 3), 0);
}

TEST(ImageView, OutOfBoundsAccessIsAnAssertionAndStaysInside) {
    test::AssertCapture capture;
    std::uint8_t pixels[4] = {1, 2, 3, 4};
    const ImageView<std::uint8_t> view(pixels, 2, 2);
    EXPECT_EQ(view.at(5, 0), 1);  // falls back to (0, 0), never outside the buffer
    EXPECT_EQ(capture.count(), 1);
    EXPECT_FALSE(view.subView(1, 1, 2, 2).valid());
    EXPECT_EQ(capture.count(), 2);
}

TEST(ImageView, ConvertsToConstView) {
    std::uint8_t pixels[2] = {4, 5};
    const ImageView<std::uint8_t> view(pixels, 2, 1);
    const ImageView<const std::uint8_t> cview = view;
    EXPECT_EQ(cview.at(1, 0), 5);
}

TEST(CopyImage, CopiesAcrossStridesAndRejectsSizeMismatch) {
    std::uint8_t src[3 * 4];
    for (int i = 0; i < 12; ++i) {
        src[i] = static_cast<std::uint8_t>(i);
    }
    std::uint8_t dst[3 * 3] = {};
    const ImageView<const std::uint8_t> s(src, 3, 3, 4);
    EXPECT_TRUE(copyImage(s, ImageView<std::uint8_t>(dst, 3, 3)).isOk());
    EXPECT_EQ(dst[4], src[5]);
    EXPECT_EQ(dst[8], src[10]);
    const Status bad = copyImage(s, ImageView<std::uint8_t>(dst, 2, 3));
    EXPECT_EQ(bad.code(), StatusCode::kSizeMismatch);
    EXPECT_EQ(copyImage(ImageView<const std::uint8_t>(), ImageView<std::uint8_t>(dst, 3, 3)).code(),
              StatusCode::kInvalidArgument);
}

TEST(ImageBuffer, SizeIsBoundedByCapacity) {
    static ImageBuffer<std::uint8_t, 64, 32> buffer;
    EXPECT_TRUE(buffer.setSize(64, 10).isOk());
    EXPECT_EQ(buffer.view().width(), 64);
    EXPECT_EQ(buffer.view().height(), 10);
    EXPECT_EQ(buffer.setSize(65, 10).code(), StatusCode::kSizeMismatch);
    EXPECT_EQ(buffer.setSize(0, 10).code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(buffer.view().width(), 64);  // a rejected size leaves the buffer as it was
}

TEST(AllocateImage, CarvesFromTheArenaOrReportsOutOfMemory) {
    StaticArena<1024> arena;
    ImageView<std::uint16_t> img;
    ASSERT_TRUE(allocateImage(arena, 10, 20, img).isOk());
    EXPECT_EQ(img.stride(), 10);
    EXPECT_EQ(img.at(9, 19), 0U);
    ImageView<std::uint16_t> big;
    const Status s = allocateImage(arena, 100, 100, big);
    EXPECT_EQ(s.code(), StatusCode::kOutOfMemory);
    EXPECT_EQ(s.detail(), 100 * 100 * 2);
    EXPECT_FALSE(big.valid());
    EXPECT_EQ(allocateImage(arena, -1, 3, big).code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace vtm
