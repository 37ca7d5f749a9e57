// SimOdometry: a hal::Odometry serving the odometry-reported poses of a simulated
// scenario (truth plus the scenario's seeded error model, with its covariance), with
// faults injected on cue from a FaultPlan (docs/hal-sim.md).
#pragma once

#include <cstdint>

#include "hal/odometry.hpp"
#include "hal/sim/fault_plan.hpp"
#include "sim/scenario.hpp"

namespace vtm::hal {

class SimOdometry final : public Odometry {
public:
    // Borrowed, not copied: keep frames and faults alive and unchanged while in use.
    struct Config {
        const sim::ScenarioFrames* frames = nullptr;  // sim::buildScenarioFrames output
        const FaultPlan* faults = nullptr;            // optional
    };

    // Collects the scenario's pose samples (one per distinct frame timestamp, in time
    // order). kInvalidConfig naming the field (null frames, no frame).
    [[nodiscard]] Status init(const Config& config) noexcept;

    // The odometry pose at t: a sample's pose exactly at its timestamp; between two
    // samples position and covariance linear, attitude normalised-linear (shorter arc)
    // in the fraction s = (t - ta) / (tb - ta). kNoData outside [first, last] sample;
    // faults as docs/hal-sim.md; every pose passes validatePose() on the way out
    // (kCorruptData with its reason otherwise). `out` is written only on success.
    [[nodiscard]] Status poseAt(std::uint64_t timestamp_ns, PoseEstimate& out) override;

private:
    [[nodiscard]] std::uint64_t sourceStamp(std::int32_t sample) const noexcept;
    [[nodiscard]] Status checkSourceOrder(std::int32_t sample) const noexcept;

    Config config_{};
    std::int32_t sample_frame_[sim::kMaxScenarioFrames] = {};  // frame index of each sample, time order
    std::int32_t sample_count_ = 0;
    bool initialized_ = false;
};

}  // namespace vtm::hal
