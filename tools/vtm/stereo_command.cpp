#include "stereo_command.hpp"
#include "command_support.hpp"
#include "option_pair.hpp"

#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <vector>

#include "vtm/ground/exit_codes.hpp"
#include "vtm/core/arena.hpp"
#include "vtm/ground/disparity_colormap.hpp"
#include "vtm/ground/image_io.hpp"
#include "vtm/ground/pfm.hpp"
#include "vtm/stereo/ml_stereo.hpp"

namespace vtm::tools {
namespace {

using ground::FloatImage;
using ground::GreyImage;
using stereo::Config;
using stereo::MlStereo;

constexpr double kBytesPerMiB = 1024.0 * 1024.0;

// Short name of a stereo::Reason value, for the summary. A value this table does not
// know yet is printed by number rather than refused.
std::string reasonName(std::int32_t value) {
    switch (static_cast<stereo::Reason>(value)) {
        case stereo::Reason::kValid: return "valid";
        case stereo::Reason::kBorder: return "border";
        case stereo::Reason::kNoTexture: return "no texture";
        case stereo::Reason::kAmbiguous: return "ambiguous";
        case stereo::Reason::kLeftRightMismatch: return "left-right mismatch";
        case stereo::Reason::kOutOfRange: return "out of range";
        case stereo::Reason::kLowLikelihood: return "low likelihood";
        case stereo::Reason::kSpeckle: return "speckle";
        case stereo::Reason::kNoPrior: return "no prior";
        default: return "reason " + std::to_string(value);
    }
}

struct DisparityRange {
    bool ok = false;
    std::int32_t min = 0;
    std::int32_t max = 0;
    std::string error;
};

DisparityRange parseRange(const std::string& text) {
    double lo = 0.0, hi = 0.0;
    const std::string e =
        cli::parseOptionPair("--disparity", text, cli::PairRule::kWholeOrdered, "in whole pixels", "0:63", lo, hi);
    if (!e.empty()) return DisparityRange{false, 0, 0, e};
    return DisparityRange{true, static_cast<std::int32_t>(lo), static_cast<std::int32_t>(hi), ""};
}


struct StereoInputs {
    GreyImage left;
    GreyImage right;
    Config config;
};

// Loads the pair and builds the configuration; "" or the one-line error.
std::string prepare(const StereoOptions& o, const DisparityRange& range, StereoInputs& in) {
    ground::Result<GreyImage> left = ground::loadGrey8(o.left);
    if (!left.ok) {
        return left.error;
    }
    ground::Result<GreyImage> right = ground::loadGrey8(o.right);
    if (!right.ok) {
        return right.error;
    }
    if (!left.value.sameSize(right.value)) {
        return o.left + " is " + sizeText(left.value) + " but " + o.right + " is " + sizeText(right.value) +
               " (a rectified pair has equal sizes)";
    }
    in.left = std::move(left.value);
    in.right = std::move(right.value);
    in.config.max_width = in.left.width;
    in.config.max_height = in.left.height;
    in.config.d_min = range.min;
    in.config.d_max = range.max;
    in.config.window = o.window;
    const Status valid = in.config.validate();
    if (!valid.isOk()) {
        return "configuration refused for --disparity " + o.disparity_range + " on " + sizeText(in.left) + ": " +
               valid.reason() + " (got " + std::to_string(valid.detail()) + ")";
    }
    return "";
}

// The budget check: "" or the one-line refusal naming the range and the bytes.
std::string checkBudget(const StereoOptions& o, const StereoInputs& in, std::size_t need) {
    const double budget = o.budget_mib * kBytesPerMiB;
    if (static_cast<double>(need) <= budget) {
        return "";
    }
    char text[256];
    std::snprintf(text, sizeof text,
                  "--disparity %s on %dx%d, window %d, needs %zu bytes of workspace, over the budget of %.0f bytes "
                  "(%g MiB); narrow the range or raise --budget-mib",
                  o.disparity_range.c_str(), in.left.width, in.left.height, in.config.window, need, budget,
                  o.budget_mib);
    return text;
}

struct StereoRun {
    ground::Image<std::int16_t> disparity_px16;
    FloatImage sigma_px;
    GreyImage reason;
    stereo::StereoStats stats;
    double seconds = 0.0;
};

// init + compute in an arena of exactly workspaceBytes(config); "" or the error.
std::string runMatcher(const StereoInputs& in, std::size_t workspace, bool want_sigma, StereoRun& run) {
    std::vector<std::byte> pool(workspace);
    Arena arena(pool.data(), pool.size());
    MlStereo matcher;
    const Status init = matcher.init(in.config, arena);
    if (!init.isOk()) {
        return std::string("MlStereo::init: ") + init.reason() + " (" + std::to_string(init.detail()) + ")";
    }
    arena.freeze();
    run.disparity_px16 = ground::Image<std::int16_t>(in.left.width, in.left.height);
    run.reason = GreyImage(in.left.width, in.left.height);
    run.sigma_px = want_sigma ? FloatImage(in.left.width, in.left.height) : FloatImage();
    const stereo::DisparityOutput out{run.disparity_px16.view(),
                                      want_sigma ? run.sigma_px.view() : ImageView<float>(), run.reason.view()};
    const auto t0 = std::chrono::steady_clock::now();
    const Status s = matcher.compute(in.left.view(), in.right.view(), out, &run.stats);
    run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!s.isOk()) {
        return std::string("MlStereo::compute: ") + s.reason() + " (" + std::to_string(s.detail()) + ")";
    }
    return "";
}

// Fixed point 1/16 px -> pixels; kNoDisparity -> +inf (PFM / Middlebury "no value").
FloatImage disparityInPixels(const ground::Image<std::int16_t>& px16) {
    FloatImage d(px16.width, px16.height);
    for (std::size_t i = 0; i < d.pixels.size(); ++i) {
        const std::int16_t v = px16.pixels[i];
        d.pixels[i] = (v == stereo::kNoDisparity) ? std::numeric_limits<float>::infinity()
                                                  : static_cast<float>(v) / static_cast<float>(stereo::kDisparityScale);
    }
    return d;
}

// Writes the requested files; "" or the error.
std::string writeOutputs(const StereoOptions& o, const StereoInputs& in, const StereoRun& run) {
    const FloatImage disparity = disparityInPixels(run.disparity_px16);
    ground::Outcome w = ground::Outcome::success();
    if (!o.out_pfm.empty()) {
        w = ground::writePfm(o.out_pfm, disparity);
    }
    if (w.ok && !o.uncertainty_pfm.empty()) {
        w = ground::writePfm(o.uncertainty_pfm, run.sigma_px);
    }
    if (w.ok && !o.color_png.empty()) {
        const auto lo = static_cast<float>(in.config.d_min);
        const auto hi = static_cast<float>(in.config.d_max);
        w = ground::writePng(o.color_png, ground::colorizeDisparity(disparity, lo, hi));
    }
    return w.ok ? "" : w.error;
}

void printSummary(const StereoOptions& o, const StereoInputs& in, std::size_t workspace, const StereoRun& run) {
    const double pixels = static_cast<double>(in.left.pixels.size());
    const double disparities = in.config.d_max - in.config.d_min + 1;
    std::printf("vtm stereo: %s + %s, %dx%d, disparity %d:%d, window %d\n", o.left.c_str(), o.right.c_str(),
                in.left.width, in.left.height, in.config.d_min, in.config.d_max, in.config.window);
    std::printf("  workspace  %zu bytes (budget %.0f)\n", workspace, o.budget_mib * kBytesPerMiB);
    std::printf("  time       %.3f s, %.1f Mpx*disp/s\n", run.seconds,
                pixels * disparities / 1e6 / (run.seconds > 0.0 ? run.seconds : 1e-9));
    for (std::int32_t r = 0; r < stereo::kReasonCount; ++r) {
        const std::int32_t n = run.stats.reason_counts[r];
        if (n > 0 || r == 0) {
            std::printf("  %-20s %6.2f %%  (%" PRId32 " px)\n", reasonName(r).c_str(), 100.0 * n / pixels, n);
        }
    }
}

}  // namespace

CLI::App* addStereoCommand(CLI::App& app, StereoOptions& o) {
    CLI::App* cmd = app.add_subcommand("stereo", "dense disparity of a rectified pair (ML stereo, flight module)");
    cmd->add_option("LEFT", o.left, "left (reference) image: PNG, PGM, JPEG or BMP; colour becomes grey")->required();
    cmd->add_option("RIGHT", o.right, "right image, same size")->required();
    cmd->add_option("--disparity", o.disparity_range,
                    "search range MIN:MAX in whole pixels, inclusive (MIN may be negative); "
                    "left x matches right x - d")
        ->required();
    cmd->add_option("--window", o.window,
                    "matching window side, odd, 3..31 px (default " + std::to_string(Config{}.window) + ")");
    cmd->add_option("--out", o.out_pfm, "disparity in pixels as PFM (+inf = no match)");
    cmd->add_option("--uncertainty", o.uncertainty_pfm, "1-sigma disparity uncertainty in pixels as PFM");
    cmd->add_option("--color", o.color_png, "colour-coded disparity PNG (red = MAX ... purple = MIN, black = none)");
    cmd->add_option("--budget-mib", o.budget_mib, "largest workspace allowed, MiB (default: the flight budget, 8)");
    return cmd;
}

int runStereo(const StereoOptions& o) {
    const DisparityRange range = parseRange(o.disparity_range);
    if (!range.ok) {
        return failCommand("stereo", kExitUsageError, range.error);
    }
    if (!(o.budget_mib > 0.0) || !std::isfinite(o.budget_mib)) {
        return failCommand("stereo", kExitUsageError, "--budget-mib " + std::to_string(o.budget_mib) + ": must be a positive number");
    }
    StereoInputs in;
    std::string error = prepare(o, range, in);
    const std::size_t workspace = error.empty() ? MlStereo::workspaceBytes(in.config) : 0U;
    error = error.empty() ? checkBudget(o, in, workspace) : error;
    StereoRun run;
    error = error.empty() ? runMatcher(in, workspace, !o.uncertainty_pfm.empty(), run) : error;
    error = error.empty() ? writeOutputs(o, in, run) : error;
    if (!error.empty()) {
        return failCommand("stereo", kExitInputError, error);
    }
    printSummary(o, in, workspace, run);
    return kExitOk;
}

}  // namespace vtm::tools
