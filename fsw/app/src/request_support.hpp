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

// Position sigma (mm) of a pose: sqrt of the trace of its position covariance.
[[nodiscard]] std::int64_t positionSigmaMm(const hal::PoseEstimate& pose) noexcept;

// Finite and within [lo, hi] (config checks).
[[nodiscard]] bool inRange(double value, double lo, double hi) noexcept;

// Appends a record of `stage` (begun at t0_ns on `clock`) to `log` and mirrors it to
// `events` (stage_log.hpp has the event layout). Returns `status`.
Status recordStage(StageLog& log, hal::EventLog& events, const hal::Clock& clock, Stage stage,
                   const Status& status, std::int64_t quality, std::uint64_t t0_ns) noexcept;

// The pose stage of both executives: odometry.poseAt(frame time), recorded with the
// position sigma in mm as its quality.
Status poseStage(hal::Odometry& odometry, StageLog& log, hal::EventLog& events, const hal::Clock& clock,
                 Stage stage, const hal::FrameInfo& frame, hal::PoseEstimate& pose) noexcept;

}  // namespace vtm::app::detail
