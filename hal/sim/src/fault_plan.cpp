#include "hal/sim/fault_plan.hpp"

#include "vtm/core/math.hpp"

namespace vtm::hal {
namespace {

Status invalid(const char* reason) noexcept { return Status(StatusCode::kInvalidArgument, reason); }

Status checkCameraParameters(const Fault& f) noexcept {
    if ((f.kind == FaultKind::kStuckColumns || f.kind == FaultKind::kDeadColumns) &&
        (f.first_column < 0 || f.column_count < 1)) {
        return invalid("FaultPlan: first_column must be >= 0 and column_count >= 1");
    }
    if (f.kind == FaultKind::kSaturation && f.gain_factor < 2U) {
        return invalid("FaultPlan: gain_factor must be >= 2");
    }
    if (f.kind == FaultKind::kTruncatedFrame && f.delivered_rows < 0) {
        return invalid("FaultPlan: delivered_rows must be >= 0");
    }
    return Status::ok();
}

}  // namespace

Fault cameraFault(FaultKind kind, std::uint8_t camera_id, std::uint32_t sequence) noexcept {
    Fault f;
    f.kind = kind;
    f.camera_id = camera_id;
    f.sequence = sequence;
    return f;
}

Fault odometryFault(FaultKind kind, std::uint64_t from_ns, std::uint64_t until_ns) noexcept {
    Fault f;
    f.kind = kind;
    f.from_ns = from_ns;
    f.until_ns = until_ns;
    return f;
}

Status FaultPlan::add(const Fault& fault) noexcept {
    if (fault.kind < FaultKind::kDroppedFrame || fault.kind > FaultKind::kPoseTimestampBackwards) {
        return Status(StatusCode::kInvalidArgument, "FaultPlan: kind is not a FaultKind",
                      static_cast<std::int64_t>(fault.kind));
    }
    VTM_RETURN_IF_ERROR(checkCameraParameters(fault));
    const bool timestamp = fault.kind == FaultKind::kFrameTimestampBackwards ||
                           fault.kind == FaultKind::kPoseTimestampBackwards;
    if (timestamp && fault.backwards_ns == 0U) {
        return invalid("FaultPlan: backwards_ns must be > 0");
    }
    if (!fault.isCameraFault() && fault.until_ns != 0U && fault.until_ns <= fault.from_ns) {
        return invalid("FaultPlan: until_ns must be 0 or after from_ns");
    }
    for (double v : fault.offset_m) {
        if (!math::isFinite(v)) {
            return invalid("FaultPlan: offset_m is not finite");
        }
    }
    if (count_ == kMaxFaults) {
        return Status(StatusCode::kUnsupported, "FaultPlan: more than kMaxFaults (32) faults");
    }
    faults_[count_] = fault;
    ++count_;
    return Status::ok();
}

const Fault* FaultPlan::cameraFault(FaultKind kind, std::uint8_t camera_id, std::uint32_t sequence) const noexcept {
    for (std::size_t i = 0U; i < count_; ++i) {
        const Fault& f = faults_[i];
        if (f.kind == kind && f.camera_id == camera_id && f.sequence == sequence) {
            return &f;
        }
    }
    return nullptr;
}

const Fault* FaultPlan::odometryFault(FaultKind kind, std::uint64_t t_ns) const noexcept {
    for (std::size_t i = 0U; i < count_; ++i) {
        if (faults_[i].kind == kind && faults_[i].activeAt(t_ns)) {
            return &faults_[i];
        }
    }
    return nullptr;
}

}  // namespace vtm::hal
