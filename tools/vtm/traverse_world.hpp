// The world of the traverse-and-descent fusion (docs/integrator.md "The traverse and the
// descent, fused"; flown by `vtm run`, measured by tests/integrate): one terrain (a
// traverse scenario's, e.g. sim/scenarios/traverse.scn), the traverse's stops with the
// rover's fixed stereo pair rendered at each stop's TRUE pose and mapped by MlStereo +
// triangulation in the stop's vehicle frame, and a descent pair over the same terrain
// mapped by DescentMapper (true poses) into its elevation map. Ground side (heap).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "sim/scenario.hpp"
#include "vtm/core/pose.hpp"
#include "vtm/ground/sim_world.hpp"

namespace vtm::traverse {

// The rover's fixed stereo pair at each stop: two parallel 45 deg pinholes this far apart.
constexpr double kStereoBaseline_m = 0.35;

struct Sizes {
    std::int32_t stereo_px = 512;    // the rover pair's side
    std::int32_t descent_px = 512;   // the nadir frames' side
    std::int32_t samples_log2 = 10;  // terrain grids (as traverse.scn)
};

// One stop: the points of its stereo map in its vehicle frame, the true and odometry
// site_from_vehicle, and the left camera's centre in the vehicle frame (footprints).
struct StopMap {
    RigidPose truth;
    RigidPose odometry;
    std::vector<Vec3> points;
    Vec3 sensor_m = Vec3::Zero();
    double pixel_angle_rad = 0.0;
    std::int64_t valid_disparities = 0;
    double median_abs_vs_truth_m = 0.0;  // |elevation - terrain| of the points at the true pose
};

// The descent's elevation map (site frame, true poses): cell centres and elevations.
struct DescentMap {
    std::vector<Vec3> points;  // (north, east, -elevation), site frame
    double cell_m = 0.0;
    double camera1_height_m = 0.0;
    double rms_vs_truth_m = 0.0;  // cells against the terrain at their centres
};

struct World {
    Sizes sizes;
    ground::SimWorld traverse;  // its scenario, the terrain, the stops' frames
    sim::Scenario descent;
    std::unique_ptr<sim::ScenarioFrames> nadir_frames = std::make_unique<sim::ScenarioFrames>();
    std::vector<StopMap> stops;
    DescentMap descent_map;
    double build_s = 0.0, stereo_s = 0.0, descent_s = 0.0;
    std::string error;  // empty when everything was built
};

// Builds everything (terrain, frames, the stop maps, the descent map) from a traverse
// scenario's text (its terrain's samples_log2 set to sizes.samples_log2). World::error
// says what failed, in one line.
std::unique_ptr<World> buildWorld(const std::string& traverse_text, const Sizes& sizes);

// site_from_vehicle of a simulator pose.
RigidPose toRigidPose(const sim::VehiclePose& v);

}  // namespace vtm::traverse
