// The analytic terrain of the octree tests: two smooth hills, a tilt and a box-shaped rock,
// sampled by three sources of different resolution over a 64 m cube (north edge 32 m,
// west edge -32 m, top z -16 m, max_depth 10: finest cell 0.0625 m).
//   - source 0, rover stereo: a 0.125 m grid over north, east in [-8, 8); footprint
//     0.01 x range from the rover at the origin (1 cm per metre: a pixel of 10 mrad), so
//     levels 10 (footprint <= 0.0625 m, range <= 6.25 m) and 9 beyond;
//   - source 1, orbital: 1 m cells (footprint 1 m: level 6) over east < 16 m;
//   - source 2, descent: 4 m cells (footprint 3 m: level 4) over the whole cube.
// Each sample is the surface at its cell centre. Elevations up (site z = -elevation).
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "vtm/octree/octree.hpp"

namespace vtm::octree::test {

constexpr double kNorth = 32.0;
constexpr double kWest = -32.0;
constexpr double kSide = 64.0;
constexpr double kRoverHalf = 8.0;      // rover square: north, east in [-8, 8)
constexpr double kRoverStep = 0.125;
constexpr double kOrbitalEastEnd = 16.0;  // orbital data east < 16 m
constexpr double kRockHeight = 0.6;

inline OctreeConfig sceneConfig() {
    OctreeConfig c;
    c.north_edge_m = kNorth;
    c.west_edge_m = kWest;
    c.top_z_m = -16.0;
    c.side_m = kSide;
    c.max_depth = 10;
    c.max_nodes = 60000;
    return c;
}

inline double bump(double dn, double de, double radius) {
    const double u = (dn * dn + de * de) / (radius * radius);
    return (u < 1.0) ? (1.0 - u) * (1.0 - u) : 0.0;
}

// The rock: north [2, 3), east [-4, -3): edges on the 0.25 m and 1 m bin boundaries and
// between the rover's sample rows, so every bin is wholly on or off it.
inline bool onRock(double north, double east) { return north >= 2.0 && north < 3.0 && east >= -4.0 && east < -3.0; }

// Elevation (up, metres) at (north, east).
inline double surface(double north, double east) {
    const double hills = 1.5 * bump(north - 3.0, east + 2.0, 6.0) + 0.8 * bump(north + 10.0, east - 12.0, 9.0) +
                         0.02 * north - 0.01 * east;
    return hills + (onRock(north, east) ? kRockHeight : 0.0);
}

inline Sample sampleAt(double north, double east, double footprint, std::uint8_t source) {
    Sample s;
    s.site_m = Vec3(north, east, -surface(north, east));
    s.footprint_m = footprint;
    s.source = source;
    return s;
}

inline bool inRover(double north, double east) {
    return north >= -kRoverHalf && north < kRoverHalf && east >= -kRoverHalf && east < kRoverHalf;
}

// Rover, then orbital, then descent samples.
inline std::vector<Sample> sceneSamples() {
    std::vector<Sample> out;
    const int n = static_cast<int>(2.0 * kRoverHalf / kRoverStep);
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            const double north = -kRoverHalf + (i + 0.5) * kRoverStep;
            const double east = -kRoverHalf + (j + 0.5) * kRoverStep;
            const double range = std::sqrt(north * north + east * east);
            out.push_back(sampleAt(north, east, 0.01 * range, 0U));
        }
    }
    for (int i = 0; i < 64; ++i) {
        for (int j = 0; j < 64; ++j) {
            const double north = kNorth - kSide + i + 0.5;
            const double east = kWest + j + 0.5;
            if (east < kOrbitalEastEnd) {
                out.push_back(sampleAt(north, east, 1.0, 1U));
            }
        }
    }
    for (int i = 0; i < 16; ++i) {
        for (int j = 0; j < 16; ++j) {
            out.push_back(sampleAt(kNorth - kSide + 4.0 * i + 2.0, kWest + 4.0 * j + 2.0, 3.0, 2U));
        }
    }
    return out;
}

}  // namespace vtm::octree::test
