#include "eval_command.hpp"
#include "command_support.hpp"

#include <cmath>
#include <cstdio>

#include "vtm/ground/exit_codes.hpp"
#include "vtm/ground/disparity_evaluation.hpp"
#include "vtm/ground/image_io.hpp"
#include "vtm/ground/middlebury.hpp"
#include "vtm/ground/pfm.hpp"

namespace vtm::tools {
namespace {

using ground::FloatImage;
using ground::GreyImage;

// What is evaluated against: ground truth in pixels, an optional mask and their names.
struct Reference {
    FloatImage gt_px;
    GreyImage mask;  // empty: every pixel with known ground truth
    std::string gt_name;
    std::string mask_name = "none (every pixel with known ground truth)";
};

// A mask file (8- or 16-bit grey): nonzero = evaluate.
std::string loadMask(const std::string& path, Reference& ref) {
    ground::Result<ground::Grey16Image> m = ground::loadGrey16(path);
    if (!m.ok) {
        return m.error;
    }
    ref.mask = GreyImage(m.value.width, m.value.height);
    for (std::size_t i = 0; i < ref.mask.pixels.size(); ++i) {
        ref.mask.pixels[i] = (m.value.pixels[i] != 0U) ? 255 : 0;
    }
    ref.mask_name = path + " (nonzero = evaluate)";
    return "";
}

std::string fromMiddlebury(const EvalOptions& o, Reference& ref) {
    const std::string dir = o.data_dir.empty() ? ground::dataDirFromEnvironment() : o.data_dir;
    ground::Result<ground::MiddleburyGroundTruth> t = ground::loadMiddleburyGroundTruth(dir, o.middlebury);
    if (!t.ok) {
        return t.error;
    }
    const ground::MiddleburySet* set = ground::findMiddleburySet(o.middlebury);
    ref.gt_px = std::move(t.value.disparity_px);
    ref.mask = std::move(t.value.nonoccluded);
    char scale[32];
    std::snprintf(scale, sizeof scale, "%g", set->scale);
    ref.gt_name = std::string("Middlebury ") + set->name + " " + set->gt_left + " / " + scale;
    ref.mask_name = t.value.mask_description;
    return "";
}

// Integer ground truth means nothing without its scale; a PFM is in pixels already.
// A file that does not load is left for the loader to report (missing beats unscaled).
bool needsScale(const EvalOptions& o) {
    return o.middlebury.empty() && !o.scaleGiven() && !ground::looksLikePfm(o.ground_truth) &&
           ground::loadGrey16(o.ground_truth).ok;
}

std::string fromFiles(const EvalOptions& o, Reference& ref) {
    const double scale = o.scaleGiven() ? o.scale : 1.0;
    ground::Result<FloatImage> gt = ground::loadGroundTruth(o.ground_truth, scale);
    if (!gt.ok) {
        return gt.error;
    }
    ref.gt_px = std::move(gt.value);
    char s[32];
    std::snprintf(s, sizeof s, "%g", scale);
    ref.gt_name = o.ground_truth + " / " + s;
    return "";
}

void printErrors(const EvalOptions& o, const Reference& ref, const ground::DisparityErrors& e) {
    std::printf("vtm eval: %s\n", o.disparity_pfm.c_str());
    std::printf("  ground truth  %s\n", ref.gt_name.c_str());
    std::printf("  mask          %s\n", ref.mask_name.c_str());
    std::printf("  evaluated     %lld px (no match counted as bad)\n", static_cast<long long>(e.evaluated_pixels));
    std::printf("  bad>0.5       %7.2f %%\n", e.bad05_percent);
    std::printf("  bad>1         %7.2f %%\n", e.bad1_percent);
    std::printf("  bad>2         %7.2f %%\n", e.bad2_percent);
    std::printf("  invalid       %7.2f %%\n", e.invalid_percent);
    std::printf("  MAE           %7.3f px (over %lld matched px)\n", e.mae_px,
                static_cast<long long>(e.matched_pixels));
}

}  // namespace

CLI::App* addEvalCommand(CLI::App& app, EvalOptions& o) {
    CLI::App* cmd = app.add_subcommand("eval", "bad-pixel percentages and MAE of a disparity map against ground truth");
    cmd->add_option("DISP", o.disparity_pfm, "disparity in pixels, PFM (+inf = no match)")->required();
    cmd->add_option("GT", o.ground_truth, "ground truth: grey PNG/PGM (levels / --scale) or PFM; 0 = unknown");
    CLI::Option* scale =
        cmd->add_option("--scale", o.scale, "ground-truth grey levels per pixel (teddy 4, tsukuba 16)");
    cmd->add_option("--mask", o.mask, "evaluate only where this grey image is nonzero");
    CLI::Option* set = cmd->add_option("--middlebury", o.middlebury,
                                       "set name (tsukuba, venus, teddy, cones): its ground truth, scale and "
                                       "derived non-occluded mask");
    CLI::Option* data =
        cmd->add_option("--data", o.data_dir, "data directory holding SET/ or middlebury/SET/ (default: $VTM_DATA)");
    set->excludes(scale);
    data->needs(set);
    return cmd;
}

int runEval(const EvalOptions& o) {
    if (o.ground_truth.empty() == o.middlebury.empty()) {
        return failCommand("eval", kExitUsageError, "give either GT or --middlebury SET (not both, not neither)");
    }
    if (o.scaleGiven() && !(o.scale > 0.0 && std::isfinite(o.scale))) {
        return failCommand("eval", kExitUsageError, "--scale " + std::to_string(o.scale) + ": must be a positive number");
    }
    if (needsScale(o)) {
        return failCommand("eval", kExitUsageError, o.ground_truth +
                                         ": integer ground truth needs --scale (grey levels per pixel "
                                         "of disparity, e.g. 4 for teddy, 16 for tsukuba)");
    }
    ground::Result<FloatImage> estimate = ground::readPfm(o.disparity_pfm);
    if (!estimate.ok) {
        return failCommand("eval", kExitInputError, estimate.error);
    }
    Reference ref;
    std::string error = o.middlebury.empty() ? fromFiles(o, ref) : fromMiddlebury(o, ref);
    error = (error.empty() && !o.mask.empty()) ? loadMask(o.mask, ref) : error;
    if (!error.empty()) {
        return failCommand("eval", kExitInputError, error);
    }
    ground::Result<ground::DisparityErrors> e =
        ground::evaluateDisparity(estimate.value, ref.gt_px, ref.mask.empty() ? nullptr : &ref.mask);
    if (!e.ok) {
        return failCommand("eval", kExitInputError, o.disparity_pfm + ": " + e.error);
    }
    printErrors(o, ref, e.value);
    return kExitOk;
}

}  // namespace vtm::tools
