// hal::Camera: how flight code gets frames. A driver (hal/sim, hal/link, hal/file, or a
// flight camera) fills a caller-provided buffer; the interface never allocates and
// never blocks longer than the driver's configured timeout.
#pragma once

#include <cstdint>

#include "hal/camera_model.hpp"
#include "vtm/core/image.hpp"
#include "vtm/core/status.hpp"

namespace vtm::hal {

struct FrameInfo {
    std::uint32_t sequence = 0U;      // frame counter of this camera, +1 per frame
    std::uint64_t timestamp_ns = 0U;  // exposure mid-point, monotonic clock (hal::Clock)
    std::uint32_t exposure_us = 0U;   // exposure time, microseconds
    std::uint8_t camera_id = 0U;      // which camera on the vehicle
    std::uint8_t bit_depth = 8U;      // significant bits per pixel (8 or 12)
    std::int32_t width_px = 0;
    std::int32_t height_px = 0;
};

struct CameraDescription {
    std::uint8_t camera_id = 0U;
    std::uint8_t bit_depth = 8U;
    std::int32_t width_px = 0;
    std::int32_t height_px = 0;
    CameraModel model{};
};

class Camera {
public:

    // Static description: size, bit depth, geometric model.
    [[nodiscard]] virtual Status describe(CameraDescription& out) const = 0;

    // Captures the next frame into `out` (8-bit pixels), which must have exactly the
    // camera's size. Failures: kSizeMismatch (buffer), kTimeout, kNoData (frame
    // dropped), kCorruptData (truncated or damaged frame), kUnsupported (a 12-bit
    // camera: use capture16). On failure `out` content is unspecified and `info` is
    // left unchanged.
    [[nodiscard]] virtual Status capture(const ImageView<std::uint8_t>& out, FrameInfo& info) = 0;

    // The same for cameras with more than 8 significant bits (values 0..2^bit_depth-1).
    [[nodiscard]] virtual Status capture16(const ImageView<std::uint16_t>& out, FrameInfo& info) {
        (void)out;
        (void)info;
        return Status(StatusCode::kUnsupported, "Camera: this camera has no 16-bit capture");
    }

protected:
    // Not deletable through the interface, hence no virtual destructor: a virtual one
    // makes every driver emit a deleting destructor that references operator delete
    // (the heap-symbol check rejects it). Drivers are statically allocated and final.
    Camera() = default;
    ~Camera() = default;
    Camera(const Camera&) = default;
    Camera& operator=(const Camera&) = default;
    Camera(Camera&&) = default;
    Camera& operator=(Camera&&) = default;
};

}  // namespace vtm::hal
