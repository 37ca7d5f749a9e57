// The peer of the PDS pointing adjustment: OpenCV's stitching bundle adjusters for cameras
// that only rotate (cv::detail::BundleAdjusterReproj with its intrinsics held, and
// cv::detail::BundleAdjusterRay, which also refines each camera's focal length), on the
// same ties. Host test code only (docs/pds.md "Pointing adjustment").
#pragma once

#include <string>
#include <vector>

#include "vtm/ground/pds_pointing.hpp"

namespace vtm::ground::test {

enum class OpenCvAdjuster { kReproj, kRay };

struct OpenCvPointing {
    bool ok = false;
    std::string error;                  // why not (OpenCV absent, an adjuster refused)
    std::vector<Vec3> correction_rad;   // per frame, the convention of PdsPointingResult
    std::vector<double> focal_px;       // per frame after adjustment (the Ray adjuster moves it)
};

// True when the test was built with OpenCV's stitching module.
bool openCvStitchingAvailable();

// Each tie's pixels go to an ideal pinhole camera per frame (the ray of the CAHVOR model, in
// axes A, H', V' with f = |H'| and the principal point (hc, vc)); each connected part of the
// network is adjusted on its own from the labels' rotations (OpenCV needs one connected
// graph), and its result turned as a whole onto the labels' rotations (the rotation that
// best fits the labels: OpenCV's gauge is one camera of each part), so the corrections are
// comparable with the module's.
OpenCvPointing openCvPointing(const std::vector<PdsImage>& frames, const std::vector<PdsTiePair>& pairs,
                              OpenCvAdjuster kind);

}  // namespace vtm::ground::test
