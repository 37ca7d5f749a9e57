// The fault matrix (docs/app.md "Faults"): every fault of hal/sim's FaultPlan
// (docs/hal-sim.md) against each mapping executive, one test per cell. The cells hit the
// second frame of a request and the odometry at and after its time. A cell expects either
// a refusal (a named Status from the stage that meets the fault, nothing published) or a
// map whose damage the executive's own test bounds against the truth (the faults a camera
// or odometry delivers as kOk).
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "hal/clock.hpp"
#include "hal/event_log.hpp"
#include "hal/sim/fault_plan.hpp"
#include "no_heap_guard.hpp"
#include "hal/sim/sim_camera.hpp"
#include "hal/sim/sim_odometry.hpp"
#include "sim/scenario.hpp"
#include "vtm/core/arena.hpp"
#include "vtm/app/stage_log.hpp"
#include "vtm/core/status.hpp"

namespace vtm::app::faults {

enum class Expect : std::uint8_t {
    kRefused,  // code at stage, products() == nullptr
    kMapped,   // products published, damage within the executive's bound
    kMiss,     // products published, damage beyond the bound: a known miss, printed and
               // listed in docs/app.md "Faults" with its figures (the cell still fails on a
               // crash, heap use or a refusal)
};

struct FaultCell {
    std::string name;  // the test's name
    hal::Fault fault;
    Expect expect = Expect::kRefused;
    StatusCode code = StatusCode::kOk;  // kRefused
    Stage stage = Stage::kNone;         // kRefused
};

// The cells, each fault with its parameters and what a flight engineer expects of it;
// an executive's test overrides a cell's expectation where it knowingly misses (kMiss). `width` is the frame width (the damaged
// columns are the 16 around the middle). Where the fault strikes is set by aim(), in the
// test, once the world is built (the cells are listed before, when tests register).
inline std::vector<FaultCell> faultCells(std::int32_t width) {
    using hal::FaultKind;
    const auto camera = [](FaultKind kind) { return hal::cameraFault(kind, 0U, 0U); };
    const auto odometry = [](FaultKind kind) { return hal::odometryFault(kind, 0U, 0U); };
    std::vector<FaultCell> cells;
    cells.push_back({"DroppedFrame", camera(FaultKind::kDroppedFrame), Expect::kRefused, StatusCode::kNoData,
                     Stage::kCapture2});
    hal::Fault truncated = camera(FaultKind::kTruncatedFrame);
    truncated.delivered_rows = 100;
    cells.push_back({"TruncatedFrame", truncated, Expect::kRefused, StatusCode::kCorruptData, Stage::kCapture2});
    hal::Fault stuck = camera(FaultKind::kStuckColumns);
    stuck.first_column = width / 2 - 8;
    stuck.column_count = 16;
    stuck.stuck_value = 200U;
    cells.push_back({"StuckColumns", stuck, Expect::kMapped});
    hal::Fault dead = stuck;
    dead.kind = FaultKind::kDeadColumns;
    cells.push_back({"DeadColumns", dead, Expect::kMapped});
    hal::Fault saturated = camera(FaultKind::kSaturation);
    saturated.gain_factor = 2U;
    cells.push_back({"Saturation", saturated, Expect::kMapped});
    cells.push_back({"BlackFrame", camera(FaultKind::kBlackFrame), Expect::kRefused, StatusCode::kOk, Stage::kNone});
    hal::Fault backwards = camera(FaultKind::kFrameTimestampBackwards);
    backwards.backwards_ns = 1000U;
    cells.push_back({"FrameTimestampBackwards", backwards, Expect::kRefused, StatusCode::kOutOfOrder,
                     Stage::kCapture2});
    cells.push_back({"OdometryJump", odometry(FaultKind::kOdometryJump), Expect::kMapped});
    cells.push_back({"PoseNaN", odometry(FaultKind::kPoseNaN), Expect::kRefused, StatusCode::kCorruptData,
                     Stage::kPose2});
    cells.push_back({"PoseTimestampBackwards", odometry(FaultKind::kPoseTimestampBackwards), Expect::kRefused,
                     StatusCode::kOutOfOrder, Stage::kPose2});
    return cells;
}

// Aims a cell's fault at a request: a camera fault at the frame of `camera_id` with
// sequence `sequence2`; an odometry fault at every query from t2_ns on (a pose-timestamp
// fault stamps those samples t2_ns earlier, far enough to pass the previous one; a jump
// moves the position by jump_m, site frame).
inline hal::Fault aim(const FaultCell& cell, std::uint8_t camera_id, std::uint32_t sequence2, std::uint64_t t2_ns,
                      const double (&jump_m)[3]) {
    hal::Fault f = cell.fault;
    if (f.isCameraFault()) {
        f.camera_id = camera_id;
        f.sequence = sequence2;
        return f;
    }
    f.from_ns = t2_ns;
    f.backwards_ns = t2_ns;
    for (int i = 0; i < 3; ++i) {
        f.offset_m[i] = jump_m[i];
    }
    return f;
}

// Aims a cell at a request of frames 0 and 1 of a scenario: frame 1 (its camera,
// sequence 1) and the odometry from its time; a jump of 5 % of the vehicle's displacement
// between the two frames, along it: the baseline length, which the images cannot observe,
// is what such a jump spoils (every range or depth scales with it).
inline hal::Fault aimAtSecondFrame(const FaultCell& cell, const sim::ScenarioFrames& frames) {
    const sim::ScenarioFrame& f0 = frames.frames[0];
    const sim::ScenarioFrame& f1 = frames.frames[1];
    double jump[3];
    for (int i = 0; i < 3; ++i) {
        jump[i] = 0.05 * (f1.true_pose.position_m[i] - f0.true_pose.position_m[i]);
    }
    return aim(cell, f1.camera_id, 1U, f1.timestamp_ns, jump);
}

// The clean request a damaged map is held against: `Mapper` (WideBaselineMapper,
// DescentMapper) flies one request of the world (its scenario, terrain and frames) on the
// simulated drivers without faults; its products stay valid as long as this object.
template <typename Mapper>
struct CleanRequest {
    hal::SimCamera camera;
    hal::SimOdometry odometry;
    hal::ManualClock clock;
    hal::EventLog events;
    std::vector<std::byte> pool;
    std::unique_ptr<Arena> arena;
    std::unique_ptr<Mapper> mapper = std::make_unique<Mapper>();

    template <typename Config, typename World>
    const auto* fly(const Config& config, const World& world) {
        hal::SimCamera::Config cc;
        cc.scenario = &world.scenario;
        cc.terrain = &world.terrain;
        cc.frames = &world.frames;
        pool.assign(Mapper::workspaceBytes(config), std::byte{0});
        arena = std::make_unique<Arena>(pool.data(), pool.size());
        const bool ok = camera.init(cc).isOk() && odometry.init({&world.frames, nullptr}).isOk() &&
                        mapper->init(config, *arena, camera, odometry, clock, events).isOk() && mapper->map().isOk();
        return ok ? mapper->products() : nullptr;
    }
};

// One request of an executive (map()), failing the test if it touched the heap.
template <typename Mapper>
Status mapWithoutHeap(Mapper& mapper) {
    Status st;
    std::uint64_t heap = 0U;
    {
        vtm::test::NoHeapScope guard;
        st = mapper.map();
        heap = guard.heapCalls();
    }
    EXPECT_EQ(heap, 0U) << "map() used the heap";
    return st;
}

// One line per cell: the stage that failed and why, or "mapped".
inline void printOutcome(const FaultCell& cell, const Status& st, const StageRecord* failed) {
    std::printf("[ fault %s ] %s%s%s (%lld)\n", cell.name.c_str(), failed != nullptr ? stageName(failed->stage) : "mapped",
                st.isOk() ? "" : ": ", st.isOk() ? "" : st.reason(), static_cast<long long>(st.detail()));
}

// A refused cell: a named Status with the cell's code, from the cell's stage (where it
// names them), an error event last, and nothing published.
inline void expectRefused(const FaultCell& cell, const Status& st, const StageRecord* failed, bool published,
                          const hal::EventLog& events) {
    EXPECT_FALSE(st.isOk());
    EXPECT_STRNE(st.reason(), "");
    if (cell.code != StatusCode::kOk) {
        EXPECT_EQ(st.code(), cell.code) << st.reason();
    }
    ASSERT_NE(failed, nullptr);
    if (cell.stage != Stage::kNone) {
        EXPECT_EQ(failed->stage, cell.stage) << stageName(failed->stage);
    }
    EXPECT_FALSE(published);
    ASSERT_GT(events.size(), 0U);
    EXPECT_EQ(events.at(events.size() - 1U).severity, hal::Severity::kError);
}

}  // namespace vtm::app::faults
