// Peer matchers: OpenCV StereoBM / StereoSGBM with the README parameters, and a plain
// ZNCC winner-take-all. See include/vtm/peer/peer_stereo.hpp.
#include "vtm/peer/peer_stereo.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

#include <opencv2/core.hpp>

namespace vtm::peer {
namespace {

constexpr float kNoMatch = std::numeric_limits<float>::infinity();

void checkPair(const cv::Mat& left, const cv::Mat& right, int numDisparities, bool multipleOf16) {
    if (left.empty() || left.type() != CV_8UC1 || right.type() != CV_8UC1 || left.size() != right.size()) {
        throw std::invalid_argument("peer stereo: left and right must be CV_8UC1 of the same size");
    }
    if (numDisparities < 1 || (multipleOf16 && numDisparities % 16 != 0)) {
        throw std::invalid_argument("peer stereo: numDisparities must be positive (and a multiple of 16 for OpenCV)");
    }
}

// Box sums over a (2r+1)^2 window of an int64 image, for every pixel whose window lies
// inside the image (others: 0). Separable: column sums, then a running row sum.
void boxSums(const std::vector<std::int64_t>& src, int width, int height, int r,
             std::vector<std::int64_t>& colSums, std::vector<std::int64_t>& out) {
    colSums.assign(src.size(), 0);
    out.assign(src.size(), 0);
    const int n = 2 * r + 1;
    for (int x = 0; x < width; ++x) {
        std::int64_t s = 0;
        for (int y = 0; y < height; ++y) {
            s += src[static_cast<std::size_t>(y) * width + x];
            if (y >= n) {
                s -= src[static_cast<std::size_t>(y - n) * width + x];
            }
            if (y >= n - 1) {
                colSums[static_cast<std::size_t>(y - r) * width + x] = s;
            }
        }
    }
    for (int y = r; y < height - r; ++y) {
        const std::int64_t* c = &colSums[static_cast<std::size_t>(y) * width];
        std::int64_t* o = &out[static_cast<std::size_t>(y) * width];
        std::int64_t s = 0;
        for (int x = 0; x < width; ++x) {
            s += c[x];
            if (x >= n) {
                s -= c[x - n];
            }
            if (x >= n - 1) {
                o[x - r] = s;
            }
        }
    }
}

// The WTA result as a disparity image: +inf where a pixel had no candidate; with
// `subpixel`, the vertex of the parabola through the scores at best-1, best, best+1.
cv::Mat disparityImage(int w, int h, const std::vector<int>& bestD, const std::vector<double>& best,
                       const std::vector<double>& atPrev, const std::vector<double>& atNext, bool subpixel) {
    const double kNone = -std::numeric_limits<double>::infinity();
    cv::Mat out(h, w, CV_32FC1, cv::Scalar(kNoMatch));
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * w + x;
            if (bestD[i] < 0 || best[i] == kNone) {
                continue;  // window leaves the image, flat, or no candidate
            }
            double disparity = bestD[i];
            if (subpixel && atPrev[i] != kNone && atNext[i] != kNone) {
                const double denom = atPrev[i] - 2.0 * best[i] + atNext[i];
                if (denom < 0.0) {
                    disparity += 0.5 * (atPrev[i] - atNext[i]) / denom;
                }
            }
            out.at<float>(y, x) = static_cast<float>(disparity);
        }
    }
    return out;
}

// ZNCC WTA with the kInsideOnly rule (the zero-padding rule runs this on padded images).
cv::Mat znccInsideOnly(const cv::Mat& left, const cv::Mat& right, int numDisparities, const ZnccOptions& options) {
    const int w = left.cols;
    const int h = left.rows;
    const int r = options.window / 2;
    const std::int64_t n = static_cast<std::int64_t>(options.window) * options.window;
    const std::size_t count = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);

    // Window sums of I and I^2 of both images (exact integers).
    std::vector<std::int64_t> l1(count), l2(count), r1(count), r2(count), col;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * w + x;
            l1[i] = left.at<std::uint8_t>(y, x);
            l2[i] = l1[i] * l1[i];
            r1[i] = right.at<std::uint8_t>(y, x);
            r2[i] = r1[i] * r1[i];
        }
    }
    std::vector<std::int64_t> sl, sll, sr, srr;
    boxSums(l1, w, h, r, col, sl);
    boxSums(l2, w, h, r, col, sll);
    boxSums(r1, w, h, r, col, sr);
    boxSums(r2, w, h, r, col, srr);

    // Per pixel: best score and disparity, and the scores beside the best (subpixel).
    const double kNone = -std::numeric_limits<double>::infinity();
    std::vector<double> best(count, kNone), atPrev(count, kNone), atNext(count, kNone), last(count, kNone);
    std::vector<int> bestD(count, -1);
    std::vector<std::int64_t> product(count), slr;
    for (int d = 0; d < numDisparities; ++d) {
        for (int y = 0; y < h; ++y) {
            for (int x = 0; x < w; ++x) {
                const std::size_t i = static_cast<std::size_t>(y) * w + x;
                product[i] = x >= d ? l1[i] * r1[i - static_cast<std::size_t>(d)] : 0;
            }
        }
        boxSums(product, w, h, r, col, slr);
        for (int y = r; y < h - r; ++y) {
            for (int x = r + d; x < w - r; ++x) {  // x - d - r >= 0: right window inside
                const std::size_t i = static_cast<std::size_t>(y) * w + x;
                const std::size_t j = i - static_cast<std::size_t>(d);
                const std::int64_t varL = n * sll[i] - sl[i] * sl[i];
                const std::int64_t varR = n * srr[j] - sr[j] * sr[j];
                double score = kNone;
                if (varL > 0 && varR > 0) {
                    const std::int64_t cov = n * slr[i] - sl[i] * sr[j];
                    score = static_cast<double>(cov) /
                            std::sqrt(static_cast<double>(varL) * static_cast<double>(varR));
                }
                if (bestD[i] == d - 1 && d > 0) {
                    atNext[i] = score;
                }
                if (score > best[i]) {
                    best[i] = score;
                    bestD[i] = d;
                    atPrev[i] = last[i];
                    atNext[i] = kNone;
                }
                last[i] = score;
            }
        }
    }

    return disparityImage(w, h, bestD, best, atPrev, atNext, options.subpixel);
}

}  // namespace

cv::Mat asMat(const ImageView<const std::uint8_t>& grey) {
    if (!grey.valid()) {
        throw std::invalid_argument("asMat: empty or malformed view");
    }
    // OpenCV takes a non-const pointer; the returned header is only read by the peers.
    return cv::Mat(grey.height(), grey.width(), CV_8UC1, const_cast<std::uint8_t*>(grey.data()),
                   static_cast<std::size_t>(grey.stride()));
}

void copyDisparity(const cv::Mat& disparity_px, const ImageView<float>& out) {
    if (disparity_px.type() != CV_32FC1 || !out.valid() || !out.sameSize(disparity_px.cols, disparity_px.rows)) {
        throw std::invalid_argument("copyDisparity: CV_32FC1 disparity and a view of its size required");
    }
    for (int y = 0; y < disparity_px.rows; ++y) {
        const float* s = disparity_px.ptr<float>(y);
        float* d = out.row(y);
        for (int x = 0; x < disparity_px.cols; ++x) {
            d[x] = s[x];
        }
    }
}

int numDisparitiesFor(double maxDisparityPx) {
    const int whole = static_cast<int>(std::ceil(maxDisparityPx));
    const int n = ((whole + 15) / 16) * 16;
    return n < 16 ? 16 : n;
}

cv::Ptr<cv::StereoBM> makeStereoBm(int numDisparities) {
    cv::Ptr<cv::StereoBM> bm = cv::StereoBM::create(numDisparities, 9);
    bm->setMinDisparity(0);
    bm->setPreFilterCap(31);
    bm->setTextureThreshold(10);
    bm->setUniquenessRatio(15);
    bm->setSpeckleWindowSize(100);
    bm->setSpeckleRange(32);
    bm->setDisp12MaxDiff(1);
    return bm;
}

cv::Ptr<cv::StereoSGBM> makeStereoSgbm3Way(int numDisparities) {
    constexpr int kBlock = 5;
    return cv::StereoSGBM::create(/*minDisparity=*/0, numDisparities, kBlock,
                                  /*P1=*/8 * kBlock * kBlock, /*P2=*/32 * kBlock * kBlock,
                                  /*disp12MaxDiff=*/1, /*preFilterCap=*/63, /*uniquenessRatio=*/10,
                                  /*speckleWindowSize=*/100, /*speckleRange=*/32,
                                  cv::StereoSGBM::MODE_SGBM_3WAY);
}

cv::Mat fixedPointToFloat(const cv::Mat& disparity16, int minDisparity) {
    CV_Assert(disparity16.type() == CV_16SC1);
    cv::Mat out(disparity16.size(), CV_32FC1);
    const int invalidBelow = minDisparity * 16;
    for (int y = 0; y < disparity16.rows; ++y) {
        const std::int16_t* s = disparity16.ptr<std::int16_t>(y);
        float* d = out.ptr<float>(y);
        for (int x = 0; x < disparity16.cols; ++x) {
            d[x] = s[x] < invalidBelow ? kNoMatch : static_cast<float>(s[x]) / 16.0F;
        }
    }
    return out;
}

cv::Mat stereoBm(const cv::Mat& left, const cv::Mat& right, int numDisparities) {
    checkPair(left, right, numDisparities, true);
    cv::setNumThreads(1);
    cv::Mat d16;
    makeStereoBm(numDisparities)->compute(left, right, d16);
    return fixedPointToFloat(d16);
}

cv::Mat stereoSgbm3Way(const cv::Mat& left, const cv::Mat& right, int numDisparities) {
    checkPair(left, right, numDisparities, true);
    cv::setNumThreads(1);
    cv::Mat d16;
    makeStereoSgbm3Way(numDisparities)->compute(left, right, d16);
    return fixedPointToFloat(d16);
}

cv::Mat znccWta(const cv::Mat& left, const cv::Mat& right, int numDisparities, const ZnccOptions& options) {
    checkPair(left, right, numDisparities, false);
    if (options.window < 3 || options.window % 2 == 0) {
        throw std::invalid_argument("znccWta: window must be odd and >= 3");
    }
    if (options.border == ZnccBorder::kInsideOnly) {
        return znccInsideOnly(left, right, numDisparities, options);
    }
    // Zero padding by r on every side: in the padded images every original left pixel
    // has its window inside, and the inside-only rule x_p - d - r >= 0 becomes x - d >= 0.
    const int r = options.window / 2;
    cv::Mat lp, rp;
    cv::copyMakeBorder(left, lp, r, r, r, r, cv::BORDER_CONSTANT, cv::Scalar(0));
    cv::copyMakeBorder(right, rp, r, r, r, r, cv::BORDER_CONSTANT, cv::Scalar(0));
    return znccInsideOnly(lp, rp, numDisparities, options)(cv::Rect(r, r, left.cols, left.rows)).clone();
}

}  // namespace vtm::peer
