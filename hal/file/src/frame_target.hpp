// FrameTarget: the caller's output buffer as the frame decoders see it, 8-bit or 16-bit,
// with the largest sample value it may receive. Decoders hand it one row at a time as a
// "sample at column x" function; the target checks the value and stores it, so the PGM
// and PNG decoders share one range check and one store loop.
#pragma once

#include <cstdint>

#include "vtm/core/image.hpp"
#include "vtm/core/status.hpp"

namespace vtm::hal::detail {

class FrameTarget {
public:
    // An 8-bit camera: samples 0..255.
    explicit FrameTarget(const ImageView<std::uint8_t>& out) noexcept
        : out8_(out), width_(out.width()), height_(out.height()), max_sample_(255U) {}
    // A camera of bit_depth 9..16: samples 0..2^bit_depth - 1.
    FrameTarget(const ImageView<std::uint16_t>& out, std::uint8_t bit_depth) noexcept
        : out16_(out), wide_(true), width_(out.width()), height_(out.height()),
          max_sample_((1U << bit_depth) - 1U) {}

    [[nodiscard]] std::int32_t width() const noexcept { return width_; }
    [[nodiscard]] std::int32_t height() const noexcept { return height_; }
    // True for a capture16 target (16-bit samples allowed in the file).
    [[nodiscard]] bool wide() const noexcept { return wide_; }
    [[nodiscard]] std::uint32_t maxSample() const noexcept { return max_sample_; }

    // A copy that refuses samples above `limit` (when that is tighter than the camera's
    // range) with `reason`; e.g. a PGM's maxval.
    [[nodiscard]] FrameTarget limitedTo(std::uint32_t limit, const char* reason) const noexcept {
        FrameTarget narrower = *this;
        if (limit < max_sample_) {
            narrower.max_sample_ = limit;
            narrower.range_reason_ = reason;
        }
        return narrower;
    }

    // Stores row y: out[y][x] = sampleAt(x) for x in [0, width). kCorruptData (detail =
    // the sample) when a sample exceeds maxSample(); the row is then partly written.
    template <typename SampleAt>
    [[nodiscard]] Status fillRow(std::int32_t y, const SampleAt& sampleAt) const noexcept {
        if (wide_) {
            std::uint16_t* row = out16_.row(y);
            for (std::int32_t x = 0; x < width_; ++x) {
                const std::uint32_t v = sampleAt(x);
                if (v > max_sample_) {
                    return Status(StatusCode::kCorruptData, range_reason_, static_cast<std::int64_t>(v));
                }
                row[x] = static_cast<std::uint16_t>(v);
            }
            return Status::ok();
        }
        std::uint8_t* row = out8_.row(y);
        for (std::int32_t x = 0; x < width_; ++x) {
            const std::uint32_t v = sampleAt(x);
            if (v > max_sample_) {
                return Status(StatusCode::kCorruptData, range_reason_, static_cast<std::int64_t>(v));
            }
            row[x] = static_cast<std::uint8_t>(v);
        }
        return Status::ok();
    }

private:
    ImageView<std::uint8_t> out8_{};
    ImageView<std::uint16_t> out16_{};
    bool wide_ = false;
    std::int32_t width_ = 0;
    std::int32_t height_ = 0;
    std::uint32_t max_sample_ = 0U;
    const char* range_reason_ = "frame: sample exceeds the camera's bit depth";
};

// Reasons shared by both decoders when a file disagrees with the manifest.
inline constexpr const char* kWidthMismatch = "frame: width differs from the manifest's width_px";
inline constexpr const char* kHeightMismatch = "frame: height differs from the manifest's height_px";
inline constexpr const char* kWideSamplesFor8Bit = "frame: 16-bit samples for an 8-bit camera";

}  // namespace vtm::hal::detail
