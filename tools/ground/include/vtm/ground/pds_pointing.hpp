// The pointing adjustment of a PDS panorama (MER Navcam frames of one pointing sequence):
// each frame's rotation is corrected about its own projection centre so that the tie points
// of neighbouring frames (pds_panorama.hpp) close (docs/pds.md "Pointing adjustment").
// Ground side: it hands the frames and ties to the flight bundle adjustment (fsw/bundle) as
// mono stations (the right eye never observed), unchanged.
//
// Model: frame k becomes a network station whose camera model is its CAHVOR model moved so
// that C = 0 (the frame's projection centre is the station's origin) with site_from_a =
// (R_site_rover, t_site_rover + R_site_rover C). Its prior (vtm/core/image_network.hpp) is
// prior_sigma_deg per site axis on dtheta and centre_sigma_m per axis on dt (0 holds the
// centre): R_adjusted = rotationExp(dtheta) R_label turns the frame about its projection
// centre, dtheta about the site axes. Every tie is a tie point of its own, seen in A at
// pixel_a and in B at pixel_b; its 3D position is solved with the pointing (the projection
// centres of the Navcam frames are 7-9 cm apart and most ties 1-9 m away, so a model with
// one centre and directions would not close them), points eliminated by the Schur complement.
// The priors fix the gauge of every connected part of the network (MER frames 2 and 3 share
// no ties); they are weak against the ties.
#pragma once

#include <cstdint>
#include <vector>

#include "vtm/bundle/bundle_adjuster.hpp"
#include "vtm/core/eigen.hpp"
#include "vtm/core/pose.hpp"
#include "vtm/ground/image.hpp"
#include "vtm/ground/pds_image.hpp"
#include "vtm/ground/pds_panorama.hpp"

namespace vtm::ground {

// The ties of one neighbour pair: indices into the frames.
struct PdsTiePair {
    std::int32_t frame_a = 0;
    std::int32_t frame_b = 1;
    std::vector<PdsTie> ties;
};

struct PdsPointingConfig {
    double sigma_px = 0.2;              // tie measurement noise per axis (> 0)
    double prior_sigma_deg = 0.25;      // each frame's attitude prior per site axis (> 0)
    // Each frame's projection-centre prior per site axis (>= 0; 0 holds the centres): the
    // mast's kinematics place the centres to millimetres, and on 7-9 cm between neighbours a
    // millimetre turns the baseline by half a degree, which held centres push into the
    // rotations (docs/pds.md).
    double centre_sigma_m = 0.005;
    bundle::RobustLoss loss = bundle::RobustLoss::kHuber;
    double robust_k = 3.0;              // in sigma_px
    double outlier_sigmas = 5.0;        // a sighting beyond is left out between rounds
    // A tie whose two rays are closer to parallel than this is left out (kNotTriangulated):
    // with 7-9 cm between the centres, 1e-4 rad keeps ties out to about 800 m.
    double min_parallax_rad = 1e-4;
};

enum class PdsTieUse : std::uint8_t {
    kUsed = 0,             // both sightings inliers of the adjustment
    kOutlier = 1,          // a sighting beyond outlier_sigmas (or its point left with one)
    kNotTriangulated = 2,  // rays too close to parallel (a far tie), or no ray
    kBehindCamera = 3,     // triangulated behind one of the frames
};

struct PdsPointingResult {
    // Per frame: dtheta (rad, about the site axes) with R_adjusted = rotationExp(dtheta) R_label,
    // and its 3x3 covariance (rad^2, a priori: from sigma_px and the prior).
    std::vector<Vec3> correction_rad;
    std::vector<Mat3> covariance_rad2;
    std::vector<Vec3> shift_m;  // the projection centre's move (site frame, m): 0 when held
    // Per pair (in the order given), per tie: its use and its reprojection residuals at the
    // solution (observed minus predicted, px) in A and in B.
    std::vector<std::vector<PdsTieUse>> use;
    std::vector<std::vector<Vec2>> residual_a_px, residual_b_px;
    std::vector<std::vector<double>> range_m;  // the tie point's distance from A's centre (adjusted; else initial)
    bundle::BundleResult bundle;  // counts, image RMS before/after, iterations, stop reason
};

// Errors (one line naming the frame, the pair or the field): fewer than two frames or more
// than 64; a frame without a camera model or rover pose; a pair naming a frame out of range
// or itself; no ties; a bad config field; the adjustment's refusal (its reason).
Result<PdsPointingResult> adjustPdsPointing(const std::vector<PdsImage>& frames, const std::vector<PdsTiePair>& pairs,
                                            const PdsPointingConfig& config);

// The frame's site_from_rover with its attitude turned by correction_rad (about the site axes)
// about its projection centre: R' = rotationExp(c) R, the centre R C + t kept. Put it in a copy
// of the frame to see it with the adjusted pointing (pdsEpipolarDistance, pdsCylinderMosaic).
RigidPose pdsTurnedRoverPose(const PdsImage& frame, const Vec3& correction_rad, const Vec3& shift_m = Vec3::Zero());

}  // namespace vtm::ground
