// TerrainIntegrator: the executive that merges terrain models of different sources and
// resolutions into one map (issue 25, paper §6, SUMMITT; docs/integrator.md). It sequences
// three modules over one memory plan: octree::Octree (the map), icp::PointToPlaneIcp (the
// registration of each new model to the map) and octree::HeightProducts (height maps at
// several resolutions, finest data wins).
//
// Frames: the map frame is the site frame of the first model (x north, y east, z down,
// metres). A model comes as points in its own frame with the navigation's guess of
// map_from_model (RigidPose, X_map = R X_model + t_m). Each addModel() request:
//   mapmodel  (map not empty, registration asked) the ICP model drawn from the map: the
//             registration grid (a mean height map at registration_level, finest data
//             wins) inside the model's guessed footprint grown by window_margin_m; one
//             point per bin with its own data (bin centre, mean elevation), one per coarse
//             cell for bins filled from a coarser level (the coarse cell's centre); at most
//             icp.max_model_points (an even integer stride when more)
//   register  ICP of the model's points to that cloud from the guess: map_from_model
//   insert    each point moved by the pose into the octree at the level of its footprint
// The first model (an empty map) and models with register_model = false are inserted with
// their guess. A refusal (bad input, too little map under the model, ICP's named Status)
// ends the request before insert: nothing is inserted. extractProducts() rebuilds the
// height maps; products() is null until it succeeds and again after the next addModel().
//
// Every stage leaves a StageRecord and one event (stage_log.hpp). No heap after init, no
// recursion, bounded loops (max_input_points per request), deterministic.
#pragma once

#include <cstddef>
#include <cstdint>

#include "hal/clock.hpp"
#include "hal/event_log.hpp"
#include "vtm/app/stage_log.hpp"
#include "vtm/core/arena.hpp"
#include "vtm/core/eigen.hpp"
#include "vtm/core/pose.hpp"
#include "vtm/core/span.hpp"
#include "vtm/core/status.hpp"
#include "vtm/icp/icp.hpp"
#include "vtm/octree/height_products.hpp"
#include "vtm/octree/octree.hpp"

namespace vtm::app {

constexpr std::int32_t kMaxInputPointsLimit = 1 << 24;  // max_input_points, at most

// How big a piece of ground each point of a model stands for (its octree level).
enum class FootprintKind : std::uint8_t {
    kFixed = 0,           // one footprint for all: a grid's cell, an orbital post
    kPerPoint = 1,        // per_point_m[i] for point i
    kRangeTimesAngle = 2, // |point - sensor_m| * pixel_angle_rad (stereo)
};

struct FootprintRule {
    FootprintKind kind = FootprintKind::kFixed;
    double footprint_m = 0.0;          // kFixed: metres, finite and > 0
    Span<const float> per_point_m{};   // kPerPoint: one per point, metres, finite and > 0
    Vec3 sensor_m{0.0, 0.0, 0.0};      // kRangeTimesAngle: the sensor in the model's frame
    double pixel_angle_rad = 0.0;      // kRangeTimesAngle: finite and > 0
};

struct ModelInput {
    Span<const Vec3> points_m{};          // the model's frame, metres
    RigidPose map_from_model_guess{};     // the navigation's pose of the model frame in the map
    FootprintRule footprint{};
    std::uint8_t source = 0U;             // 0..octree::kMaxSources - 1
    bool register_model = true;           // false: inserted with the guess (a reference)
};

// ICP defaults for models registered to the map's registration grid (docs/integrator.md).
[[nodiscard]] icp::IcpConfig integratorIcpConfig() noexcept;

struct IntegratorConfig {
    octree::OctreeConfig octree{};
    octree::ProductConfig products{};
    icp::IcpConfig icp = integratorIcpConfig();
    // Level of the grid the ICP model is drawn from: 0..min(octree.max_depth,
    // octree::kMaxProductLevel). Default 9: 0.25 m cells in the default 128 m cube.
    std::int32_t registration_level = 9;
    // The window of the map drawn into the ICP model: the model's guessed (x, y) bounding
    // box grown by this, metres, [0, 1e4].
    double window_margin_m = 2.0;
    // Points one addModel() takes at most, 1..kMaxInputPointsLimit (the bound of its loops).
    std::int32_t max_input_points = 1 << 20;
    // kInvalidConfig naming the field ("integrator.registration_level: ..."), or the
    // modules' own ("octree.side_m", "products.levels", "icp.min_gate_m").
    [[nodiscard]] Status validate() const noexcept;
};

struct AddResult {
    RigidPose map_from_model{};   // the pose the points were inserted with (or would have been)
    bool registered = false;      // ICP ran and its pose was used
    icp::IcpResult icp{};         // the registration's figures (empty when it did not run)
    std::int32_t map_model_points = 0;  // ICP model drawn from the map
    double correction_rad = 0.0;  // rotation between the guess and the registered pose
    double correction_m = 0.0;    // how far the registration moved the model's centroid
    std::int64_t inserted = 0;    // samples the octree took
    std::int64_t refused_outside = 0;    // samples outside the octree's cube (skipped)
    std::int64_t refused_pool_full = 0;  // samples refused for the node pool (skipped)
};

class TerrainIntegrator {
public:
    // Octree + HeightProducts (products) + HeightProducts (registration grid, kMean) +
    // PointToPlaneIcp + the ICP model buffer (Vec3 x icp.max_model_points); 0 if invalid.
    [[nodiscard]] static std::size_t workspaceBytes(const IntegratorConfig& config) noexcept;

    // Validates and carves. The clock and the event log are borrowed and must outlive it.
    // kInvalidConfig (the field), kOutOfMemory.
    [[nodiscard]] Status init(const IntegratorConfig& config, Arena& arena, const hal::Clock& clock,
                              hal::EventLog& events) noexcept;

    // One model (file comment). kNotInitialized; before anything changes: kInvalidArgument
    // (no points, more than max_input_points: the count; a guess that is not a rotation; a
    // source >= 16; a footprint rule's value; a footprint not finite and > 0: the point's
    // index), kSizeMismatch (per_point_m's size), kCorruptData (a non-finite point: its
    // index); kNoData (mapmodel: fewer map points under the model than
    // icp.min_correspondences: their count); ICP's setModel / registerData Statuses
    // (kDegenerate for overlap or an ambiguous surface, kNoData ...). insert: kOutOfMemory
    // when the node pool refused samples (those that fit stay inserted; counts in result).
    [[nodiscard]] Status addModel(const ModelInput& model, AddResult& result) noexcept;

    // Rebuilds the height maps from the map. kNotInitialized; the products' Status.
    [[nodiscard]] Status extractProducts() noexcept;
    [[nodiscard]] const octree::HeightProducts* products() const noexcept {
        return published_ ? &products_ : nullptr;
    }

    [[nodiscard]] const octree::Octree& map() const noexcept { return tree_; }
    [[nodiscard]] std::int32_t modelsInserted() const noexcept { return models_; }
    [[nodiscard]] const StageLog& stages() const noexcept { return stages_; }
    [[nodiscard]] const IntegratorConfig& config() const noexcept { return config_; }

private:
    [[nodiscard]] Status checkInput(const ModelInput& model, Vec3& centroid_m) const noexcept;
    [[nodiscard]] double footprintOf(const ModelInput& model, std::size_t i) const noexcept;
    [[nodiscard]] Status drawMapModel(const ModelInput& model, std::int32_t& count) noexcept;
    [[nodiscard]] Status registerModel(const ModelInput& model, std::int32_t map_points, AddResult& result) noexcept;
    [[nodiscard]] Status insertModel(const ModelInput& model, AddResult& result) noexcept;
    Status finish(Stage stage, const Status& status, std::int64_t quality, std::uint64_t t0_ns) noexcept;

    IntegratorConfig config_{};
    const hal::Clock* clock_ = nullptr;
    hal::EventLog* events_ = nullptr;
    octree::Octree tree_{};
    octree::HeightProducts products_{};
    octree::HeightProducts grid_{};    // the registration grid
    icp::PointToPlaneIcp icp_{};
    Span<Vec3> map_model_{};           // the ICP model drawn from the map
    StageLog stages_{};
    std::int32_t models_ = 0;
    bool initialized_ = false;
    bool published_ = false;
};

}  // namespace vtm::app
