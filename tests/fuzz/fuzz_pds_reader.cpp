// libFuzzer target (7): tools/ground's PDS3 reader (docs/pds.md), decodePdsImage on the
// input bytes as a file's contents, once requiring the camera model and the rover pose and
// once not. Properties: no crash, no sanitizer report, no assertion; an accepted image has
// LINES x LINE_SAMPLES samples, a camera model that validates and of that size, a rotation
// that is orthonormal; every refusal names the input and a reason.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "vtm/core/assert.hpp"
#include "vtm/ground/pds_image.hpp"

namespace {

void abortOnAssert(const vtm::AssertInfo&) { std::abort(); }

void check(const std::vector<unsigned char>& bytes, bool require) {
    vtm::ground::PdsReadOptions options;
    options.require_camera_model = require;
    options.require_rover_pose = require;
    const vtm::ground::Result<vtm::ground::PdsImage> r = vtm::ground::decodePdsImage(bytes, "fuzz.IMG", options);
    if (!r.ok) {
        if (r.error.rfind("fuzz.IMG: ", 0) != 0) std::abort();  // every refusal names the input
        return;
    }
    const vtm::ground::PdsImage& im = r.value;
    if (im.pixels.width != im.info.line_samples || im.pixels.height != im.info.lines ||
        im.pixels.pixels.size() != static_cast<std::size_t>(im.info.lines) * static_cast<std::size_t>(im.info.line_samples)) {
        std::abort();
    }
    if (require && (!im.has_camera_model || !im.has_rover_pose)) std::abort();
    if (im.has_camera_model) {
        if (!vtm::validateCameraModel(im.camera_model).isOk()) std::abort();
        if (im.camera_model.width_px != im.info.line_samples || im.camera_model.height_px != im.info.lines) std::abort();
    }
    if (im.has_rover_pose) {
        const vtm::Mat3 e = im.site_from_rover.R.transpose() * im.site_from_rover.R - vtm::Mat3::Identity();
        if (!(e.norm() < 1e-9) || !im.site_from_rover.t_m.allFinite()) std::abort();
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    (void)vtm::setAssertHook(abortOnAssert);
    const std::vector<unsigned char> bytes(data, data + size);
    check(bytes, true);
    check(bytes, false);
    return 0;
}
