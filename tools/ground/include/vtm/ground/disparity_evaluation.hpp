// Dense-stereo accuracy against ground truth, the Middlebury way (Scharstein & Szeliski,
// IJCV 2002): the percentage of "bad" pixels whose disparity differs from the truth by
// more than a threshold, over the pixels that are evaluated.
//
// Evaluated pixels: ground truth known (finite and nonzero: Middlebury writes 0 where
// the truth is unknown) and, when a mask is given, mask nonzero (e.g. non-occluded).
// A pixel without an estimate (+inf or NaN: no match) is counted as bad at every
// threshold, so a matcher cannot improve its score by refusing pixels; how many it
// refused is reported separately (invalid_percent). MAE is over the evaluated pixels
// that have an estimate.
#pragma once

#include <cstdint>
#include <string>

#include "vtm/ground/image.hpp"

namespace vtm::ground {

struct DisparityErrors {
    std::int64_t evaluated_pixels = 0;  // ground truth known and inside the mask
    std::int64_t matched_pixels = 0;    // of those, with an estimate
    double bad05_percent = 0.0;         // |d - gt| > 0.5 px or no estimate, % of evaluated
    double bad1_percent = 0.0;          // |d - gt| > 1 px or no estimate
    double bad2_percent = 0.0;          // |d - gt| > 2 px or no estimate
    double invalid_percent = 0.0;       // no estimate, % of evaluated
    double mae_px = 0.0;                // mean |d - gt| over matched pixels, pixels (NaN if none)
};

// estimate_px, ground_truth_px: one-channel disparities in pixels, same size.
// mask: nullptr (all pixels) or a one-channel image of the same size, nonzero = evaluate.
// Fails when sizes differ or no pixel is evaluated.
Result<DisparityErrors> evaluateDisparity(const FloatImage& estimate_px, const FloatImage& ground_truth_px,
                                          const GreyImage* mask = nullptr);

// Ground truth disparity in pixels from a file: a grey 8/16-bit PNG or PGM whose levels
// are disparity * scale (Middlebury: tsukuba 16, venus 8, teddy and cones 4), or a PFM
// (its values divided by scale; 1 for a PFM in pixels). Unknown pixels (level 0,
// non-finite) become +inf. scale must be positive.
Result<FloatImage> loadGroundTruth(const std::string& path, double scale);

// True when a ground truth value is known (finite and nonzero).
bool isKnownDisparity(float gt_px);

}  // namespace vtm::ground
