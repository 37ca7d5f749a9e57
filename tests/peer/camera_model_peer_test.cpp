// Peer check of the pinhole + Brown model against OpenCV (calib3d), the de-facto
// reference for the k1 k2 p1 p2 k3 convention: cv::projectPoints must give the same
// pixels (1e-9 px) and cv::undistortPoints (iterated to convergence) the same rays.
#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>

#include <cmath>
#include <cstdio>
#include <vector>

#include "vtm/core/camera_model.hpp"

namespace vtm {
namespace {

CameraModel brownNavcam() {
    CameraModel m = makePinhole(1024U, 1024U, 45.0);
    m.fy_px *= 0.998;
    m.cx_px += 3.25;
    m.cy_px -= 2.5;
    m.k1 = -0.2;
    m.k2 = 0.08;
    m.k3 = -0.01;
    m.p1 = 1.2e-3;
    m.p2 = -6e-4;
    return m;
}

cv::Mat cameraMatrix(const CameraModel& m) {
    return (cv::Mat_<double>(3, 3) << m.fx_px, 0.0, m.cx_px, 0.0, m.fy_px, m.cy_px, 0.0, 0.0, 1.0);
}
cv::Mat distortion(const CameraModel& m) { return (cv::Mat_<double>(1, 5) << m.k1, m.k2, m.p1, m.p2, m.k3); }

TEST(CameraModelPeer, BrownProjectionMatchesOpenCvProjectPoints) {
    const CameraModel m = brownNavcam();
    std::vector<cv::Point3d> points;
    for (int j = -12; j <= 12; ++j) {
        for (int i = -12; i <= 12; ++i) {
            const double z = 2.0 + 0.25 * (i + 12);
            points.emplace_back(0.55 * i / 12.0 * z, 0.55 * j / 12.0 * z, z);  // corners at ~38 deg
        }
    }
    std::vector<cv::Point2d> cv_pixels;
    cv::projectPoints(points, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), cameraMatrix(m), distortion(m), cv_pixels);
    double worst_px = 0.0;
    for (std::size_t k = 0; k < points.size(); ++k) {
        Vec2 px;
        ASSERT_TRUE(projectPoint(m, Vec3(points[k].x, points[k].y, points[k].z), px).isOk());
        worst_px = std::fmax(worst_px, std::hypot(px.x() - cv_pixels[k].x, px.y() - cv_pixels[k].y));
    }
    EXPECT_LT(worst_px, 1e-9);
    std::printf("[ figure ] %zu points: worst |VTM - cv::projectPoints| = %.3g px\n", points.size(), worst_px);
}

TEST(CameraModelPeer, BrownBackProjectionMatchesOpenCvUndistortPoints) {
    const CameraModel m = brownNavcam();
    std::vector<cv::Point2d> pixels;
    for (int j = 0; j <= 16; ++j) {
        for (int i = 0; i <= 16; ++i) {
            pixels.emplace_back(-0.5 + 1024.0 * i / 16.0, -0.5 + 1024.0 * j / 16.0);
        }
    }
    std::vector<cv::Point2d> normalised;
    cv::undistortPoints(pixels, normalised, cameraMatrix(m), distortion(m), cv::noArray(), cv::noArray(),
                        cv::TermCriteria(cv::TermCriteria::COUNT, 200, 0.0));
    double worst_rad = 0.0;
    for (std::size_t k = 0; k < pixels.size(); ++k) {
        CameraRay ray;
        ASSERT_TRUE(backProjectPixel(m, Vec2(pixels[k].x, pixels[k].y), ray).isOk());
        const Vec3 cv_dir = Vec3(normalised[k].x, normalised[k].y, 1.0).normalized();
        worst_rad = std::fmax(worst_rad, std::atan2(ray.direction.cross(cv_dir).norm(), ray.direction.dot(cv_dir)));
    }
    EXPECT_LT(worst_rad, 1e-12);
    std::printf("[ figure ] %zu pixels: worst angle VTM ray vs cv::undistortPoints = %.3g rad\n", pixels.size(),
                worst_rad);
}

}  // namespace
}  // namespace vtm
