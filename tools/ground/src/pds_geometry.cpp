// The camera model and the rover pose of a PDS label (pds_image.hpp has the conventions).
#include <cmath>

#include "pds_fields.hpp"
#include "vtm/ground/pds_image.hpp"

namespace vtm::ground {
namespace {

using detail::PdsFields;

constexpr double kUnitTolerance = 1e-3;  // |A| and |q|: 6 printed digits are ~1e-6 off

void copy3(const std::vector<double>& from, double to[3]) {
    for (std::size_t i = 0; i < 3U; ++i) to[i] = from[i];
}

double norm3(const double v[3]) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

}  // namespace

Result<CameraModel> pdsCameraModel(const PdsLabel& label, std::int32_t width, std::int32_t height,
                                   const std::string& name) {
    const PdsFields f{label, name};
    const std::string group = detail::pdsCameraModelGroup(label);
    if (group.empty()) return Result<CameraModel>::failure(f.missing("GEOMETRIC_CAMERA_MODEL", "MODEL_TYPE"));
    const PdsStatement* type = label.find(group, "MODEL_TYPE");
    const std::string kind = pdsText(type->value);
    if (kind != "CAHV" && kind != "CAHVOR") {
        return Result<CameraModel>::failure(f.bad(*type, "is not read (CAHV and CAHVOR are)"));
    }
    const PdsStatement* frame = label.find(group, "REFERENCE_COORD_SYSTEM_NAME");
    if (frame != nullptr && pdsText(frame->value) != "ROVER_FRAME") {
        return Result<CameraModel>::failure(f.bad(*frame, "must be ROVER_FRAME (the frame the rover pose places)"));
    }
    if (width < 1 || height < 1 || width > 65535 || height > 65535) {
        return Result<CameraModel>::failure(name + ": PDS camera model: image size out of 1..65535");
    }
    CameraModel m;
    m.kind = kind == "CAHV" ? CameraModelKind::kCahv : CameraModelKind::kCahvor;
    m.width_px = static_cast<std::uint16_t>(width);
    m.height_px = static_cast<std::uint16_t>(height);
    double* const targets[6] = {m.c, m.a, m.h, m.v, m.o, m.r};
    const std::size_t components = kind == "CAHV" ? 4U : 6U;
    for (std::size_t k = 0; k < components; ++k) {
        std::vector<double> values;
        const std::string e = f.realsField(group, "MODEL_COMPONENT_" + std::to_string(k + 1U), 3U, values);
        if (!e.empty()) return Result<CameraModel>::failure(e);
        copy3(values, targets[k]);
    }
    const double a_norm = norm3(m.a);
    if (!(std::fabs(a_norm - 1.0) <= kUnitTolerance)) {
        return Result<CameraModel>::failure(f.bad(*label.find(group, "MODEL_COMPONENT_2"),
                                                  "(A) must be a unit vector within 1e-3"));
    }
    // Dividing A, H and V by one number leaves (P-C).H / (P-C).A and (P-C).V / (P-C).A as they were.
    for (std::size_t i = 0; i < 3U; ++i) {
        m.a[i] /= a_norm;
        m.h[i] /= a_norm;
        m.v[i] /= a_norm;
    }
    const Status valid = validateCameraModel(m);
    if (!valid.isOk()) {
        return Result<CameraModel>::failure(name + ": PDS camera model (" + kind + " in GROUP " + group +
                                            ") fails validation: " + valid.reason());
    }
    return Result<CameraModel>::success(m);
}

Result<RigidPose> pdsSiteFromRover(const PdsLabel& label, const std::string& name) {
    const PdsFields f{label, name};
    const std::string group = detail::pdsRoverFrameGroup(label);
    if (group.empty()) {
        return Result<RigidPose>::failure(name + ": PDS label: no group with COORDINATE_SYSTEM_NAME = ROVER_FRAME and "
                                                 "REFERENCE_COORD_SYSTEM_NAME = SITE_FRAME (the rover pose)");
    }
    std::vector<double> t, q;
    std::string e = f.realsField(group, "ORIGIN_OFFSET_VECTOR", 3U, t);
    if (e.empty()) e = f.realsField(group, "ORIGIN_ROTATION_QUATERNION", 4U, q);
    if (!e.empty()) return Result<RigidPose>::failure(e);
    const double q_norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (!(std::fabs(q_norm - 1.0) <= kUnitTolerance)) {
        return Result<RigidPose>::failure(
            f.bad(*label.find(group, "ORIGIN_ROTATION_QUATERNION"), "must be a unit quaternion within 1e-3"));
    }
    // (s, v1, v2, v3): Eigen's Quaternion(w, x, y, z), its rotation matrix the Hamilton one.
    RigidPose pose;
    pose.R = Quat(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
    pose.t_m = Vec3(t[0], t[1], t[2]);
    return Result<RigidPose>::success(pose);
}

}  // namespace vtm::ground
