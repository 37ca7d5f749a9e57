// libFuzzer target (3): vtm::parseCameraModel, the text form of camera models
// (fsw/core). A model it accepts must also pass validateCameraModel and survive a
// projection / back-projection of the image centre. Properties: no crash, no
// sanitizer report, no assertion.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "vtm/core/assert.hpp"
#include "vtm/core/camera_model.hpp"

namespace {
void abortOnAssert(const vtm::AssertInfo&) { std::abort(); }
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    (void)vtm::setAssertHook(abortOnAssert);
    vtm::CameraModel model;
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    if (!vtm::parseCameraModel(text, model).isOk()) {
        return 0;
    }
    if (!vtm::validateCameraModel(model).isOk()) {
        std::abort();  // parseCameraModel promises a validated model
    }
    vtm::CameraRay ray;
    const vtm::Vec2 centre(0.5 * (model.width_px - 1), 0.5 * (model.height_px - 1));
    if (vtm::backProjectPixel(model, centre, ray).isOk()) {
        vtm::Vec2 pixel;
        (void)vtm::projectPoint(model, ray.origin_m + 10.0 * ray.direction, pixel);
    }
    return 0;
}
