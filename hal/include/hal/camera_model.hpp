// Camera model data as the HAL delivers it with every camera: the parameters only,
// in a fixed layout. fsw/rectify interprets them (projection, back-projection,
// linearisation). Units: pixels for image quantities, metres for C, unit vectors for
// A and O, CAHV(OR) as in Yakimovsky & Cunningham 1978 and Gennery 2001.
#pragma once

#include <cstdint>

namespace vtm::hal {

enum class CameraModelKind : std::uint8_t {
    kNone = 0,
    kPinholeBrown = 1,  // fx, fy, cx, cy, k1..k3 radial, p1 p2 tangential
    kCahv = 2,          // C, A, H, V
    kCahvor = 3,        // C, A, H, V, O, R
};

struct CameraModel {
    CameraModelKind kind = CameraModelKind::kNone;
    std::uint16_t width_px = 0U;
    std::uint16_t height_px = 0U;
    // Pinhole + Brown distortion (kPinholeBrown), pixels.
    double fx_px = 0.0, fy_px = 0.0, cx_px = 0.0, cy_px = 0.0;
    double k1 = 0.0, k2 = 0.0, k3 = 0.0, p1 = 0.0, p2 = 0.0;
    // CAHV / CAHVOR vectors in the camera's mounting frame (C in metres).
    double c[3] = {0.0, 0.0, 0.0};
    double a[3] = {0.0, 0.0, 0.0};
    double h[3] = {0.0, 0.0, 0.0};
    double v[3] = {0.0, 0.0, 0.0};
    double o[3] = {0.0, 0.0, 0.0};
    double r[3] = {0.0, 0.0, 0.0};
};

}  // namespace vtm::hal
