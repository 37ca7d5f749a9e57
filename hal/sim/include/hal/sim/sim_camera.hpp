// SimCamera: a hal::Camera that renders the frames of a simulated scenario in process
// (sim::renderFrame straight into the caller's buffer: no heap, no extra copy), with
// faults injected on cue from a FaultPlan (docs/hal-sim.md).
#pragma once

#include <cstdint>

#include "hal/camera.hpp"
#include "hal/sim/fault_plan.hpp"
#include "sim/render.hpp"
#include "sim/scenario.hpp"

namespace vtm::hal {

class SimCamera final : public Camera {
public:
    // Everything is borrowed, not copied: the caller keeps the scenario, its built terrain,
    // its frames (sim::buildScenarioFrames) and the fault plan alive and unchanged while
    // the camera is used (they are large: declare them static).
    struct Config {
        const sim::Scenario* scenario = nullptr;      // lighting
        const sim::Terrain* terrain = nullptr;        // built
        const sim::ScenarioFrames* frames = nullptr;  // the frames to play
        std::uint8_t camera_id = sim::kMainCameraId;  // which of the scenario's cameras this is
        const FaultPlan* faults = nullptr;            // optional
    };

    // kInvalidConfig naming the field (null pointer, terrain not built, no frame of
    // camera_id). A failed init leaves the camera uninitialised.
    [[nodiscard]] Status init(const Config& config) noexcept;

    [[nodiscard]] Status describe(CameraDescription& out) const override;
    [[nodiscard]] Status capture(const ImageView<std::uint8_t>& out, FrameInfo& info) override;
    [[nodiscard]] Status capture16(const ImageView<std::uint16_t>& out, FrameInfo& info) override;

    // Plays the scenario again from its first frame (the timestamp history is cleared).
    void rewind() noexcept;

    // Ground truth for tests and reports: bit (1 << FaultKind) for every fault applied
    // to the frame of the last capture()/capture16() that consumed a frame.
    [[nodiscard]] std::uint32_t lastFaults() const noexcept { return last_faults_; }

private:
    template <typename T>
    [[nodiscard]] Status captureInto(const ImageView<T>& out, FrameInfo& info, bool wide) noexcept;
    template <typename T>
    [[nodiscard]] Status render(const sim::ScenarioFrame& frame, const ImageView<T>& out) const noexcept;
    [[nodiscard]] const sim::ScenarioFrame* takeNextFrame() noexcept;
    [[nodiscard]] const Fault* fault(FaultKind kind, std::uint32_t sequence) const noexcept;
    [[nodiscard]] Status checkTimestamp(const sim::ScenarioFrame& frame, std::uint64_t& timestamp_ns) noexcept;

    Config config_{};
    CameraDescription description_{};
    std::int32_t next_index_ = 0;  // next entry of frames->frames to look at
    bool initialized_ = false;
    bool have_previous_ = false;
    std::uint64_t previous_timestamp_ns_ = 0U;
    std::uint32_t last_faults_ = 0U;
};

}  // namespace vtm::hal
