// Camera models as text files (the form vtm::parseCameraModel reads, docs/camera-models.md):
// the ground side writes them (vtm-sim render, calibration import) and reads them back.
#pragma once

#include <string>

#include "vtm/core/camera_model.hpp"
#include "vtm/ground/image.hpp"

namespace vtm::ground {

// The text form of a model: header, kind, size, then the kind's fields in the documented
// order, every number with 17 significant digits ("%.17g"), so parseCameraModel gives
// back the same bits. The model is written as it is (not validated).
std::string formatCameraModel(const CameraModel& model);

// Reads and parses a model file (vtm::parseCameraModel: validated). On failure `out` is
// unchanged and the error names the file, the line and the field, e.g.
// "left.cmod: line 9: camera model text: H must be three finite numbers".
Outcome readCameraModelFile(const std::string& path, CameraModel& out);
Outcome writeCameraModelFile(const std::string& path, const CameraModel& model);

}  // namespace vtm::ground
