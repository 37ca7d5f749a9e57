// The OpenCV peer of the traverse-and-descent evaluation (fusion_peer.hpp).
#include "fusion_peer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>

#if defined(VTM_HAVE_OPENCV_SURFACE_MATCHING)
#include <opencv2/core.hpp>
#include <opencv2/surface_matching.hpp>
#include <opencv2/surface_matching/ppf_helpers.hpp>
#endif

namespace vtm::traverse {
namespace {
RigidPose compose(const RigidPose& a, const RigidPose& b) {
    RigidPose p;
    p.R = a.R * b.R;
    p.t_m = a.R * b.t_m + a.t_m;
    return p;
}
double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

#if defined(VTM_HAVE_OPENCV_SURFACE_MATCHING)
namespace {
cv::Mat withNormals(const std::vector<Vec3>& pts) {  // as tests/icp/icp_peer_evaluation.cpp
    cv::Mat pc(static_cast<int>(pts.size()), 3, CV_32F);
    for (int i = 0; i < pc.rows; ++i) {
        for (int a = 0; a < 3; ++a) pc.at<float>(i, a) = static_cast<float>(pts[static_cast<std::size_t>(i)](a));
    }
    cv::Mat out;
    cv::ppf_match_3d::computeNormalsPC3d(pc, out, 12, true, cv::Vec3f(0.0F, 0.0F, -1000.0F));
    return out;
}
}  // namespace
#endif

namespace {
// Every n/m-th point (the module's own subsample rule, index floor(i n / m)), moved by `pose`.
std::vector<Vec3> subsample(const std::vector<Vec3>& pts, std::size_t m, const RigidPose& pose) {
    const std::size_t n = pts.size();
    m = std::min(n, m);
    std::vector<Vec3> out;
    for (std::size_t i = 0; i < m; ++i) out.push_back(pose.R * pts[i * n / m] + pose.t_m);
    return out;
}
}  // namespace

void comparePeer(const Truth& truth, const icp::IcpConfig& config, const std::vector<app::AddResult>& integrated) {
#if !defined(VTM_HAVE_OPENCV_SURFACE_MATCHING)
    (void)truth; (void)config; (void)integrated;
    std::printf("\nOpenCV peer skipped: OpenCV surface_matching (libopencv-contrib-dev) not found at configure time\n");
#else
    std::vector<std::byte> pool(icp::PointToPlaneIcp::workspaceBytes(config));
    Arena arena(pool.data(), pool.size());
    auto module = std::make_unique<icp::PointToPlaneIcp>();
    if (!module->init(config, arena).isOk()) {
        ADD_FAILURE() << "icp init";
        return;
    }
    const std::size_t cap = static_cast<std::size_t>(config.max_data_points);
    std::printf("\nSame clouds, same guess: stop k (%zu points at most, evenly; guess its odometry) against stop k-1 at its "
                "true pose (as many); the descent map (identity guess) against every stop at its true pose (%zu each). "
                "Rotation deg / translation at the centroid mm / ms\n"
                "| model | integrator (its map) | fsw/icp on these clouds | OpenCV ppf_match_3d::ICP | better here |\n"
                "|---|---|---|---|---|\n", cap, cap / 8);
    int wins_module = 0, wins_opencv = 0;
    for (std::size_t k = 1; k <= truth.stops->size(); ++k) {
        std::vector<Vec3> scene;
        RigidPose guess;
        if (truth.isDescent(k)) {
            for (std::size_t j = 0; j < truth.stops->size(); ++j) {
                const std::vector<Vec3> part = subsample((*truth.stops)[j].points, cap / 8, (*truth.stops)[j].truth);
                scene.insert(scene.end(), part.begin(), part.end());
            }
        } else {
            scene = subsample((*truth.stops)[k - 1].points, cap, (*truth.stops)[k - 1].truth);
            guess = (*truth.stops)[k].odometry;
        }
        const std::vector<Vec3> data = subsample(truth.modelPoints(k), cap, RigidPose{});
        const std::vector<Vec3> moved = subsample(data, cap, guess);
        auto t0 = std::chrono::steady_clock::now();
        icp::IcpResult r;
        const Status st = module->setModel(Span<const Vec3>(scene.data(), scene.size())).isOk()
                              ? module->registerData(Span<const Vec3>(data.data(), data.size()), guess, r)
                              : Status(StatusCode::kDegenerate, "setModel");
        const double module_ms = msSince(t0);
        const PoseError me = poseError(truth, k, r.model_from_data);
        t0 = std::chrono::steady_clock::now();
        cv::ppf_match_3d::ICP cv_icp;  // its defaults, as the ICP peer evaluation
        double residual = 0.0;
        cv::Matx44d pose;
        const int rc = cv_icp.registerModelToScene(withNormals(moved), withNormals(scene), residual, pose);
        const double cv_ms = msSince(t0);
        RigidPose delta;
        for (int a = 0; a < 3; ++a) {
            for (int b = 0; b < 3; ++b) delta.R(a, b) = pose(a, b);
            delta.t_m(a) = pose(a, 3);
        }
        const PoseError ce = poseError(truth, k, compose(delta, guess));
        const PoseError ie = poseError(truth, k, integrated[k].map_from_model);
        const bool module_better = me.rotation_deg / kRotationTarget_deg + me.translation_percent / kTranslationTarget_percent <
                                   ce.rotation_deg / kRotationTarget_deg + ce.translation_percent / kTranslationTarget_percent;
        (module_better ? wins_module : wins_opencv) += 1;
        const std::string name = truth.isDescent(k) ? "descent" : "stop " + std::to_string(k);
        const std::string refused = st.isOk() ? "" : std::string(" (refused: ") + st.reason() + ", " + std::to_string(st.detail()) + ")";
        std::printf("| %s | %.4f / %.1f | %.4f / %.1f / %.0f%s | %.4f / %.1f / %.0f%s | %s |\n", name.c_str(),
                    ie.rotation_deg, 1000.0 * ie.translation_m, me.rotation_deg, 1000.0 * me.translation_m, module_ms,
                    refused.c_str(), ce.rotation_deg, 1000.0 * ce.translation_m, cv_ms,
                    rc == 0 ? "" : " (failed)", module_better ? "fsw/icp" : "OpenCV");
    }
    std::printf("who wins (rotation / 0.05 deg + translation / 1 %% of the step, lower is better): fsw/icp %d, OpenCV %d\n",
                wins_module, wins_opencv);
#endif
}


}  // namespace vtm::traverse
