// What the real-pair tests share (tests/peer: the Curiosity Navcam pair, the Strecha
// wide-baseline views): module workspaces over a vector, OpenCV SIFT matches found
// independently of the flight modules, and the vertical disparity of matches after
// rectification.
#pragma once

#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "vtm/core/arena.hpp"
#include "vtm/core/eigen.hpp"
#include "vtm/core/image.hpp"
#include "vtm/rectify/rectifier.hpp"

namespace vtm::test {

// Storage for a module's workspace: the arena over a vector sized by workspaceBytes.
struct Workspace {
    explicit Workspace(std::size_t bytes) : pool(bytes), arena(pool.data(), pool.size()) {}
    std::vector<std::byte> pool;
    Arena arena;
};

inline ImageView<const std::uint8_t> greyView(const cv::Mat& m) {
    return ImageView<const std::uint8_t>(m.ptr<std::uint8_t>(0), m.cols, m.rows);
}

struct RowStats {
    std::size_t count = 0;
    double rms_px = 0.0;      // of |vd| <= 2 px (the rest: wrong matches)
    double within1 = 0.0;     // share of all with |vd| <= 1 px
    double median_abs = 0.0;  // of all
};

// Vertical disparity y_a - y_b of matches after rectification.
inline RowStats rowStats(const rectify::Rectifier& r, const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
    std::vector<double> vd;
    for (std::size_t i = 0; i < a.size(); ++i) {
        Vec2 ra, rb;
        if (r.rectifyPixel(rectify::Rectifier::Side::kA, a[i], ra).isOk() &&
            r.rectifyPixel(rectify::Rectifier::Side::kB, b[i], rb).isOk()) {
            vd.push_back(ra.y() - rb.y());
        }
    }
    RowStats s;
    s.count = vd.size();
    if (vd.empty()) return s;
    double sum2 = 0.0;
    std::size_t n2 = 0, n1 = 0;
    std::vector<double> abs_vd;
    for (double v : vd) {
        abs_vd.push_back(std::fabs(v));
        if (std::fabs(v) <= 2.0) { sum2 += v * v; ++n2; }
        if (std::fabs(v) <= 1.0) ++n1;
    }
    std::nth_element(abs_vd.begin(), abs_vd.begin() + static_cast<std::ptrdiff_t>(abs_vd.size() / 2), abs_vd.end());
    s.median_abs = abs_vd[abs_vd.size() / 2];
    s.rms_px = n2 > 0 ? std::sqrt(sum2 / static_cast<double>(n2)) : 0.0;
    s.within1 = static_cast<double>(n1) / static_cast<double>(vd.size());
    return s;
}

// SIFT matches of the two images (ratio test 0.75, mutual), found without the refinement.
inline void siftMatches(const cv::Mat& left, const cv::Mat& right, std::vector<Vec2>& a, std::vector<Vec2>& b) {
    cv::Ptr<cv::SIFT> sift = cv::SIFT::create(4000);
    std::vector<cv::KeyPoint> ka, kb;
    cv::Mat da, db;
    sift->detectAndCompute(left, cv::noArray(), ka, da);
    sift->detectAndCompute(right, cv::noArray(), kb, db);
    cv::BFMatcher bf(cv::NORM_L2);
    std::vector<std::vector<cv::DMatch>> ab, ba;
    bf.knnMatch(da, db, ab, 2);
    bf.knnMatch(db, da, ba, 1);
    for (const auto& m : ab) {
        if (m.size() < 2 || m[0].distance > 0.75F * m[1].distance) continue;
        const auto& back = ba[static_cast<std::size_t>(m[0].trainIdx)];
        if (back.empty() || back[0].trainIdx != m[0].queryIdx) continue;
        const cv::Point2f pa = ka[static_cast<std::size_t>(m[0].queryIdx)].pt;
        const cv::Point2f pb = kb[static_cast<std::size_t>(m[0].trainIdx)].pt;
        a.emplace_back(pa.x, pa.y);
        b.emplace_back(pb.x, pb.y);
    }
}

}  // namespace vtm::test
