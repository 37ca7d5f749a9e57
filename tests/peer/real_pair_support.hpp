// What the real-pair tests share (tests/peer: the Curiosity Navcam pair, the Strecha
// wide-baseline views): module workspaces over a vector, OpenCV SIFT matches found
// independently of the flight modules, the vertical disparity of matches after
// rectification, and the dense ML stereo of a rectified pair with its picture.
#pragma once

#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "vtm/core/arena.hpp"
#include "vtm/core/eigen.hpp"
#include "vtm/core/image.hpp"
#include "vtm/ground/disparity_colormap.hpp"
#include "vtm/rectify/rectifier.hpp"
#include "vtm/refine/pair_refiner.hpp"
#include "vtm/stereo/ml_stereo.hpp"
#include "vtm/stereo/speckle_filter.hpp"

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

// Matches a[i] <-> b[i] after rectification: the rectified difference a - b of each match
// that both sides rectify (x: the disparity, y: the vertical disparity).
inline std::vector<Vec2> rectifiedDifferences(const rectify::Rectifier& r, const std::vector<Vec2>& a,
                                              const std::vector<Vec2>& b) {
    std::vector<Vec2> diff;
    for (std::size_t i = 0; i < a.size(); ++i) {
        Vec2 ra, rb;
        if (r.rectifyPixel(rectify::Rectifier::Side::kA, a[i], ra).isOk() &&
            r.rectifyPixel(rectify::Rectifier::Side::kB, b[i], rb).isOk()) {
            diff.push_back(ra - rb);
        }
    }
    return diff;
}

// Vertical disparity y_a - y_b of matches after rectification.
inline RowStats rowStats(const rectify::Rectifier& r, const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
    std::vector<double> vd;
    for (const Vec2& d : rectifiedDifferences(r, a, b)) vd.push_back(d.y());
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

// The refiner's inlier matches: pixel in A and in B of each.
inline void inlierPixels(const refine::Result& r, std::vector<Vec2>& a, std::vector<Vec2>& b) {
    a.clear();
    b.clear();
    for (std::size_t i = 0; i < r.inliers.size(); ++i) {
        if (r.inliers[i] != 0U) {
            a.push_back(r.pixels_a[i]);
            b.push_back(r.pixels_b[i]);
        }
    }
}

// Disparities x_a - x_b of matches after rectification (those both sides rectify).
inline std::vector<double> matchDisparities(const rectify::Rectifier& r, const std::vector<Vec2>& a,
                                            const std::vector<Vec2>& b) {
    std::vector<double> d;
    for (const Vec2& diff : rectifiedDifferences(r, a, b)) d.push_back(diff.x());
    return d;
}

// The dense map of a rectified pair as the real-pair tests make it: both images remapped,
// the ML stereo with its left-right check and uniqueness (Config::conservative()) over
// [d_min, d_max], then the speckle filter as the rover mapper runs it (islands of at most
// 100 px, 3 px steps). content: A's rectified pixels that see the input image; mapped: those
// of them with a disparity (a pixel without content keeps none).
struct DenseMap {
    cv::Mat rect_a, rect_b;
    std::vector<std::int16_t> disp;  // 1/16 px (stereo::kDisparityScale), kNoDisparity where none
    std::int32_t d_min = 0, d_max = 0;
    std::int64_t content = 0, mapped = 0;
    [[nodiscard]] double share() const { return content > 0 ? static_cast<double>(mapped) / static_cast<double>(content) : 0.0; }
    // Disparity (px) at rectified pixel (x, y) of A; false where there is none or outside.
    [[nodiscard]] bool at(std::int32_t x, std::int32_t y, double& d_px) const {
        if (x < 0 || y < 0 || x >= rect_a.cols || y >= rect_a.rows) return false;
        const std::int16_t v = disp[static_cast<std::size_t>(y) * static_cast<std::size_t>(rect_a.cols) + static_cast<std::size_t>(x)];
        if (v == stereo::kNoDisparity) return false;
        d_px = static_cast<double>(v) / stereo::kDisparityScale;
        return true;
    }
};

// Fills `out` for the pair `r` was last computed for (`pair`: its rectified size); the
// first failing module's Status otherwise.
inline Status denseMap(const rectify::Rectifier& r, const rectify::RectifiedPair& pair, const cv::Mat& image_a,
                       const cv::Mat& image_b, std::int32_t d_min, std::int32_t d_max, DenseMap& out) {
    const std::int32_t w = pair.model_a.width_px, h = pair.model_a.height_px;
    out.rect_a = cv::Mat(h, w, CV_8UC1);
    out.rect_b = cv::Mat(h, w, CV_8UC1);
    VTM_RETURN_IF_ERROR(r.remap(rectify::Rectifier::Side::kA, greyView(image_a),
                                ImageView<std::uint8_t>(out.rect_a.ptr<std::uint8_t>(0), w, h)));
    VTM_RETURN_IF_ERROR(r.remap(rectify::Rectifier::Side::kB, greyView(image_b),
                                ImageView<std::uint8_t>(out.rect_b.ptr<std::uint8_t>(0), w, h)));
    stereo::Config sc = stereo::Config::conservative();
    sc.max_width = w;
    sc.max_height = h;
    sc.d_min = d_min;
    sc.d_max = d_max;
    out.d_min = d_min;
    out.d_max = d_max;
    Workspace sw(stereo::MlStereo::workspaceBytes(sc));
    stereo::MlStereo ml;
    VTM_RETURN_IF_ERROR(ml.init(sc, sw.arena));
    out.disp.assign(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), stereo::kNoDisparity);
    const stereo::DisparityOutput dout{ImageView<std::int16_t>(out.disp.data(), w, h), ImageView<float>(),
                                       ImageView<std::uint8_t>()};
    VTM_RETURN_IF_ERROR(ml.compute(greyView(out.rect_a), greyView(out.rect_b), dout));
    stereo::SpeckleConfig fc;
    fc.max_width = w;
    fc.max_height = h;
    fc.max_diff_px16 = 3 * stereo::kDisparityScale;
    Workspace fw(stereo::SpeckleFilter::workspaceBytes(fc));
    stereo::SpeckleFilter speckles;
    VTM_RETURN_IF_ERROR(speckles.init(fc, fw.arena));
    VTM_RETURN_IF_ERROR(speckles.apply(dout));
    out.content = out.mapped = 0;
    for (std::int32_t y = 0; y < h; ++y) {
        for (std::int32_t x = 0; x < w; ++x) {
            std::int16_t xq = 0, yq = 0;
            if (!r.tableEntry(rectify::Rectifier::Side::kA, x, y, xq, yq).isOk() || xq == rectify::kOutsideInput) {
                // no input behind the pixel: a disparity of the fill value means nothing
                out.disp[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)] =
                    stereo::kNoDisparity;
                continue;
            }
            ++out.content;
            double d = 0.0;
            out.mapped += out.at(x, y, d) ? 1 : 0;
        }
    }
    return Status::ok();
}

// The disparity picture of a dense map (ground::disparityColor from lo to hi px, black
// where there is none) written as a PNG.
inline bool writeDisparityPng(const std::string& path, const DenseMap& m, float lo_px, float hi_px) {
    cv::Mat colour(m.rect_a.rows, m.rect_a.cols, CV_8UC3, cv::Scalar(0, 0, 0));
    for (std::int32_t y = 0; y < m.rect_a.rows; ++y) {
        for (std::int32_t x = 0; x < m.rect_a.cols; ++x) {
            double d = 0.0;
            if (!m.at(x, y, d)) continue;
            const ground::Rgb c = ground::disparityColor(static_cast<float>(d), lo_px, hi_px);
            colour.at<cv::Vec3b>(y, x) = cv::Vec3b(c[2], c[1], c[0]);
        }
    }
    return cv::imwrite(path, colour);
}

}  // namespace vtm::test
