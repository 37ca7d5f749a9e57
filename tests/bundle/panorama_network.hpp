// A synthetic panorama network for the bundle adjustment tests: a stereo rig (0.42 m
// baseline) on a mast head 1.5 m above gently rolling ground, turned through `azimuths`
// pan positions in each of `tiers` tilts; ground points 2-20 m away seen by at least two
// images; true poses known, approximate poses drawn from a prior with correlated attitude
// and position (a mast turned about a wrong axis is rotated and displaced by the lever arm
// of the eye about the mast head), pixels with Gaussian noise and optional gross outliers.
// Only vtm::math and vtm::Random: the same network on every target (the determinism suite's
// section "bundle" builds one too).
#pragma once

#include <cstdint>
#include <vector>

#include "vtm/core/image_network.hpp"
#include "vtm/core/math.hpp"
#include "vtm/core/random.hpp"
#include "vtm/core/rotation.hpp"

namespace vtm::bundle::test {

struct NetworkSpec {
    int azimuths = 6;
    int tiers = 2;
    double hfov_deg = 70.0;
    std::uint16_t image_px = 512U;
    bool cahvor = false;            // CAHVOR with radial distortion instead of a pinhole
    int candidate_points = 450;     // ground points drawn; those seen twice are kept
    double pixel_sigma = 0.3;
    double outlier_fraction = 0.0;  // observations moved by outlier_px in a random direction
    double outlier_px = 20.0;
    double sigma_rotation_rad = 0.01;
    double sigma_position_m = 0.02;  // besides the lever arm's share
    bool left_eye_on_axis = false;   // the rig turns about the left eye's centre (no lever arm)
    std::uint64_t seed = 1U;
};

struct Network {
    std::vector<NetworkStation> truth;
    std::vector<NetworkStation> approx;  // what the adjustment is given
    std::vector<Vec3> points_m;          // true tie points
    std::vector<TieObservation> observations;
    std::vector<std::uint8_t> planted_outlier;  // per observation
};

inline double groundZ(double x, double y) { return 0.15 * math::sin(0.5 * x) * math::cos(0.4 * y); }

inline CameraModel rigModel(const NetworkSpec& spec) {
    CameraModel m = makePinhole(spec.image_px, spec.image_px, spec.hfov_deg);
    if (!spec.cahvor) {
        return m;
    }
    m = cahvFromPinhole(m);
    m.kind = CameraModelKind::kCahvor;
    m.o[0] = m.a[0];
    m.o[1] = m.a[1];
    m.o[2] = m.a[2];
    m.r[0] = 0.0;
    m.r[1] = -0.08;
    m.r[2] = 0.01;
    return m;
}

// site_from_cam of a camera looking at azimuth az (from north towards east) and depression el.
inline Mat3 lookRotation(double az, double el) {
    const Vec3 f(math::cos(el) * math::cos(az), math::cos(el) * math::sin(az), math::sin(el));
    const Vec3 r(-math::sin(az), math::cos(az), 0.0);
    Mat3 R;
    R.col(0) = r;
    R.col(1) = f.cross(r);
    R.col(2) = f;
    return R;
}

// Prior covariance of (dtheta, dt) for an eye with lever arm l about the mast head:
// dt = dtheta x l + e, e ~ N(0, sigma_p^2 I).
inline Mat6 priorCovariance(const Vec3& lever, double sigma_r, double sigma_p) {
    Mat6 g = Mat6::Zero();  // (dtheta, dt) = g (n1, n2)
    g.topLeftCorner<3, 3>() = sigma_r * Mat3::Identity();
    g.bottomLeftCorner<3, 3>() = -sigma_r * skew(lever);
    g.bottomRightCorner<3, 3>() = sigma_p * Mat3::Identity();
    return g * g.transpose();
}

inline Network makeNetwork(const NetworkSpec& spec) {
    Network net;
    Random rng(spec.seed);
    const Vec3 head(0.0, 0.0, -1.5);
    const double pi = 3.14159265358979323846;
    for (int tier = 0; tier < spec.tiers; ++tier) {
        for (int a = 0; a < spec.azimuths; ++a) {
            NetworkStation s;
            s.rig.model_a = rigModel(spec);
            s.rig.model_b = s.rig.model_a;
            s.rig.b_from_a.t_m = Vec3(-0.42, 0.0, 0.0);
            const double az = 2.0 * pi * (a + 0.5 * tier) / spec.azimuths;
            const double el = (15.0 + 28.0 * tier) * pi / 180.0;
            s.site_from_a.R = lookRotation(az, el);
            const Vec3 lever = spec.left_eye_on_axis ? Vec3::Zero() : Vec3(s.site_from_a.R * Vec3(-0.21, 0.0, 0.1));
            s.site_from_a.t_m = head + lever;
            s.prior_covariance = priorCovariance(lever, spec.sigma_rotation_rad, spec.sigma_position_m);
            net.truth.push_back(s);
            // The approximate pose: truth = (Exp(dtheta) R_approx, t_approx + dt).
            Vec3 n1;
            Vec3 n2;
            for (int k = 0; k < 3; ++k) n1(k) = rng.normal();
            for (int k = 0; k < 3; ++k) n2(k) = rng.normal();
            const Vec3 dtheta = spec.sigma_rotation_rad * n1;
            const Vec3 dt = dtheta.cross(lever) + spec.sigma_position_m * n2;
            NetworkStation approx = s;
            approx.site_from_a.R = rotationExp(-dtheta) * s.site_from_a.R;
            approx.site_from_a.t_m = s.site_from_a.t_m - dt;
            net.approx.push_back(approx);
        }
    }
    for (int i = 0; i < spec.candidate_points; ++i) {
        const double az = 2.0 * pi * rng.uniform01();
        const double range = 2.0 + 18.0 * rng.uniform01();
        const double x = range * math::cos(az);
        const double y = range * math::sin(az);
        const Vec3 X(x, y, groundZ(x, y));
        std::vector<TieObservation> seen;
        for (std::size_t s = 0; s < net.truth.size(); ++s) {
            for (int eye = 0; eye < 2; ++eye) {
                const RigidPose pose = siteFromEye(net.truth[s], static_cast<Eye>(eye));
                Vec2 px;
                const CameraModel& m = modelOfEye(net.truth[s], static_cast<Eye>(eye));
                if (!projectPoint(m, pose.R.transpose() * (X - pose.t_m), px).isOk() || px.x() < 2.0 || px.y() < 2.0 ||
                    px.x() > m.width_px - 3.0 || px.y() > m.height_px - 3.0) {
                    continue;
                }
                TieObservation o;
                o.image.station = static_cast<std::uint16_t>(s);
                o.image.eye = static_cast<Eye>(eye);
                o.pixel_px = px;
                seen.push_back(o);
            }
        }
        if (seen.size() < 2U) {
            continue;
        }
        const auto id = static_cast<std::uint32_t>(net.points_m.size());
        net.points_m.push_back(X);
        for (TieObservation& o : seen) {
            o.point = id;
            const double nx = rng.normal(0.0, spec.pixel_sigma);
            const double ny = rng.normal(0.0, spec.pixel_sigma);
            o.pixel_px += Vec2(nx, ny);
            const bool outlier = rng.uniform01() < spec.outlier_fraction;
            if (outlier) {
                const double phi = 2.0 * pi * rng.uniform01();
                o.pixel_px += spec.outlier_px * Vec2(math::cos(phi), math::sin(phi));
            }
            net.observations.push_back(o);
            net.planted_outlier.push_back(outlier ? 1U : 0U);
        }
    }
    return net;
}

// Error of an adjusted pose against the truth as the prior's perturbation:
// R_true = Exp(e_theta) R_adjusted, t_true = t_adjusted + e_t.
inline Vec6 poseError(const RigidPose& adjusted, const RigidPose& truth) {
    Vec6 e;
    e.head<3>() = rotationLog(truth.R * adjusted.R.transpose());
    e.tail<3>() = truth.t_m - adjusted.t_m;
    return e;
}

}  // namespace vtm::bundle::test
