// The rover half of `vtm run` (run_command.cpp has the command and the descent half): a
// rover_pair scenario flown through hal/sim by app::WideBaselineMapper, its products on
// disk and the report's section, every figure measured against the simulator's truth.
#pragma once

#include <string>

#include "hal/camera.hpp"
#include "hal/odometry.hpp"
#include "vtm/app/camera_mount.hpp"
#include "vtm/ground/sim_world.hpp"

namespace vtm::tools {

// A camera's mount on its vehicle (the calibration): the simulator's TRUE camera pose of
// a frame in the TRUE vehicle frame of the same frame.
app::CameraMount cameraMountOf(const sim::ScenarioFrame& frame);

// Flies the scenario's wide-baseline pair (frames 0 and 1 of the main camera) once.
// Writes rover_* products into out_dir and returns the report's Markdown section in
// `section`. Returns "" or the one-line error (drivers, init, a file that cannot be
// written); a request that fails in a stage is not an error here: `mapped` is false and
// the section says which stage and why.
// Frames and poses come from `camera` and `odometry` (the simulated drivers in process, or
// the HIL link); `world` is the same scenario in process, for the truth.
std::string flyRover(const ground::SimWorld& world, hal::Camera& camera, hal::Odometry& odometry,
                     const std::string& out_dir, std::string& section, bool& mapped);

}  // namespace vtm::tools
