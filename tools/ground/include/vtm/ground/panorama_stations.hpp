// The stations file of a mast panorama, "vtm-panorama-stations 1" (docs/panorama-cli.md):
// what `vtm panorama` reads and `vtm-sim render` writes for a panorama scenario
// (panorama_stations.txt). Per file: the rig (the two eyes' camera model files and the
// calibrated right_from_left), the images' bit depth; per station: its two image files,
// the left eye's approximate site pose and its pointing prior (6x6 covariance of
// (dtheta [rad], dt [m]), vtm/core/image_network.hpp), optionally the true pose (the
// simulator's) and its place in the panorama (tier, column, pan, tilt).
//
// One format, one reader and one writer: the simulator formats its stations with
// formatPanoramaStations and the command parses them with parsePanoramaStations, so what
// the one writes is what the other reads. Ground code: heap and std::string.
#pragma once

#include <string>
#include <vector>

#include "vtm/core/eigen.hpp"
#include "vtm/core/pose.hpp"
#include "vtm/ground/image.hpp"

namespace vtm::ground {

// The most stations a file may hold: the bundle adjustment's capacity
// (bundle::kMaxStationsLimit; `vtm panorama` checks that the two agree).
constexpr int kMaxPanoramaFileStations = 64;

struct PanoramaStationRecord {
    std::string left_image;         // as written: a path relative to the file's directory, or absolute
    std::string right_image;
    std::size_t images_line = 0U;   // the line of the 'images' key (for the messages about the files)
    RigidPose approx{};             // site_from_left: the telemetry's pose
    bool has_truth = false;         // a "true" line (simulator files)
    RigidPose truth{};
    Mat6 prior = Mat6::Zero();      // of (dtheta [rad], dt [m])
    int tier = -1;                  // -1: not given
    int column = -1;
    double pan_deg = 0.0;           // informational (0 when not given)
    double tilt_deg = 0.0;
};

struct PanoramaStationsFile {
    std::string left_camera;        // camera model files (docs/camera-models.md), as written
    std::string right_camera;
    RigidPose right_from_left{};    // X_right = R X_left + t: the rig's calibration (CameraPair::b_from_a)
    int bit_depth = 8;              // of the image files, 8..16; 16-bit samples are shifted right by bit_depth - 8
    int tiers = 0;                  // 0: not given
    int columns = 0;                // 0: not given (the stations per ring)
    std::vector<PanoramaStationRecord> stations;
};

// Parses the text of a stations file. Refused with "line N: reason" (N 1-based; 0 for what
// is missing at the end): a wrong first line, an unknown or repeated key, a malformed or
// non-finite number, a pose whose quaternion is not unit within 2e-6 in its squared norm,
// a prior that is not symmetric (1e-12 relative), has a negative variance, a fixed
// parameter (zero variance) with a non-zero covariance, or is not positive definite on
// its free parameters, more stations than kMaxPanoramaFileStations, tiers x columns other
// than the station count, stations out of order, a station without images, approx or
// prior, a missing left_camera / right_camera / right_from_left, or fewer stations than
// announced.
Result<PanoramaStationsFile> parsePanoramaStations(const std::string& text);

// Reads and parses PATH; errors "PATH: line N: reason" (or "PATH: cannot open").
Result<PanoramaStationsFile> readPanoramaStationsFile(const std::string& path);

// The text of a file: header, the comment lines (each prefixed "# "), the rig, the
// stations; every number "%.17g" (positions and priors read back bit for bit; attitudes
// as Eigen's quaternion of R, read back through siteFromCam's conversion).
std::string formatPanoramaStations(const PanoramaStationsFile& file, const std::vector<std::string>& comments);

// The prior checks of the parser on a matrix: "" or the reason.
std::string checkPointingPrior(const Mat6& prior);

}  // namespace vtm::ground
