#include "vtm/ground/camera_model_io.hpp"
#include "vtm/ground/number_text.hpp"

#include <cstdio>
#include <string_view>

#include "file_bytes.hpp"

namespace vtm::ground {
namespace {

// 17 significant digits identify every double; glibc's printf and strtod are both
// correctly rounded, so the round trip is exact (also for -0, subnormals, extremes).
void scalar(std::string& out, const char* key, double value) { out += std::string(key) + " " + exactNumber(value) + "\n"; }

void vector3(std::string& out, const char* key, const double (&v)[3]) {
    out += std::string(key) + " " + exactNumber(v[0]) + " " + exactNumber(v[1]) + " " + exactNumber(v[2]) + "\n";
}

const char* kindName(CameraModelKind kind) {
    switch (kind) {
        case CameraModelKind::kPinholeBrown:
            return "pinhole";
        case CameraModelKind::kCahv:
            return "cahv";
        case CameraModelKind::kCahvor:
            return "cahvor";
        case CameraModelKind::kNone:
            break;
    }
    return "none";  // parseCameraModel refuses it, as it should
}

}  // namespace

std::string formatCameraModel(const CameraModel& m) {
    std::string out = "vtm_camera_model 1\n";
    out += std::string("kind ") + kindName(m.kind) + "\n";
    out += "width_px " + std::to_string(m.width_px) + "\n";
    out += "height_px " + std::to_string(m.height_px) + "\n";
    if (m.kind == CameraModelKind::kPinholeBrown) {
        scalar(out, "fx_px", m.fx_px);
        scalar(out, "fy_px", m.fy_px);
        scalar(out, "cx_px", m.cx_px);
        scalar(out, "cy_px", m.cy_px);
        scalar(out, "k1", m.k1);
        scalar(out, "k2", m.k2);
        scalar(out, "k3", m.k3);
        scalar(out, "p1", m.p1);
        scalar(out, "p2", m.p2);
        return out;
    }
    vector3(out, "C", m.c);
    vector3(out, "A", m.a);
    vector3(out, "H", m.h);
    vector3(out, "V", m.v);
    if (m.kind == CameraModelKind::kCahvor) {
        vector3(out, "O", m.o);
        vector3(out, "R", m.r);
    }
    return out;
}

Outcome readCameraModelFile(const std::string& path, CameraModel& out) {
    const Result<detail::Bytes> bytes = detail::readFileBytes(path);
    if (!bytes.ok) {
        return Outcome::failure(bytes.error);
    }
    const std::string_view text(reinterpret_cast<const char*>(bytes.value.data()), bytes.value.size());
    CameraModel parsed;
    const Status s = parseCameraModel(text, parsed);
    if (!s.isOk()) {
        const std::string where = s.detail() > 0 ? ": line " + std::to_string(s.detail()) : std::string();
        return Outcome::failure(path + where + ": " + s.reason());
    }
    out = parsed;
    return Outcome::success();
}

Outcome writeCameraModelFile(const std::string& path, const CameraModel& model) {
    const std::string text = formatCameraModel(model);
    return detail::writeFileBytes(path, detail::Bytes(text.begin(), text.end()));
}

}  // namespace vtm::ground
