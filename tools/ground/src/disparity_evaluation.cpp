#include "vtm/ground/disparity_evaluation.hpp"

#include <cmath>
#include <limits>

#include "vtm/ground/image_io.hpp"
#include "vtm/ground/pfm.hpp"

namespace vtm::ground {
namespace {

constexpr float kUnknown = std::numeric_limits<float>::infinity();

template <typename T>
std::string sizeText(const Image<T>& img) { return std::to_string(img.width) + "x" + std::to_string(img.height); }

struct Tally {
    std::int64_t evaluated = 0;
    std::int64_t matched = 0;
    std::int64_t bad[3] = {0, 0, 0};  // > 0.5, > 1, > 2 px
    double abs_error_sum = 0.0;
};

void tallyPixel(float d, float gt, Tally& t) {
    ++t.evaluated;
    if (!std::isfinite(d)) {  // no match: bad at every threshold
        t.bad[0]++;
        t.bad[1]++;
        t.bad[2]++;
        return;
    }
    const double err = std::fabs(static_cast<double>(d) - static_cast<double>(gt));
    ++t.matched;
    t.abs_error_sum += err;
    t.bad[0] += (err > 0.5) ? 1 : 0;
    t.bad[1] += (err > 1.0) ? 1 : 0;
    t.bad[2] += (err > 2.0) ? 1 : 0;
}

DisparityErrors summarise(const Tally& t) {
    const double n = static_cast<double>(t.evaluated);
    DisparityErrors e;
    e.evaluated_pixels = t.evaluated;
    e.matched_pixels = t.matched;
    e.bad05_percent = 100.0 * static_cast<double>(t.bad[0]) / n;
    e.bad1_percent = 100.0 * static_cast<double>(t.bad[1]) / n;
    e.bad2_percent = 100.0 * static_cast<double>(t.bad[2]) / n;
    e.invalid_percent = 100.0 * static_cast<double>(t.evaluated - t.matched) / n;
    e.mae_px = (t.matched > 0) ? t.abs_error_sum / static_cast<double>(t.matched)
                               : std::numeric_limits<double>::quiet_NaN();
    return e;
}

}  // namespace

bool isKnownDisparity(float gt_px) { return std::isfinite(gt_px) && gt_px != 0.0F; }

Result<DisparityErrors> evaluateDisparity(const FloatImage& estimate_px, const FloatImage& ground_truth_px,
                                          const GreyImage* mask) {
    if (!estimate_px.sameSize(ground_truth_px)) {
        return Result<DisparityErrors>::failure("disparity is " + sizeText(estimate_px) + " but ground truth is " +
                                                sizeText(ground_truth_px));
    }
    if (mask != nullptr && !mask->sameSize(ground_truth_px)) {
        return Result<DisparityErrors>::failure("mask is " + sizeText(*mask) + " but ground truth is " +
                                                sizeText(ground_truth_px));
    }
    Tally t;
    for (std::int32_t y = 0; y < ground_truth_px.height; ++y) {
        for (std::int32_t x = 0; x < ground_truth_px.width; ++x) {
            const float gt = ground_truth_px.at(x, y);
            if (isKnownDisparity(gt) && (mask == nullptr || mask->at(x, y) != 0)) {
                tallyPixel(estimate_px.at(x, y), gt, t);
            }
        }
    }
    if (t.evaluated == 0) {
        return Result<DisparityErrors>::failure("no pixel to evaluate (ground truth unknown everywhere in the mask)");
    }
    return Result<DisparityErrors>::success(summarise(t));
}

Result<FloatImage> loadGroundTruth(const std::string& path, double scale) {
    if (!(scale > 0.0) || !std::isfinite(scale)) {
        return Result<FloatImage>::failure(path + ": ground truth scale must be a positive number, got " +
                                           std::to_string(scale));
    }
    FloatImage gt;
    if (looksLikePfm(path)) {
        Result<FloatImage> pfm = readPfm(path);
        if (!pfm.ok) {
            return pfm;
        }
        gt = std::move(pfm.value);
        for (float& v : gt.pixels) {
            v = isKnownDisparity(v) ? static_cast<float>(static_cast<double>(v) / scale) : kUnknown;
        }
        return Result<FloatImage>::success(std::move(gt));
    }
    Result<Grey16Image> levels = loadGrey16(path);
    if (!levels.ok) {
        return Result<FloatImage>::failure(levels.error);
    }
    gt = FloatImage(levels.value.width, levels.value.height);
    for (std::size_t i = 0; i < gt.pixels.size(); ++i) {
        const std::uint16_t level = levels.value.pixels[i];
        gt.pixels[i] = (level == 0U) ? kUnknown : static_cast<float>(level / scale);
    }
    return Result<FloatImage>::success(std::move(gt));
}

}  // namespace vtm::ground
