#include "vtm/ground/middlebury.hpp"

#include <cstdlib>
#include <filesystem>

#include "vtm/ground/disparity_evaluation.hpp"
#include "vtm/ground/image_io.hpp"
#include "vtm/ground/occlusion_mask.hpp"

namespace vtm::ground {
namespace {

std::string join(const std::string& dir, const char* file) { return (std::filesystem::path(dir) / file).string(); }

Result<MiddleburyGroundTruth> withMask(const std::string& dir, const MiddleburySet& set, FloatImage gt_left) {
    MiddleburyGroundTruth truth;
    const std::string tol = " (1 px)";
    if (set.mask == MaskMethod::kRowVisibility) {
        truth.nonoccluded = visibilityMask(gt_left);
        truth.mask_description = std::string("non-occluded (row visibility test of ") + set.gt_left + tol + ")";
    } else {
        Result<FloatImage> gt_right = loadGroundTruth(join(dir, set.gt_right), set.scale);
        if (!gt_right.ok) {
            return Result<MiddleburyGroundTruth>::failure(gt_right.error);
        }
        Result<GreyImage> mask = leftRightCheckMask(gt_left, gt_right.value);
        if (!mask.ok) {
            return Result<MiddleburyGroundTruth>::failure(dir + ": " + mask.error);
        }
        truth.nonoccluded = std::move(mask.value);
        truth.mask_description = std::string("non-occluded (left-right check of ") + set.gt_left + " vs " +
                                 set.gt_right + tol + ")";
    }
    truth.disparity_px = std::move(gt_left);
    return Result<MiddleburyGroundTruth>::success(std::move(truth));
}

Result<const MiddleburySet*> lookUp(std::string_view name) {
    const MiddleburySet* set = findMiddleburySet(name);
    if (set == nullptr) {
        return Result<const MiddleburySet*>::failure("unknown Middlebury set '" + std::string(name) +
                                                     "' (known: " + middleburySetNames() + ")");
    }
    return Result<const MiddleburySet*>::success(set);
}

}  // namespace

const std::vector<MiddleburySet>& middleburySets() {
    // Scales and files from shared/data/middlebury/README.md.
    static const std::vector<MiddleburySet> kSets = {
        {"tsukuba", "im3.png", "im4.png", "disp3.pgm", nullptr, 16.0, MaskMethod::kRowVisibility},
        {"venus", "im2.png", "im6.png", "disp2.pgm", nullptr, 8.0, MaskMethod::kRowVisibility},
        {"teddy", "im2.png", "im6.png", "disp2.png", "disp6.png", 4.0, MaskMethod::kLeftRightCheck},
        {"cones", "im2.png", "im6.png", "disp2.png", "disp6.png", 4.0, MaskMethod::kLeftRightCheck},
    };
    return kSets;
}

const MiddleburySet* findMiddleburySet(std::string_view name) {
    for (const MiddleburySet& s : middleburySets()) {
        if (name == s.name) {
            return &s;
        }
    }
    return nullptr;
}

std::string middleburySetNames() {
    std::string names;
    for (const MiddleburySet& s : middleburySets()) {
        names += (names.empty() ? "" : ", ") + std::string(s.name);
    }
    return names;
}

std::string dataDirFromEnvironment() {
    const char* v = std::getenv("VTM_DATA");
    return (v != nullptr) ? std::string(v) : std::string();
}

Result<std::string> middleburySetDir(const std::string& data_dir, const MiddleburySet& set) {
    if (data_dir.empty()) {
        return Result<std::string>::failure("no data directory: pass --data DIR or set VTM_DATA");
    }
    const std::filesystem::path root(data_dir);
    std::error_code ec;
    for (const std::filesystem::path& p : {root / set.name, root / "middlebury" / set.name}) {
        if (std::filesystem::is_directory(p, ec)) {
            return Result<std::string>::success(p.string());
        }
    }
    return Result<std::string>::failure(data_dir + ": no folder " + set.name + " or middlebury/" + set.name);
}

Result<MiddleburyGroundTruth> loadMiddleburyGroundTruth(const std::string& data_dir, std::string_view set_name) {
    Result<const MiddleburySet*> set = lookUp(set_name);
    if (!set.ok) {
        return Result<MiddleburyGroundTruth>::failure(set.error);
    }
    Result<std::string> dir = middleburySetDir(data_dir, *set.value);
    if (!dir.ok) {
        return Result<MiddleburyGroundTruth>::failure(dir.error);
    }
    Result<FloatImage> gt = loadGroundTruth(join(dir.value, set.value->gt_left), set.value->scale);
    if (!gt.ok) {
        return Result<MiddleburyGroundTruth>::failure(gt.error);
    }
    return withMask(dir.value, *set.value, std::move(gt.value));
}

Result<MiddleburyPair> loadMiddleburyPair(const std::string& data_dir, std::string_view set_name) {
    Result<MiddleburyGroundTruth> truth = loadMiddleburyGroundTruth(data_dir, set_name);
    if (!truth.ok) {
        return Result<MiddleburyPair>::failure(truth.error);
    }
    MiddleburyPair pair;
    pair.set = findMiddleburySet(set_name);
    const std::string dir = middleburySetDir(data_dir, *pair.set).value;
    Result<GreyImage> left = loadGrey8(join(dir, pair.set->left_image));
    Result<GreyImage> right = loadGrey8(join(dir, pair.set->right_image));
    if (!left.ok || !right.ok) {
        return Result<MiddleburyPair>::failure(!left.ok ? left.error : right.error);
    }
    pair.left = std::move(left.value);
    pair.right = std::move(right.value);
    pair.truth = std::move(truth.value);
    return Result<MiddleburyPair>::success(std::move(pair));
}

}  // namespace vtm::ground
