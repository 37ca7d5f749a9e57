// Peer dense-stereo matchers for tests and benchmarks (tools/peer, host only; OpenCV is
// allowed under tests/, tools/peer and tools/bench, never in fsw/, hal/ or sim/).
//
// Every matcher takes a rectified 8-bit grey pair (left = reference; a left pixel
// (x, y) with disparity d sees the right pixel (x - d, y)) and returns a CV_32FC1
// disparity image of the left image's size, in pixels, with +infinity where the
// matcher gives no disparity ("no match"). Search range: d in [0, numDisparities - 1].
//
// The parameters are those of the peer table in shared/data/middlebury/README.md, so
// that a test can reproduce that table in the same run as the VTM matcher:
//   StereoBM          blockSize 9, preFilterCap 31, textureThreshold 10,
//                     uniquenessRatio 15, speckle window 100 / range 32, disp12MaxDiff 1
//   StereoSGBM 3-way  blockSize 5, P1 = 8*bs^2, P2 = 32*bs^2, uniquenessRatio 10,
//                     preFilterCap 63, speckle 100 / 32, disp12MaxDiff 1
//   ZNCC 7x7 WTA      our own plain zero-mean normalised cross-correlation, winner
//                     takes all, integer disparities (see ZnccOptions)
// OpenCV runs with one thread: the OpenCV functions below call cv::setNumThreads(1)
// (a process-wide setting).
#pragma once

#include <cstdint>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "vtm/core/image.hpp"

namespace vtm::peer {

// Bridges to VTM image views (and so to vtm::ground::Image via its view()):
// a CV_8UC1 header over a grey view, without copying (valid while the view's pixels are);
[[nodiscard]] cv::Mat asMat(const ImageView<const std::uint8_t>& grey);
// a CV_32FC1 disparity (pixels, +inf = no match) copied into a float view of its size
// (throws std::invalid_argument when the sizes differ).
void copyDisparity(const cv::Mat& disparity_px, const ImageView<float>& out);

// numDisparities for a ground-truth maximum disparity (pixels): rounded up to a
// multiple of 16 (OpenCV's requirement), at least 16.
[[nodiscard]] int numDisparitiesFor(double maxDisparityPx);

// The configured OpenCV matchers (README parameters; minDisparity 0). Exposed so that
// benchmarks time exactly the matcher the tests evaluate.
[[nodiscard]] cv::Ptr<cv::StereoBM> makeStereoBm(int numDisparities);
[[nodiscard]] cv::Ptr<cv::StereoSGBM> makeStereoSgbm3Way(int numDisparities);

// OpenCV's CV_16S output (disparity * 16, values below minDisparity * 16 = invalid,
// OpenCV writes (minDisparity - 1) * 16) as CV_32F pixels with +inf = no match.
[[nodiscard]] cv::Mat fixedPointToFloat(const cv::Mat& disparity16, int minDisparity = 0);

// (a) StereoBM and (b) StereoSGBM MODE_SGBM_3WAY with the README parameters.
// left, right: CV_8UC1, same size. numDisparities: multiple of 16.
// OpenCV leaves the leftmost minDisparity + numDisparities - 1 (+ half a block)
// columns without disparity (+inf here).
[[nodiscard]] cv::Mat stereoBm(const cv::Mat& left, const cv::Mat& right, int numDisparities);
[[nodiscard]] cv::Mat stereoSgbm3Way(const cv::Mat& left, const cv::Mat& right, int numDisparities);

// (c) Plain ZNCC winner-take-all.
//   score(x, y, d) = sum((L - mean L)(R - mean R)) / sqrt(sum (L - mean L)^2 * sum (R - mean R)^2)
//   over the `window` x `window` square centred on left (x, y) and right (x - d, y).
// Candidates: d in [0, numDisparities - 1] with a non-flat (non-zero variance) window
// on both sides, and, by border rule:
//   kZeroPadding (default; reproduces the README's figures): pixels outside the images
//     are 0; every left pixel is matched; candidates need x - d >= 0 (the right window
//     centre inside the right image), so column x searches d <= x.
//   kInsideOnly: no padding; a pixel whose left window leaves the image (the r-pixel
//     frame, r = window / 2) has no match; candidates need x - d - r >= 0 (the whole
//     right window inside the right image).
// A pixel without a candidate has no match (+inf). Winner: the largest score; ties go
// to the smaller d. Window sums are exact integers (sums of 8-bit values and
// products); only the final ratio is floating point. Integer disparities by default.
enum class ZnccBorder { kZeroPadding, kInsideOnly };
struct ZnccOptions {
    int window = 7;                              // odd, >= 3
    ZnccBorder border = ZnccBorder::kZeroPadding;
    bool subpixel = false;  // false: integer disparities (the README's figures);
                            // true: parabola through the scores at d-1, d, d+1
};
[[nodiscard]] cv::Mat znccWta(const cv::Mat& left, const cv::Mat& right, int numDisparities,
                              const ZnccOptions& options = ZnccOptions{});

}  // namespace vtm::peer
