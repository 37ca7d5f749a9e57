// OpenCV's stitching bundle adjusters on the PDS ties (pds_pointing_peer.hpp).
#include "pds_pointing_peer.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>

#include "vtm/core/rotation.hpp"

#if VTM_HAVE_OPENCV_STITCHING
#include <opencv2/core.hpp>
#include <opencv2/stitching/detail/motion_estimators.hpp>
#endif

namespace vtm::ground::test {

#if VTM_HAVE_OPENCV_STITCHING

bool openCvStitchingAvailable() { return true; }

namespace {

// The ideal pinhole of a CAHV(OR) frame: rover-from-camera axes (x = H', y = A x H', z = A),
// focal |H'| and principal point (hc, vc), px.
struct Pinhole {
    Mat3 rover_from_cam = Mat3::Identity();
    double f = 1.0, cx = 0.0, cy = 0.0;
};

Pinhole pinholeOf(const CameraModel& m) {
    const Vec3 a(m.a[0], m.a[1], m.a[2]), h(m.h[0], m.h[1], m.h[2]);
    const double hc = h.dot(a), vc = Vec3(m.v[0], m.v[1], m.v[2]).dot(a);
    const Vec3 hp = h - hc * a;
    Pinhole p;
    p.f = hp.norm();
    p.cx = hc;
    p.cy = vc;
    const Vec3 x = hp / p.f, z = a.normalized();
    p.rover_from_cam.col(0) = x;
    p.rover_from_cam.col(1) = z.cross(x);
    p.rover_from_cam.col(2) = z;
    return p;
}

// Site-from-camera rotation of the frame's ideal pinhole under the labels' pointing.
Mat3 siteFromPinhole(const PdsImage& f) { return f.site_from_rover.R * pinholeOf(f.camera_model).rover_from_cam; }

// Connected parts of the network (frames linked by a pair with ties); -1 for a frame in none.
std::vector<int> partsOf(std::size_t frames, const std::vector<PdsTiePair>& pairs) {
    std::vector<int> part(frames);
    for (std::size_t i = 0; i < frames; ++i) part[i] = static_cast<int>(i);
    for (bool changed = true; changed;) {
        changed = false;
        for (const PdsTiePair& p : pairs) {
            if (p.ties.empty()) continue;
            int& a = part[static_cast<std::size_t>(p.frame_a)];
            int& b = part[static_cast<std::size_t>(p.frame_b)];
            if (a != b) a = b = std::min(a, b), changed = true;
        }
    }
    std::vector<bool> linked(frames, false);
    for (const PdsTiePair& p : pairs) {
        if (p.ties.empty()) continue;
        linked[static_cast<std::size_t>(p.frame_a)] = linked[static_cast<std::size_t>(p.frame_b)] = true;
    }
    for (std::size_t i = 0; i < frames; ++i) part[i] = linked[i] ? part[i] : -1;
    return part;
}

// The rotation G that turns OpenCV's part onto the labels: the mean of the corrections
// log(G R_i L_i^T) is zero (R_i OpenCV's site-from-camera rotation, L_i the labels'), found by
// a few fixed-point steps from the identity (the Karcher mean).
Mat3 gaugeOntoLabels(const std::vector<Mat3>& cv, const std::vector<Mat3>& labels) {
    Mat3 g = Mat3::Identity();
    for (int iteration = 0; iteration < 20; ++iteration) {
        Vec3 mean = Vec3::Zero();
        for (std::size_t i = 0; i < cv.size(); ++i) mean += rotationLog(labels[i] * (g * cv[i]).transpose());
        g = rotationExp(mean / static_cast<double>(cv.size())) * g;
    }
    return g;
}

bool pinholePixel(const PdsImage& f, const Pinhole& p, const Vec2& pixel, cv::KeyPoint& out) {
    CameraRay ray;
    if (!backProjectPixel(f.camera_model, pixel, ray).isOk()) return false;
    const Vec3 d = p.rover_from_cam.transpose() * ray.direction;
    if (!(d.z() > 0.0)) return false;
    out = cv::KeyPoint(static_cast<float>(p.f * d.x() / d.z() + p.cx), static_cast<float>(p.f * d.y() / d.z() + p.cy), 1.0F);
    return true;
}

// One connected part: `members` are frame indices; returns OpenCV's site-from-camera rotations.
bool adjustPart(const std::vector<PdsImage>& frames, const std::vector<PdsTiePair>& pairs,
                const std::vector<std::size_t>& members, OpenCvAdjuster kind, std::vector<Mat3>& rotations,
                std::vector<double>& focal) {
    const std::size_t n = members.size();
    std::vector<int> local(frames.size(), -1);
    for (std::size_t i = 0; i < n; ++i) local[members[i]] = static_cast<int>(i);
    std::vector<cv::detail::ImageFeatures> features(n);
    std::vector<Pinhole> pin(n);
    for (std::size_t i = 0; i < n; ++i) {
        const PdsImage& f = frames[members[i]];
        features[i].img_idx = static_cast<int>(i);
        features[i].img_size = cv::Size(f.camera_model.width_px, f.camera_model.height_px);
        pin[i] = pinholeOf(f.camera_model);
    }
    std::vector<cv::detail::MatchesInfo> matches(n * n);
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = 0; j < n; ++j) {
            matches[i * n + j].src_img_idx = static_cast<int>(i);
            matches[i * n + j].dst_img_idx = static_cast<int>(j);
            matches[i * n + j].H = cv::Mat::eye(3, 3, CV_64F);
        }
    }
    for (const PdsTiePair& p : pairs) {
        const int ia = local[static_cast<std::size_t>(p.frame_a)], ib = local[static_cast<std::size_t>(p.frame_b)];
        if (ia < 0 || ib < 0) continue;
        const auto a = static_cast<std::size_t>(ia), b = static_cast<std::size_t>(ib);
        for (const PdsTie& t : p.ties) {
            cv::KeyPoint ka, kb;
            if (!pinholePixel(frames[members[a]], pin[a], t.pixel_a, ka) ||
                !pinholePixel(frames[members[b]], pin[b], t.pixel_b, kb)) {
                continue;
            }
            const int qa = static_cast<int>(features[a].keypoints.size());
            const int qb = static_cast<int>(features[b].keypoints.size());
            features[a].keypoints.push_back(ka);
            features[b].keypoints.push_back(kb);
            matches[a * n + b].matches.emplace_back(qa, qb, 0.0F);
            matches[b * n + a].matches.emplace_back(qb, qa, 0.0F);
        }
    }
    for (cv::detail::MatchesInfo& m : matches) {
        m.inliers_mask.assign(m.matches.size(), 1U);
        m.num_inliers = static_cast<int>(m.matches.size());
        m.confidence = m.num_inliers >= 6 ? 2.0 : 0.0;
    }
    std::vector<cv::detail::CameraParams> cameras(n);
    for (std::size_t i = 0; i < n; ++i) {
        cameras[i].focal = pin[i].f;
        cameras[i].ppx = pin[i].cx;
        cameras[i].ppy = pin[i].cy;
        cameras[i].aspect = 1.0;
        const Mat3 r = siteFromPinhole(frames[members[i]]);
        cv::Mat m(3, 3, CV_32F);
        for (int k = 0; k < 9; ++k) m.at<float>(k / 3, k % 3) = static_cast<float>(r(k / 3, k % 3));
        cameras[i].R = m;
    }
    cv::Ptr<cv::detail::BundleAdjusterBase> adjuster;
    if (kind == OpenCvAdjuster::kReproj) {
        adjuster = cv::makePtr<cv::detail::BundleAdjusterReproj>();
        adjuster->setRefinementMask(cv::Mat::zeros(3, 3, CV_8U));  // intrinsics held: rotations only
    } else {
        adjuster = cv::makePtr<cv::detail::BundleAdjusterRay>();
    }
    adjuster->setConfThresh(1.0);
    if (!(*adjuster)(features, matches, cameras)) return false;
    for (std::size_t i = 0; i < n; ++i) {
        cv::Mat r;
        cameras[i].R.convertTo(r, CV_64F);
        Mat3 m;
        for (int k = 0; k < 9; ++k) m(k / 3, k % 3) = r.at<double>(k / 3, k % 3);
        rotations.push_back(m);
        focal.push_back(cameras[i].focal);
    }
    return true;
}

}  // namespace

OpenCvPointing openCvPointing(const std::vector<PdsImage>& frames, const std::vector<PdsTiePair>& pairs,
                              OpenCvAdjuster kind) {
    OpenCvPointing out;
    out.correction_rad.assign(frames.size(), Vec3::Zero());
    out.focal_px.assign(frames.size(), 0.0);
    for (std::size_t i = 0; i < frames.size(); ++i) out.focal_px[i] = pinholeOf(frames[i].camera_model).f;
    const std::vector<int> part = partsOf(frames.size(), pairs);
    for (std::size_t root = 0; root < frames.size(); ++root) {
        if (part[root] != static_cast<int>(root)) continue;
        std::vector<std::size_t> members;
        for (std::size_t i = 0; i < frames.size(); ++i) {
            if (part[i] == static_cast<int>(root)) members.push_back(i);
        }
        std::vector<Mat3> cv, labels;
        std::vector<double> focal;
        if (!adjustPart(frames, pairs, members, kind, cv, focal)) {
            out.error = "OpenCV's adjuster refused the part of frame " + std::to_string(root + 1U);
            return out;
        }
        for (std::size_t i : members) labels.push_back(siteFromPinhole(frames[i]));
        const Mat3 g = gaugeOntoLabels(cv, labels);
        for (std::size_t k = 0; k < members.size(); ++k) {
            out.correction_rad[members[k]] = rotationLog(g * cv[k] * labels[k].transpose());
            out.focal_px[members[k]] = focal[k];
        }
    }
    out.ok = true;
    return out;
}

#else

bool openCvStitchingAvailable() { return false; }

OpenCvPointing openCvPointing(const std::vector<PdsImage>&, const std::vector<PdsTiePair>&, OpenCvAdjuster) {
    OpenCvPointing out;
    out.error = "built without OpenCV's stitching module";
    return out;
}

#endif

}  // namespace vtm::ground::test
