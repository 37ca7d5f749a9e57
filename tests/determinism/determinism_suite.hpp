// A fixed computation suite whose result bits must be identical on every target and at
// every optimisation level (docs/flight-rules.md, "Deterministic"). It is compiled with
// the flight policy, exactly like flight code, and hashes the bit patterns of:
//   - Eigen fixed-size 3x3 work: LU and Cholesky solves, inverses, quaternion rotations;
//   - vtm::math functions (exp, log, sin, cos, atan2, sqrt) over fixed sweeps;
//   - vtm::Random sequences (integers, uniforms, normals);
//   - integer image operations (box sums, gradients, thresholds) on a generated image;
//   - FMA-sensitive expressions (a*b + c with cancellation): any contraction into a
//     fused multiply-add by the compiler changes these bits;
//   - the ML dense stereo module on a generated pair (disparity, sigma, reason);
//   - the simulated world: a small Mars terrain and a rendered frame (pinhole and
//     CAHVOR, noise and shadows on), its range truth and a rectified pair's disparity;
//   - the wide-baseline front end on a small rendered rover pair (features, matches,
//     refined motion, rectification tables and images) and triangulation into a height map;
//   - the descent plane sweep on a rendered 12-bit nadir pair (depth, score, reason);
//   - local-entropy images and a multi-modal registration on a generated pair;
//   - the terrain octree (every node) and its height products at three levels;
//   - point-to-plane ICP of two generated terrain clouds (pose, covariance, figures);
//   - the descent's orbital fix (fsw/app OrbitalLocator) on a generated map and frames;
//   - the simulated panorama: stations, approximate poses and priors (panorama_section.cpp);
//   - the panorama's tie points (fsw/tiepoints) on two rendered stations (tiepoints_section.cpp);
//   - the bundle adjustment of a small panorama network (fsw/bundle, bundle_section.cpp);
//   - ordinary kriging of scattered samples and the orthophoto of the kriged grid
//     (fsw/kriging; kriging_section.cpp).
#pragma once

#include <cstdint>

namespace vtm::determinism {

enum class Section : std::uint8_t {
    kEigen = 0,
    kMath = 1,
    kRandom = 2,
    kImage = 3,
    kFmaSensitive = 4,
    kStereo = 5,
    kSim = 6,
    kWideBaseline = 7,
    kDescent = 8,
    kEntropy = 9,
    kOctree = 10,
    kIcp = 11,
    kOrbitalFix = 12,
    kPanorama = 13,
    kTiepoints = 14,
    kBundle = 15,
    kKriging = 16,
};
constexpr int kSectionCount = 17;

// Sections defined in their own files (tests/determinism/<module>_section.cpp).
std::uint64_t panoramaSection() noexcept;   // panorama_section.cpp
std::uint64_t tiepointsSection() noexcept;  // tiepoints_section.cpp
std::uint64_t bundleSection() noexcept;     // bundle_section.cpp
std::uint64_t krigingSection() noexcept;    // kriging_section.cpp

// Name of a section for reports ("eigen", "math", ...).
const char* sectionName(Section s) noexcept;

// Hash (64-bit FNV-1a over the little-endian bytes of each value's bit pattern, so that
// byte order does not matter) of one section of the suite.
std::uint64_t sectionHash(Section s) noexcept;

}  // namespace vtm::determinism
