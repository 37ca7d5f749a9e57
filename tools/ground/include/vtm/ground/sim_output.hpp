// The files `vtm-sim render` writes (docs/sim-scenarios.md "Output files"), written and
// read back on the ground: 16-bit PNG and PGM frames, pose logs in hal/file's format
// (docs/hal-file.md "Pose log") and the per-frame camera pose table.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "vtm/core/pose.hpp"
#include "vtm/ground/image.hpp"

namespace vtm::ground {

// One-channel 16-bit grey PNG (samples stored most significant byte first, as PNG
// requires; zlib stream of stored blocks: no compression, exact and simple). Read back
// with loadGrey16() or hal/file's FileCamera.
Outcome writePng16(const std::string& path, const Grey16Image& image);

// Binary PGM (P5): 8-bit (maxval 255), or 16-bit samples most significant byte first with
// the given maxval (256..65535; 4095 for a 12-bit camera).
Outcome writePgm8(const std::string& path, const GreyImage& image);
Outcome writePgm16(const std::string& path, const Grey16Image& image, int maxval);

// A vehicle pose T_site_from_vehicle in hal::PoseEstimate's layout (hal/odometry.hpp).
struct SimPose {
    std::uint64_t timestamp_ns = 0U;
    double position_m[3] = {0.0, 0.0, 0.0};
    double attitude_wxyz[4] = {1.0, 0.0, 0.0, 0.0};
    double covariance[36] = {};
};

// "vtm-poses 1" log (hal/file FileOdometry reads it): one line per pose, 14 fields
// (covariance diagonal) when every off-diagonal covariance is zero, else 44; numbers
// with 17 significant digits, so reading gives back the same bits.
std::string formatPoseLog(const std::vector<SimPose>& poses, const std::string& comment);
// Reads a pose log written by formatPoseLog (or by hand in the same format; 14 or 44
// fields). The error names the file and the line.
Result<std::vector<SimPose>> readPoseLog(const std::string& path);

// Where a camera was when a frame was taken: site_from_cam of the camera model's
// reference frame (a vtm::RigidPose, as sim::ScenarioFrame::camera_pose), one line per frame:
//   vtm-camera-poses 1
//   <frame_index> <camera> <timestamp_ns> <x> <y> <z> <qw> <qx> <qy> <qz>
struct SimCameraPose {
    std::uint32_t frame_index = 0U;
    std::string camera;  // camera name: mast, nadir, stereo_left, stereo_right
    std::uint64_t timestamp_ns = 0U;
    double position_m[3] = {0.0, 0.0, 0.0};
    double attitude_wxyz[4] = {1.0, 0.0, 0.0, 0.0};
};
// The record is the file's layout; ground code computes with the pose as a RigidPose
// through these two, the one conversion (docs/cli-poses.md):
//  - siteFromCam: R from the quaternion, normalised (Eigen's normalized().toRotationMatrix()),
//    t_m = position_m;
//  - setSiteFromCam: position_m = t_m, attitude = Eigen's quaternion of R (w, x, y, z);
//    frame_index, camera and timestamp_ns are left as they are.
RigidPose siteFromCam(const SimCameraPose& p);
void setSiteFromCam(SimCameraPose& p, const RigidPose& site_from_cam);

std::string formatCameraPoses(const std::vector<SimCameraPose>& poses);
Result<std::vector<SimCameraPose>> readCameraPoses(const std::string& path);

// One camera pose named on a command line (docs/cli-poses.md): "FILE" (a vtm-camera-poses 1
// file with exactly one pose line) or "FILE:INDEX" (the line whose frame_index is INDEX,
// e.g. frame 1 of vtm-sim's camera_poses.txt). The attitude must be a unit quaternion
// within 1e-6 (numbers are finite: the reader refuses others); errors name the spec and the reason.
Result<SimCameraPose> readCameraPoseSpec(const std::string& spec);

}  // namespace vtm::ground
