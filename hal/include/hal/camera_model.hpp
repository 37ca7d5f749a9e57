// Camera model data as the HAL delivers it with every camera: the one definition in
// fsw/core (vtm/core/camera_model.hpp: parameters, projection, back-projection,
// validation, text form), named in the hal namespace for the drivers' interfaces.
#pragma once

#include "vtm/core/camera_model.hpp"

namespace vtm::hal {

using CameraModel = ::vtm::CameraModel;
using CameraModelKind = ::vtm::CameraModelKind;

}  // namespace vtm::hal
