// The rendered panorama of the tie-point tests (3 stations, 256 x 256), built once per
// process, with the true poses and the left images' true ranges.
#pragma once

#include <cstdint>
#include <vector>

#include "panorama_scene.hpp"
#include "vtm/tiepoints/tiepoints.hpp"

namespace vtm::tiepoints::test {

constexpr std::int32_t kStations = 3;

struct Scene {
    vtm::test::PanoramaSpec spec{};
    CameraModel model{};
    RigidPose left[kStations];
    RigidPose right[kStations];
    NetworkStation stations[kStations];
    StationImages images[kStations];
    std::vector<std::uint8_t> pixels[2 * kStations];
    std::vector<float> range[kStations];  // left images' true range
    bool ok = false;
};

const Scene& scene();

// The tests' configuration for 256 x 256 images.
Config sceneConfig();

// Bilinear true range of a left image at a pixel; false at the border, sky or a depth edge
// (the four neighbours differ by more than 3 %).
bool trueRange(const Scene& s, std::int32_t station, const Vec2& pixel, double& range_m);

// The true ground point of a left-image pixel.
bool trueGround(const Scene& s, std::int32_t station, const Vec2& pixel, Vec3& site_m);

}  // namespace vtm::tiepoints::test
