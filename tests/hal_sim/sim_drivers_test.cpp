// SimCamera and SimOdometry: frames bit-identical to sim::renderFrame, poses equal to the
// scenario's odometry poses, every injected fault reaching the consumer as its documented
// Status (docs/hal-sim.md), no heap on the run path.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "hal/sim/fault_plan.hpp"
#include "hal/sim/sim_camera.hpp"
#include "hal/sim/sim_odometry.hpp"
#include "no_heap_guard.hpp"

namespace vtm::hal {
namespace {

using sim::ScenarioFrame;

// The tiny rover pair shared with tests/sim: 128x128 frames, frames 0 and 1 from the
// mast camera (camera 0), 2 and 3 the stereo pair (cameras 1 and 2).
struct World {
    sim::Scenario scenario;
    std::vector<std::byte> storage;
    Arena* arena = nullptr;
    sim::Terrain terrain;
    sim::ScenarioFrames frames;
    bool ok = false;
};

World& world() {
    static World* w = [] {
        auto* made = new World();
        std::ifstream in(std::string(VTM_SCENARIO_DIR) + "/test_rover_small.scn", std::ios::binary);
        std::stringstream text;
        text << in.rdbuf();
        if (!sim::parseScenario(text.str(), made->scenario).isOk()) {
            return made;
        }
        made->storage.resize(sim::scenarioTerrainBytes(made->scenario) + 64U);
        made->arena = new Arena(made->storage.data(), made->storage.size());
        made->ok = sim::buildScenarioTerrain(made->scenario, *made->arena, made->terrain).isOk() &&
                   sim::buildScenarioFrames(made->scenario, made->terrain, made->frames).isOk();
        return made;
    }();
    return *w;
}

const ScenarioFrame& frameOf(std::uint8_t camera_id, std::uint32_t sequence) {
    const sim::ScenarioFrames& f = world().frames;
    for (std::int32_t i = 0; i < f.count; ++i) {
        if (f.frames[i].camera_id == camera_id && f.frames[i].sequence == sequence) {
            return f.frames[i];
        }
    }
    ADD_FAILURE() << "no frame " << int(camera_id) << "/" << sequence;
    return f.frames[0];
}

// The frame as sim::renderFrame renders it when called directly.
std::vector<std::uint8_t> directRender(const ScenarioFrame& frame) {
    std::vector<std::uint8_t> pixels(static_cast<std::size_t>(frame.model.width_px) * frame.model.height_px);
    const sim::FrameRequest r = sim::scenarioFrameRequest(world().scenario, world().terrain, frame);
    sim::FrameOutput o;
    o.image8 = ImageView<std::uint8_t>(pixels.data(), frame.model.width_px, frame.model.height_px);
    EXPECT_TRUE(sim::renderFrame(r, o, nullptr).isOk());
    return pixels;
}

class SimDrivers : public ::testing::Test {
protected:
    void SetUp() override {
        ASSERT_TRUE(world().ok) << "test_rover_small.scn did not parse or build";
        image_.assign(128U * 128U, 0U);
        view_ = ImageView<std::uint8_t>(image_.data(), 128, 128);
    }
    Status initCamera(std::uint8_t camera_id = sim::kMainCameraId) {
        SimCamera::Config c;
        c.scenario = &world().scenario;
        c.terrain = &world().terrain;
        c.frames = &world().frames;
        c.camera_id = camera_id;
        c.faults = &plan_;
        return camera_.init(c);
    }
    Status initOdometry(const FaultPlan* plan) {
        return odometry_.init({&world().frames, plan});
    }
    std::uint64_t timeOf(std::uint32_t sequence) const { return frameOf(0U, sequence).timestamp_ns; }

    FaultPlan plan_;
    SimCamera camera_;
    SimOdometry odometry_;
    std::vector<std::uint8_t> image_;
    ImageView<std::uint8_t> view_;
    FrameInfo info_;
};

TEST_F(SimDrivers, DescribeGivesTheScenarioCamera) {
    ASSERT_TRUE(initCamera().isOk());
    CameraDescription d;
    ASSERT_TRUE(camera_.describe(d).isOk());
    const ScenarioFrame& f = frameOf(0U, 0U);
    EXPECT_EQ(d.camera_id, 0U);
    EXPECT_EQ(d.bit_depth, 8U);
    EXPECT_EQ(d.width_px, 128);
    EXPECT_EQ(d.height_px, 128);
    EXPECT_EQ(std::memcmp(&d.model, &f.model, sizeof d.model), 0);
    EXPECT_EQ(d.model.kind, world().scenario.camera.kind);
}

TEST_F(SimDrivers, FramesAreBitIdenticalToRenderFrameWithTheirInfo) {
    ASSERT_TRUE(initCamera().isOk());
    for (std::uint32_t seq = 0U; seq < 2U; ++seq) {
        ASSERT_TRUE(camera_.capture(view_, info_).isOk());
        const ScenarioFrame& f = frameOf(0U, seq);
        EXPECT_EQ(image_, directRender(f));
        EXPECT_EQ(info_.sequence, seq);
        EXPECT_EQ(info_.timestamp_ns, f.timestamp_ns);
        EXPECT_EQ(info_.exposure_us, static_cast<std::uint32_t>(std::lround(f.sensor.exposure_s * 1e6)));
        EXPECT_EQ(info_.camera_id, 0U);
        EXPECT_EQ(info_.bit_depth, 8U);
        EXPECT_EQ(info_.width_px, 128);
        EXPECT_EQ(camera_.lastFaults(), 0U);
    }
    const Status end = camera_.capture(view_, info_);
    EXPECT_EQ(end.code(), StatusCode::kNoData);
    EXPECT_STREQ(end.reason(), "SimCamera: end of the scenario");
    camera_.rewind();
    ASSERT_TRUE(camera_.capture(view_, info_).isOk());
    EXPECT_EQ(info_.sequence, 0U);
    // The stereo cameras are separate cameras of the same scenario.
    ASSERT_TRUE(initCamera(sim::kStereoRightCameraId).isOk());
    ASSERT_TRUE(camera_.capture(view_, info_).isOk());
    EXPECT_EQ(image_, directRender(frameOf(sim::kStereoRightCameraId, 0U)));
    EXPECT_EQ(info_.camera_id, sim::kStereoRightCameraId);
}

TEST_F(SimDrivers, DroppedFrameIsNoDataAndLeavesASequenceGap) {
    ASSERT_TRUE(plan_.add(cameraFault(FaultKind::kDroppedFrame, 0U, 0U)).isOk());
    ASSERT_TRUE(initCamera().isOk());
    const Status s = camera_.capture(view_, info_);
    EXPECT_EQ(s.code(), StatusCode::kNoData);
    EXPECT_STREQ(s.reason(), "SimCamera: frame dropped");
    EXPECT_EQ(camera_.lastFaults(), 1U << 1U);
    ASSERT_TRUE(camera_.capture(view_, info_).isOk());
    EXPECT_EQ(info_.sequence, 1U);  // the gap tells the consumer a frame was lost
    EXPECT_EQ(image_, directRender(frameOf(0U, 1U)));
}

TEST_F(SimDrivers, TruncatedFrameIsCorruptDataAndConsumed) {
    Fault f = cameraFault(FaultKind::kTruncatedFrame, 0U, 0U);
    f.delivered_rows = 100;
    ASSERT_TRUE(plan_.add(f).isOk());
    ASSERT_TRUE(initCamera().isOk());
    info_.sequence = 77U;
    const Status s = camera_.capture(view_, info_);
    EXPECT_EQ(s.code(), StatusCode::kCorruptData);
    EXPECT_STREQ(s.reason(), "SimCamera: frame truncated (fewer rows than height_px)");
    EXPECT_EQ(s.detail(), 100 * 128);
    EXPECT_EQ(info_.sequence, 77U);  // info untouched on failure
    ASSERT_TRUE(camera_.capture(view_, info_).isOk());
    EXPECT_EQ(info_.sequence, 1U);
}

TEST_F(SimDrivers, StuckAndDeadColumnsAreDeliveredWithVisibleDamage) {
    Fault stuck = cameraFault(FaultKind::kStuckColumns, 0U, 0U);
    stuck.first_column = 10;
    stuck.column_count = 3;
    stuck.stuck_value = 200U;
    Fault dead = cameraFault(FaultKind::kDeadColumns, 0U, 0U);
    dead.first_column = 120;
    dead.column_count = 50;  // clipped at the right edge
    ASSERT_TRUE(plan_.add(stuck).isOk());
    ASSERT_TRUE(plan_.add(dead).isOk());
    ASSERT_TRUE(initCamera().isOk());
    ASSERT_TRUE(camera_.capture(view_, info_).isOk());
    EXPECT_EQ(camera_.lastFaults(), (1U << 3U) | (1U << 4U));
    const std::vector<std::uint8_t> clean = directRender(frameOf(0U, 0U));
    int changed_elsewhere = 0;
    for (int y = 0; y < 128; ++y) {
        for (int x = 0; x < 128; ++x) {
            const std::uint8_t v = image_[static_cast<std::size_t>(y * 128 + x)];
            if (x >= 10 && x < 13) {
                EXPECT_EQ(v, 200U);
            } else if (x >= 120) {
                EXPECT_EQ(v, 0U);
            } else if (v != clean[static_cast<std::size_t>(y * 128 + x)]) {
                ++changed_elsewhere;
            }
        }
    }
    EXPECT_EQ(changed_elsewhere, 0);
}

TEST_F(SimDrivers, SaturationClipsTheFrameToFullScale) {
    Fault f = cameraFault(FaultKind::kSaturation, 0U, 0U);
    f.gain_factor = 4U;
    ASSERT_TRUE(plan_.add(f).isOk());
    ASSERT_TRUE(initCamera().isOk());
    ASSERT_TRUE(camera_.capture(view_, info_).isOk());
    const std::vector<std::uint8_t> clean = directRender(frameOf(0U, 0U));
    int clipped = 0;
    for (std::size_t i = 0; i < clean.size(); ++i) {
        EXPECT_EQ(image_[i], std::min(255, 4 * clean[i]));
        clipped += image_[i] == 255U ? 1 : 0;
    }
    EXPECT_GT(clipped, static_cast<int>(clean.size() / 2));  // the scene is mostly above 64 DN
}

TEST_F(SimDrivers, BlackFrameIsDeliveredAllZero) {
    ASSERT_TRUE(plan_.add(cameraFault(FaultKind::kBlackFrame, 0U, 1U)).isOk());
    ASSERT_TRUE(initCamera().isOk());
    ASSERT_TRUE(camera_.capture(view_, info_).isOk());
    EXPECT_EQ(camera_.lastFaults(), 0U);
    ASSERT_TRUE(camera_.capture(view_, info_).isOk());
    EXPECT_EQ(info_.sequence, 1U);
    EXPECT_EQ(camera_.lastFaults(), 1U << 6U);
    EXPECT_EQ(image_, std::vector<std::uint8_t>(image_.size(), 0U));
}

TEST_F(SimDrivers, BackwardsFrameTimestampIsOutOfOrder) {
    Fault f = cameraFault(FaultKind::kFrameTimestampBackwards, 0U, 1U);
    f.backwards_ns = 5U;
    ASSERT_TRUE(plan_.add(f).isOk());
    ASSERT_TRUE(initCamera().isOk());
    ASSERT_TRUE(camera_.capture(view_, info_).isOk());
    const Status s = camera_.capture(view_, info_);
    EXPECT_EQ(s.code(), StatusCode::kOutOfOrder);
    EXPECT_STREQ(s.reason(), "SimCamera: frame timestamp not after the previous frame's");
    EXPECT_EQ(info_.sequence, 0U);
}

TEST_F(SimDrivers, WrongBuffersAndPathsAreRefusedWithoutConsumingAFrame) {
    SimCamera fresh;
    EXPECT_EQ(fresh.capture(view_, info_).code(), StatusCode::kNotInitialized);
    ASSERT_TRUE(initCamera().isOk());
    std::vector<std::uint8_t> small(64U * 128U);
    EXPECT_EQ(camera_.capture(ImageView<std::uint8_t>(small.data(), 64, 128), info_).code(),
              StatusCode::kSizeMismatch);
    EXPECT_EQ(camera_.capture(ImageView<std::uint8_t>(), info_).code(), StatusCode::kInvalidArgument);
    std::vector<std::uint16_t> wide(128U * 128U);
    EXPECT_EQ(camera_.capture16(ImageView<std::uint16_t>(wide.data(), 128, 128), info_).code(),
              StatusCode::kUnsupported);
    ASSERT_TRUE(camera_.capture(view_, info_).isOk());
    EXPECT_EQ(info_.sequence, 0U);
    SimCamera::Config bad;
    EXPECT_EQ(fresh.init(bad).code(), StatusCode::kInvalidConfig);
    bad = {&world().scenario, &world().terrain, &world().frames, 9U, nullptr};
    EXPECT_STREQ(fresh.init(bad).reason(), "SimCamera::Config: no frame of camera_id in frames");
}

TEST_F(SimDrivers, OdometryServesTheScenarioPosesAndInterpolates) {
    ASSERT_TRUE(initOdometry(nullptr).isOk());
    const ScenarioFrame& a = frameOf(0U, 0U);
    const ScenarioFrame& b = frameOf(0U, 1U);
    PoseEstimate p;
    ASSERT_TRUE(odometry_.poseAt(a.timestamp_ns, p).isOk());
    for (int i = 0; i < 3; ++i) {
        EXPECT_EQ(p.position_m[i], a.odometry_pose.position_m[i]);
    }
    for (int i = 0; i < 36; ++i) {
        EXPECT_EQ(p.covariance[i], a.odometry_pose.covariance[i]);
    }
    ASSERT_LT(a.timestamp_ns, b.timestamp_ns);
    const std::uint64_t mid = a.timestamp_ns + (b.timestamp_ns - a.timestamp_ns) / 2U;
    const double s = double(mid - a.timestamp_ns) / double(b.timestamp_ns - a.timestamp_ns);
    ASSERT_TRUE(odometry_.poseAt(mid, p).isOk());
    EXPECT_EQ(p.timestamp_ns, mid);
    for (int i = 0; i < 3; ++i) {
        const double expect = a.odometry_pose.position_m[i] * (1 - s) + b.odometry_pose.position_m[i] * s;
        EXPECT_NEAR(p.position_m[i], expect, 1e-12);
    }
    // The odometry pose differs from the truth (the scenario's error model is on).
    ASSERT_TRUE(odometry_.poseAt(b.timestamp_ns, p).isOk());
    const double err = std::hypot(p.position_m[0] - b.true_pose.position_m[0],
                                  p.position_m[1] - b.true_pose.position_m[1]);
    EXPECT_GT(err, 1e-4);
    EXPECT_EQ(odometry_.poseAt(a.timestamp_ns - 1U, p).code(), StatusCode::kNoData);
}

TEST_F(SimDrivers, OdometryJumpOffsetsThePoseFromItsTime) {
    const std::uint64_t t1 = timeOf(1U);
    Fault f = odometryFault(FaultKind::kOdometryJump, t1, 0U);
    f.offset_m[0] = 0.5;
    f.offset_m[2] = -0.25;
    FaultPlan plan;
    ASSERT_TRUE(plan.add(f).isOk());
    SimOdometry clean;
    ASSERT_TRUE(clean.init({&world().frames, nullptr}).isOk());
    ASSERT_TRUE(initOdometry(&plan).isOk());
    PoseEstimate p, q;
    ASSERT_TRUE(odometry_.poseAt(timeOf(0U), p).isOk());
    ASSERT_TRUE(clean.poseAt(timeOf(0U), q).isOk());
    EXPECT_EQ(p.position_m[0], q.position_m[0]);  // before the jump: untouched
    ASSERT_TRUE(odometry_.poseAt(t1, p).isOk());
    ASSERT_TRUE(clean.poseAt(t1, q).isOk());
    EXPECT_EQ(p.position_m[0], q.position_m[0] + 0.5);
    EXPECT_EQ(p.position_m[1], q.position_m[1]);
    EXPECT_EQ(p.position_m[2], q.position_m[2] - 0.25);
}

TEST_F(SimDrivers, NanPoseIsCorruptData) {
    FaultPlan plan;
    ASSERT_TRUE(plan.add(odometryFault(FaultKind::kPoseNaN, timeOf(1U), timeOf(1U) + 1U)).isOk());
    ASSERT_TRUE(initOdometry(&plan).isOk());
    PoseEstimate p;
    p.timestamp_ns = 42U;
    const Status s = odometry_.poseAt(timeOf(1U), p);
    EXPECT_EQ(s.code(), StatusCode::kCorruptData);
    EXPECT_STREQ(s.reason(), "pose: position_m is not finite");
    EXPECT_EQ(p.timestamp_ns, 42U);  // untouched
    EXPECT_TRUE(odometry_.poseAt(timeOf(0U), p).isOk());  // outside the window
}

TEST_F(SimDrivers, BackwardsPoseTimestampsAreOutOfOrder) {
    const std::uint64_t t0 = timeOf(0U);
    const std::uint64_t t1 = timeOf(1U);
    Fault f = odometryFault(FaultKind::kPoseTimestampBackwards, t1, t1 + 1U);
    f.backwards_ns = t1 - t0;  // stamped at (or before) its predecessor
    FaultPlan plan;
    ASSERT_TRUE(plan.add(f).isOk());
    ASSERT_TRUE(initOdometry(&plan).isOk());
    PoseEstimate p;
    const Status s = odometry_.poseAt(t1, p);
    EXPECT_EQ(s.code(), StatusCode::kOutOfOrder);
    EXPECT_STREQ(s.reason(), "SimOdometry: pose source timestamps went backwards");
    EXPECT_EQ(odometry_.poseAt(t0 + (t1 - t0) / 2U, p).code(), StatusCode::kOutOfOrder);  // needs that sample
}

TEST_F(SimDrivers, FaultPlanChecksItsFaultsAndCapacity) {
    FaultPlan plan;
    Fault f = cameraFault(FaultKind::kSaturation, 0U, 0U);
    f.gain_factor = 1U;
    EXPECT_STREQ(plan.add(f).reason(), "FaultPlan: gain_factor must be >= 2");
    f = cameraFault(FaultKind::kStuckColumns, 0U, 0U);
    f.column_count = 0;
    EXPECT_STREQ(plan.add(f).reason(), "FaultPlan: first_column must be >= 0 and column_count >= 1");
    f = odometryFault(FaultKind::kPoseTimestampBackwards, 10U, 0U);
    f.backwards_ns = 0U;
    EXPECT_STREQ(plan.add(f).reason(), "FaultPlan: backwards_ns must be > 0");
    EXPECT_STREQ(plan.add(odometryFault(FaultKind::kPoseNaN, 10U, 5U)).reason(),
                 "FaultPlan: until_ns must be 0 or after from_ns");
    f = odometryFault(FaultKind::kOdometryJump, 0U, 0U);
    f.offset_m[1] = NAN;
    EXPECT_STREQ(plan.add(f).reason(), "FaultPlan: offset_m is not finite");
    EXPECT_EQ(plan.size(), 0U);
    for (std::size_t i = 0; i < kMaxFaults; ++i) {
        ASSERT_TRUE(plan.add(cameraFault(FaultKind::kBlackFrame, 0U, static_cast<std::uint32_t>(i))).isOk());
    }
    EXPECT_EQ(plan.add(cameraFault(FaultKind::kBlackFrame, 0U, 99U)).code(), StatusCode::kUnsupported);
}

TEST_F(SimDrivers, CaptureAndPoseAtTouchNoHeap) {
    Fault stuck = cameraFault(FaultKind::kStuckColumns, 0U, 0U);
    ASSERT_TRUE(plan_.add(stuck).isOk());
    ASSERT_TRUE(initCamera().isOk());
    ASSERT_TRUE(initOdometry(&plan_).isOk());
    PoseEstimate p;
    test::NoHeapScope scope;
    EXPECT_TRUE(camera_.capture(view_, info_).isOk());
    EXPECT_TRUE(camera_.capture(view_, info_).isOk());
    EXPECT_EQ(camera_.capture(view_, info_).code(), StatusCode::kNoData);
    EXPECT_TRUE(odometry_.poseAt(timeOf(0U) + 1U, p).isOk());
    EXPECT_EQ(scope.heapCalls(), 0U);
}

}  // namespace
}  // namespace vtm::hal
