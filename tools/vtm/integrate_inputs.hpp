// The inputs of `vtm integrate` (docs/tools.md "vtm integrate"): one terrain model per
// command-line INPUT, "PATH[,key=value...]":
//   PATH        a PLY point cloud (readPlyPoints: the model's frame, x north, y east, z
//               down, metres) or a PFM elevation map (metres up, NaN = none) with geo=
//   pose=SPEC   map_from_model, a vtm-camera-poses 1 line (docs/cli-poses.md: FILE or
//               FILE:INDEX); default identity (the points are in the map frame already)
//   geo=FILE    a PFM's georeference in the vtm-orbital-geo 1 format vtm-sim writes
//               (north0_m, east0_m of pixel (0, 0)'s centre, cell_m, width_px, height_px)
//   footprint=M metres each point stands for (default: a PFM's cell_m, 0.05 for a PLY)
//   source=N    0..15 (default: the input's position)
#pragma once

#include <string>
#include <vector>

#include "vtm/core/eigen.hpp"
#include "vtm/core/pose.hpp"
#include "vtm/ground/image.hpp"

namespace vtm::tools {

constexpr double kDefaultPlyFootprintM = 0.05;

struct IntegrateInput {
    std::string spec;             // as given (for the messages)
    std::string path;
    std::vector<Vec3> points_m;   // the model's frame
    RigidPose map_from_model{};   // the navigation's guess
    double footprint_m = 0.0;
    int source = 0;
};

// Parses and loads INPUT number `index`; errors are one line naming the input.
ground::Result<IntegrateInput> loadIntegrateInput(const std::string& spec, int index);

}  // namespace vtm::tools
