#include "register_command.hpp"
#include "command_support.hpp"
#include "option_pair.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "vtm/core/arena.hpp"
#include "vtm/entropy/registration.hpp"
#include "vtm/ground/exit_codes.hpp"
#include "vtm/ground/image_io.hpp"

namespace vtm::tools {
namespace {

constexpr double kRadPerDeg = 3.14159265358979323846 / 180.0;

std::string requestOf(const RegisterOptions& o, entropy::RegistrationRequest& r) {
    double lo = 0.0, hi = 0.0;
    std::string e = cli::parseOptionPair("--rotation", o.rotation, cli::PairRule::kOrdered, "in degrees", "", lo, hi);
    if (!e.empty()) return e;
    r.angle_min_rad = lo * kRadPerDeg;
    r.angle_max_rad = hi * kRadPerDeg;
    e = cli::parseOptionPair("--scale", o.scale, cli::PairRule::kOrdered, "", "", lo, hi);
    if (!e.empty()) return e;
    r.scale_min = lo;
    r.scale_max = hi;
    e = cli::parseOptionPair("--shift", o.shift, cli::PairRule::kAny, "in pixels", "", lo, hi);
    if (!e.empty()) return e;
    r.shift_x_px = lo;
    r.shift_y_px = hi;
    r.shift_range_px = o.shift_range_px;
    return "";
}

// The matched images (entropy, or grey levels with --intensity) as PNG files.
std::string writeMatched(const RegisterOptions& o, const entropy::EntropyRegistration& reg) {
    const std::string* paths[2] = {&o.entropy1_png, &o.entropy2_png};
    for (int i = 0; i < 2; ++i) {
        if (paths[i]->empty()) continue;
        const ImageView<const std::uint8_t> v = i == 0 ? reg.matchedImage1() : reg.matchedImage2();
        ground::GreyImage img(v.width(), v.height());
        for (std::int32_t y = 0; y < v.height(); ++y) {
            std::copy(v.row(y), v.row(y) + v.width(), img.pixels.begin() + static_cast<std::ptrdiff_t>(y) * v.width());
        }
        const ground::Outcome w = ground::writePng(*paths[i], img);
        if (!w.ok) return w.error;
    }
    return "";
}

std::string report(const RegisterOptions& o, const entropy::Registration& r, const Status& s) {
    char b[1024];
    std::snprintf(b, sizeof b,
                  "# vtm register: %s -> %s (%s)\n# [x2 y2]^T = G [x1 y1 1]^T, pixels, (0,0) = centre of the top-left pixel\n"
                  "G %.9g %.9g %.9g\nG %.9g %.9g %.9g\nangle_deg %.6f\nscale %.6f\nshift_px %.4f %.4f\nncc %.4f\n"
                  "second_ncc %.4f\noverlap %.4f\nstatus %s\n",
                  o.image1.c_str(), o.image2.c_str(), o.intensity ? "intensity" : "entropy", r.image2_from_image1(0, 0),
                  r.image2_from_image1(0, 1), r.image2_from_image1(0, 2), r.image2_from_image1(1, 0),
                  r.image2_from_image1(1, 1), r.image2_from_image1(1, 2), r.angle_rad / kRadPerDeg, r.scale,
                  r.shift_x_px, r.shift_y_px, r.ncc, r.second_ncc, r.overlap, s.isOk() ? "registered" : s.reason());
    return b;
}

// The picture of the match: image 1's frame as a checkerboard of kTile px squares, the
// light squares image 1, the dark ones image 2 brought through G (bilinear; image 1 where
// G leaves image 2). Where the registration is right, roads, rivers and field edges run on
// across the squares' borders.
constexpr std::int32_t kTile = 32;

ground::GreyImage checkerboard(const ground::GreyImage& a, const ground::GreyImage& b, const entropy::Mat23& g) {
    ground::GreyImage out(a.width, a.height);
    for (std::int32_t y = 0; y < a.height; ++y) {
        for (std::int32_t x = 0; x < a.width; ++x) {
            out.at(x, y) = a.at(x, y);
            if (((x / kTile) + (y / kTile)) % 2 == 0) continue;
            const double u = g(0, 0) * x + g(0, 1) * y + g(0, 2);
            const double v = g(1, 0) * x + g(1, 1) * y + g(1, 2);
            if (!(u >= 0.0 && v >= 0.0 && u <= b.width - 1 && v <= b.height - 1)) continue;
            out.at(x, y) = static_cast<std::uint8_t>(std::lround(ground::bilinearAt(b, u, v)));
        }
    }
    return out;
}

}  // namespace

CLI::App* addRegisterCommand(CLI::App& app, RegisterOptions& o) {
    CLI::App* cmd = app.add_subcommand(
        "register", "register two images of different sensors (local entropy, flight module): similarity 1 -> 2");
    cmd->add_option("IMAGE1", o.image1, "first image (8-bit PNG, PGM, JPEG or BMP; colour becomes grey)")->required();
    cmd->add_option("IMAGE2", o.image2, "second image")->required();
    cmd->add_option("--rotation", o.rotation, "rotation searched, MIN:MAX degrees, +x towards +y (default -30:30)");
    cmd->add_option("--scale", o.scale, "scale searched, MIN:MAX (default 0.8:1.25)");
    cmd->add_option("--shift", o.shift,
                    "expected shift X:Y px: image 1's centre in image 2 minus image 2's centre (default 0:0)");
    cmd->add_option("--shift-range", o.shift_range_px, "half-width of the shifts searched around it, px (default 16)");
    cmd->add_flag("--intensity", o.intensity, "match grey levels instead of entropy images (one sensor)");
    cmd->add_option("--equalise-radius", o.equalise_radius_px,
                    "equalisation before the entropy: 0 over the whole image (flat products such as maps), 1.." +
                        std::to_string(entropy::kMaxEqualiseRadius) +
                        " px the rank within that radius (sensors whose response differs; default " +
                        std::to_string(o.equalise_radius_px) + ")");
    cmd->add_option("--out", o.out, "write G and the figures (text)");
    cmd->add_option("--entropy1", o.entropy1_png, "write image 1's matched (entropy) image, PNG");
    cmd->add_option("--entropy2", o.entropy2_png, "write image 2's matched (entropy) image, PNG");
    cmd->add_option("--matches", o.matches_png,
                    "write the match as a picture, PNG: image 1 and image 2 brought through G in alternate 32 px squares");
    return cmd;
}

int runRegister(const RegisterOptions& o) {
    entropy::RegistrationRequest request;
    const std::string bad = requestOf(o, request);
    if (!bad.empty()) return failCommand("register", kExitUsageError, bad);
    if (o.equalise_radius_px < 0 || o.equalise_radius_px > entropy::kMaxEqualiseRadius) {
        return failCommand("register", kExitUsageError, "--equalise-radius " + std::to_string(o.equalise_radius_px) +
                                         ": must be 0 (whole image) .. " + std::to_string(entropy::kMaxEqualiseRadius) +
                                         " px");
    }
    const ground::Result<ground::GreyImage> a = ground::loadGrey8(o.image1);
    if (!a.ok) return failCommand("register", kExitInputError, a.error);
    const ground::Result<ground::GreyImage> b = ground::loadGrey8(o.image2);
    if (!b.ok) return failCommand("register", kExitInputError, b.error);
    entropy::RegistrationConfig c;
    c.max_width = std::max(a.value.width, b.value.width);
    c.max_height = std::max(a.value.height, b.value.height);
    c.representation = o.intensity ? entropy::Representation::kIntensity : entropy::Representation::kEntropy;
    c.equalise_radius_px = o.equalise_radius_px;
    const Status valid = c.validate();
    if (!valid.isOk()) {
        return failCommand("register", kExitInputError, o.image1 + ", " + o.image2 + ": " + valid.reason() + " (" +
                                         std::to_string(valid.detail()) + ")");
    }
    std::vector<std::byte> pool(entropy::EntropyRegistration::workspaceBytes(c));
    Arena arena(pool.data(), pool.size());
    entropy::EntropyRegistration reg;
    const Status init = reg.init(c, arena);
    if (!init.isOk()) return failCommand("register", kExitInputError, std::string("EntropyRegistration::init: ") + init.reason());
    entropy::Registration r;
    const Status s = reg.registerImages(a.value.view(), b.value.view(), request, r);
    if (s.code() == StatusCode::kInvalidArgument || s.code() == StatusCode::kSizeMismatch) {
        return failCommand("register", kExitInputError, std::string(s.reason()) + " (" + o.image1 + ", " + o.image2 + ")");
    }
    const std::string text = report(o, r, s);
    std::fputs(text.c_str(), stdout);
    if (!o.out.empty()) {
        FILE* f = std::fopen(o.out.c_str(), "w");
        if (f == nullptr || std::fputs(text.c_str(), f) < 0 || std::fclose(f) != 0) {
            return failCommand("register", kExitInputError, o.out + ": cannot write");
        }
    }
    const std::string written = writeMatched(o, reg);
    if (!written.empty()) return failCommand("register", kExitInputError, written);
    if (!o.matches_png.empty()) {
        const ground::Outcome w = ground::writePng(o.matches_png, checkerboard(a.value, b.value, r.image2_from_image1));
        if (!w.ok) return failCommand("register", kExitInputError, w.error);
    }
    if (!s.isOk()) {
        return failCommand("register", kExitInputError, std::string("no registration: ") + s.reason() + " (" + o.image1 + ", " +
                                         o.image2 + ")");
    }
    return kExitOk;
}

}  // namespace vtm::tools
