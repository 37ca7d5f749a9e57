// Internal to fsw/app: what both mapping executives do the same way (memory carving,
// 8-bit copies of frames, recording a stage). Not installed.
#pragma once

#include <cstdint>

#include "hal/camera.hpp"
#include "hal/clock.hpp"
#include "hal/event_log.hpp"
#include "hal/odometry.hpp"
#include "vtm/app/stage_log.hpp"
#include "vtm/core/arena.hpp"
#include "vtm/core/image.hpp"

namespace vtm::app::detail {

// width x height elements from the arena, or an empty view when it is exhausted.
template <typename T>
ImageView<T> carve(Arena& arena, std::int32_t width, std::int32_t height) noexcept {
    const Span<T> s = arena.allocateArray<T>(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
    return s.empty() ? ImageView<T>() : ImageView<T>(s.data(), width, height);
}

// The top 8 bits of a frame of bit_depth significant bits (the feature, rectification and
// stereo modules are 8-bit). Same sizes (the callers' buffers are carved together).
void toGrey8(const ImageView<const std::uint16_t>& in, std::uint8_t bit_depth,
             const ImageView<std::uint8_t>& out) noexcept;

// Exposure equalisation of a pair whose stereo compares grey levels (WideBaselineMapper):
// the median grey level of each image's pixels with content (grey level 0 is the
// rectified images' "no content" and is left out) gives the gain median(reference) /
// median(image), in 1/65536. When it differs from 1 by more than tolerance_percent, every
// pixel of `image` is multiplied by it (rounded, clipped to 255) and the gain is
// returned; otherwise `image` is left alone and 65536 is returned, as it is when either
// image has no content. Integer arithmetic: the same bits on every target.
[[nodiscard]] std::uint32_t equalizeExposure(const ImageView<const std::uint8_t>& reference,
                                             const ImageView<std::uint8_t>& image,
                                             std::int32_t tolerance_percent) noexcept;

// 1-sigma of the odometry's rotation between two poses, radians: sqrt of the sum of the
// traces of both rotation covariances (the RMS length of the rotation error vector, as
// motion::MotionResult::rotation_sigma_rad). Their errors taken as independent, an upper
// bound for drift that accumulates along the drive. 0 when neither carries one.
[[nodiscard]] double relativeRotationSigmaRad(const hal::PoseEstimate& a, const hal::PoseEstimate& b) noexcept;

// A refined pose may be published only if it is not much less certain than the odometry
// it started from: false when max_ratio > 0, odometry_sigma_rad > 0 and
// refined_sigma_rad > max_ratio * odometry_sigma_rad (docs/app.md "Refinement certainty").
[[nodiscard]] bool refinementIsCertainEnough(double refined_sigma_rad, double odometry_sigma_rad,
                                             double max_ratio) noexcept;

// Position sigma (mm) of a pose: sqrt of the trace of its position covariance.
[[nodiscard]] std::int64_t positionSigmaMm(const hal::PoseEstimate& pose) noexcept;

// Appends a record of `stage` (begun at t0_ns on `clock`) to `log` and mirrors it to
// `events` (stage_log.hpp has the event layout). Returns `status`.
Status recordStage(StageLog& log, hal::EventLog& events, const hal::Clock& clock, Stage stage,
                   const Status& status, std::int64_t quality, std::uint64_t t0_ns) noexcept;

// The pose stage of both executives: odometry.poseAt(frame time), recorded with the
// position sigma in mm as its quality.
Status poseStage(hal::Odometry& odometry, StageLog& log, hal::EventLog& events, const hal::Clock& clock,
                 Stage stage, const hal::FrameInfo& frame, hal::PoseEstimate& pose) noexcept;

}  // namespace vtm::app::detail
