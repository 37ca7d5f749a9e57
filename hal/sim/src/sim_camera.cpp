#include "hal/sim/sim_camera.hpp"

#include <cstddef>

namespace vtm::hal {
namespace {

std::uint32_t bit(FaultKind kind) noexcept { return 1U << static_cast<std::uint32_t>(kind); }

Status notInitialized() noexcept {
    return Status(StatusCode::kNotInitialized, "SimCamera: call before a successful init()");
}

// Damage that leaves a frame deliverable: the pixels change, the Status does not (a real
// camera does not know its columns are stuck; the consumer's checks must see it).
template <typename T>
void setColumns(const ImageView<T>& out, const Fault& f, T value) noexcept {
    const std::int32_t end = (f.column_count > out.width() - f.first_column) ? out.width()
                                                                             : f.first_column + f.column_count;
    for (std::int32_t y = 0; y < out.height(); ++y) {
        T* row = out.row(y);
        for (std::int32_t x = f.first_column; x < end; ++x) {
            row[x] = value;
        }
    }
}

template <typename T>
void fill(const ImageView<T>& out, T value) noexcept {
    for (std::int32_t y = 0; y < out.height(); ++y) {
        T* row = out.row(y);
        for (std::int32_t x = 0; x < out.width(); ++x) {
            row[x] = value;
        }
    }
}

template <typename T>
void saturate(const ImageView<T>& out, std::uint32_t gain, std::uint32_t full_scale) noexcept {
    for (std::int32_t y = 0; y < out.height(); ++y) {
        T* row = out.row(y);
        for (std::int32_t x = 0; x < out.width(); ++x) {
            // gain <= 2^16 would be needed to overflow 32 bits: values are <= 4095 (12 bit).
            const std::uint64_t v = static_cast<std::uint64_t>(row[x]) * gain;
            row[x] = static_cast<T>(v > full_scale ? full_scale : v);
        }
    }
}

// The deliverable damage of a frame, in a fixed order; returns the bits applied.
template <typename T>
std::uint32_t applyDamage(const FaultPlan& plan, std::uint8_t camera_id, std::uint32_t seq, std::uint32_t full_scale,
                          const ImageView<T>& out) noexcept {
    std::uint32_t applied = 0U;
    if (const Fault* f = plan.cameraFault(FaultKind::kSaturation, camera_id, seq); f != nullptr) {
        applied |= bit(f->kind);
        saturate(out, f->gain_factor, full_scale);
    }
    if (const Fault* f = plan.cameraFault(FaultKind::kStuckColumns, camera_id, seq); f != nullptr) {
        applied |= bit(f->kind);
        setColumns(out, *f, static_cast<T>(f->stuck_value > full_scale ? full_scale : f->stuck_value));
    }
    if (const Fault* f = plan.cameraFault(FaultKind::kDeadColumns, camera_id, seq); f != nullptr) {
        applied |= bit(f->kind);
        setColumns(out, *f, T{0});
    }
    if (const Fault* f = plan.cameraFault(FaultKind::kBlackFrame, camera_id, seq); f != nullptr) {
        applied |= bit(f->kind);
        fill(out, T{0});
    }
    return applied;
}

}  // namespace

Status SimCamera::init(const Config& config) noexcept {
    initialized_ = false;
    if (config.scenario == nullptr) {
        return Status(StatusCode::kInvalidConfig, "SimCamera::Config: scenario is null");
    }
    if (config.terrain == nullptr || !config.terrain->built()) {
        return Status(StatusCode::kInvalidConfig, "SimCamera::Config: terrain is null or not built");
    }
    if (config.frames == nullptr) {
        return Status(StatusCode::kInvalidConfig, "SimCamera::Config: frames is null");
    }
    const sim::ScenarioFrame* first = nullptr;
    for (std::int32_t i = 0; i < config.frames->count && i < sim::kMaxScenarioFrames; ++i) {
        const sim::ScenarioFrame& f = config.frames->frames[i];
        if (f.camera_id == config.camera_id && first == nullptr) {
            first = &f;
        }
    }
    if (first == nullptr) {
        return Status(StatusCode::kInvalidConfig, "SimCamera::Config: no frame of camera_id in frames",
                      config.camera_id);
    }
    config_ = config;
    description_ = CameraDescription{};
    description_.camera_id = config.camera_id;
    description_.bit_depth = static_cast<std::uint8_t>(first->sensor.bit_depth);
    description_.width_px = first->model.width_px;
    description_.height_px = first->model.height_px;
    description_.model = first->model;
    initialized_ = true;
    rewind();
    return Status::ok();
}

void SimCamera::rewind() noexcept {
    next_index_ = 0;
    have_previous_ = false;
    previous_timestamp_ns_ = 0U;
    last_faults_ = 0U;
}

Status SimCamera::describe(CameraDescription& out) const {
    if (!initialized_) {
        return notInitialized();
    }
    out = description_;
    return Status::ok();
}

Status SimCamera::capture(const ImageView<std::uint8_t>& out, FrameInfo& info) {
    return captureInto(out, info, false);
}

Status SimCamera::capture16(const ImageView<std::uint16_t>& out, FrameInfo& info) {
    return captureInto(out, info, true);
}

const sim::ScenarioFrame* SimCamera::takeNextFrame() noexcept {
    // bound: kMaxScenarioFrames entries, each looked at once per rewind
    for (; next_index_ < config_.frames->count && next_index_ < sim::kMaxScenarioFrames; ++next_index_) {
        const sim::ScenarioFrame& f = config_.frames->frames[next_index_];
        if (f.camera_id == config_.camera_id) {
            ++next_index_;
            return &f;
        }
    }
    return nullptr;
}

const Fault* SimCamera::fault(FaultKind kind, std::uint32_t sequence) const noexcept {
    return (config_.faults == nullptr) ? nullptr : config_.faults->cameraFault(kind, config_.camera_id, sequence);
}

// Every frame's stamp must be after the previous delivered one (a driver's own check;
// the kFrameTimestampBackwards fault is what makes it fire).
Status SimCamera::checkTimestamp(const sim::ScenarioFrame& frame, std::uint64_t& timestamp_ns) noexcept {
    timestamp_ns = frame.timestamp_ns;
    const Fault* back = fault(FaultKind::kFrameTimestampBackwards, frame.sequence);
    if (back != nullptr && have_previous_) {
        last_faults_ |= bit(back->kind);
        timestamp_ns = (previous_timestamp_ns_ > back->backwards_ns) ? previous_timestamp_ns_ - back->backwards_ns : 0U;
    }
    if (have_previous_ && timestamp_ns <= previous_timestamp_ns_) {
        return Status(StatusCode::kOutOfOrder, "SimCamera: frame timestamp not after the previous frame's",
                      static_cast<std::int64_t>(frame.sequence));
    }
    return Status::ok();
}

// Straight into the caller's buffer: the bytes sim::renderFrame writes for this frame.
template <typename T>
Status SimCamera::render(const sim::ScenarioFrame& frame, const ImageView<T>& out) const noexcept {
    const sim::FrameRequest request = sim::scenarioFrameRequest(*config_.scenario, *config_.terrain, frame);
    sim::FrameOutput output;
    if constexpr (sizeof(T) == 1U) {
        output.image8 = out;
    } else {
        output.image16 = out;
    }
    return sim::renderFrame(request, output, nullptr);
}

template <typename T>
Status SimCamera::captureInto(const ImageView<T>& out, FrameInfo& info, bool wide) noexcept {
    if (!initialized_) {
        return notInitialized();
    }
    if (wide != (description_.bit_depth > 8U)) {
        return Status(StatusCode::kUnsupported, wide ? "SimCamera: camera has 8 bits per pixel: use capture"
                                                     : "SimCamera: camera has more than 8 bits per pixel: use capture16");
    }
    if (!out.valid()) {
        return Status(StatusCode::kInvalidArgument, "SimCamera: output view is empty or malformed");
    }
    if (out.width() != description_.width_px || out.height() != description_.height_px) {
        return Status(StatusCode::kSizeMismatch, "SimCamera: output buffer size differs from the camera's");
    }
    const sim::ScenarioFrame* frame = takeNextFrame();
    if (frame == nullptr) {
        return Status(StatusCode::kNoData, "SimCamera: end of the scenario");
    }
    last_faults_ = 0U;
    const std::uint32_t seq = frame->sequence;
    if (fault(FaultKind::kDroppedFrame, seq) != nullptr) {
        last_faults_ |= bit(FaultKind::kDroppedFrame);
        return Status(StatusCode::kNoData, "SimCamera: frame dropped", static_cast<std::int64_t>(seq));
    }
    std::uint64_t timestamp_ns = 0U;
    VTM_RETURN_IF_ERROR(checkTimestamp(*frame, timestamp_ns));
    VTM_RETURN_IF_ERROR(render(*frame, out));
    const Fault* truncated = fault(FaultKind::kTruncatedFrame, seq);
    if (truncated != nullptr && truncated->delivered_rows < out.height()) {
        last_faults_ |= bit(FaultKind::kTruncatedFrame);
        return Status(StatusCode::kCorruptData, "SimCamera: frame truncated (fewer rows than height_px)",
                      static_cast<std::int64_t>(truncated->delivered_rows) * out.width());
    }
    if (config_.faults != nullptr) {
        const auto full_scale = static_cast<std::uint32_t>((1U << description_.bit_depth) - 1U);
        last_faults_ |= applyDamage(*config_.faults, config_.camera_id, seq, full_scale, out);
    }
    have_previous_ = true;
    previous_timestamp_ns_ = timestamp_ns;
    info.sequence = seq;
    info.timestamp_ns = timestamp_ns;
    const double exposure_us = frame->sensor.exposure_s * 1e6 + 0.5;  // rounded to the microsecond
    info.exposure_us = (exposure_us >= 4294967295.0) ? 0xFFFFFFFFU : static_cast<std::uint32_t>(exposure_us);
    info.camera_id = description_.camera_id;
    info.bit_depth = description_.bit_depth;
    info.width_px = description_.width_px;
    info.height_px = description_.height_px;
    return Status::ok();
}

}  // namespace vtm::hal
