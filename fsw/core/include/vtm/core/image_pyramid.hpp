// Image pyramids: an 8-bit image halved by 2x2 averaging (the coarse levels of the
// coarse-to-fine stereo, stereo::PyramidStereo, and of the features' template matcher).
#pragma once

#include <cstddef>
#include <cstdint>

#include "vtm/core/image.hpp"
#include "vtm/core/status.hpp"

namespace vtm {

// 8-bit image at half the size: dst pixel (x, y) is the rounded mean of src pixels 2x..2x+1,
// 2y..2y+1 (so its centre is src's (2x + 0.5, 2y + 0.5)); an odd last row or column of src
// is dropped. dst must be exactly (src.width() / 2) x (src.height() / 2), both at least 1.
[[nodiscard]] inline Status halveImage(const ImageView<const std::uint8_t>& src,
                                       const ImageView<std::uint8_t>& dst) noexcept {
    if (!src.valid() || !dst.valid()) {
        return Status(StatusCode::kInvalidArgument, "halveImage: empty or malformed view");
    }
    if (!dst.sameSize(src.width() / 2, src.height() / 2)) {
        return Status(StatusCode::kSizeMismatch, "halveImage: destination must be half the source size",
                      dst.width());
    }
    for (std::int32_t y = 0; y < dst.height(); ++y) {
        const std::uint8_t* r0 = src.row(2 * y);
        const std::uint8_t* r1 = src.row(2 * y + 1);
        std::uint8_t* d = dst.row(y);
        for (std::int32_t x = 0; x < dst.width(); ++x) {
            const std::ptrdiff_t i = static_cast<std::ptrdiff_t>(x) * 2;
            const std::uint32_t s = static_cast<std::uint32_t>(r0[i]) + r0[i + 1] + r1[i] + r1[i + 1];
            d[x] = static_cast<std::uint8_t>((s + 2U) >> 2U);
        }
    }
    return Status::ok();
}

}  // namespace vtm
