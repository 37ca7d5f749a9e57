// The four Middlebury stereo sets kept in shared/data/middlebury (README there): file
// names, ground-truth scales and how each set's non-occluded mask is derived, plus
// loaders that return ready-to-use images, ground truth in pixels and the mask.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "vtm/ground/image.hpp"

namespace vtm::ground {

enum class MaskMethod {
    kLeftRightCheck,  // ground truth for both views: leftRightCheckMask()
    kRowVisibility,   // left ground truth only: visibilityMask()
};

struct MiddleburySet {
    const char* name;         // "tsukuba", "venus", "teddy", "cones"
    const char* left_image;   // reference view
    const char* right_image;  // left pixel (x, y) at disparity d sees right pixel (x - d, y)
    const char* gt_left;      // ground truth of the left view
    const char* gt_right;     // ground truth of the right view, or nullptr
    double scale;             // grey level per pixel of disparity (level 0 = unknown)
    MaskMethod mask;
};

// The table, in a fixed order.
const std::vector<MiddleburySet>& middleburySets();
// The set of that name, or nullptr.
const MiddleburySet* findMiddleburySet(std::string_view name);
// "tsukuba, venus, teddy, cones", for messages.
std::string middleburySetNames();

// The data directory named by the environment variable VTM_DATA ("" when unset).
std::string dataDirFromEnvironment();
// The folder of `set` under data_dir: data_dir/<set> or data_dir/middlebury/<set>,
// whichever exists (so both the shared data root and its middlebury/ folder work).
Result<std::string> middleburySetDir(const std::string& data_dir, const MiddleburySet& set);

struct MiddleburyGroundTruth {
    FloatImage disparity_px;  // left view, pixels; +inf = unknown
    GreyImage nonoccluded;    // 255 = evaluate, 0 = occluded or unknown (occlusion_mask.hpp)
    std::string mask_description;  // e.g. "non-occluded (left-right check of disp2.png vs disp6.png, 1 px)"
};

struct MiddleburyPair {
    const MiddleburySet* set = nullptr;
    GreyImage left;   // 8-bit grey (RGB converted as in image_io.hpp)
    GreyImage right;
    MiddleburyGroundTruth truth;
};

// Ground truth and non-occluded mask of a set (by name) under data_dir.
Result<MiddleburyGroundTruth> loadMiddleburyGroundTruth(const std::string& data_dir, std::string_view set_name);
// Both images plus ground truth and mask.
Result<MiddleburyPair> loadMiddleburyPair(const std::string& data_dir, std::string_view set_name);

}  // namespace vtm::ground
