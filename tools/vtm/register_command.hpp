// `vtm register IMG1 IMG2 [--rotation MIN:MAX] [--scale MIN:MAX] [--shift X:Y]
// [--shift-range PX] [--intensity] [--equalise-radius PX] [--out FILE] [--entropy1 PNG]
// [--entropy2 PNG] [--matches PNG]`: the
// multi-modal registration (fsw/entropy) run on the ground on two images of one place taken
// by different sensors; prints and writes the similarity image 1 -> image 2
// (docs/entropy.md "Command line").
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "vtm/entropy/registration.hpp"

namespace vtm::tools {

struct RegisterOptions {
    std::string image1;             // 8-bit PNG, PGM, JPEG or BMP (colour becomes grey)
    std::string image2;
    std::string rotation = "-30:30";  // degrees, image 1 -> image 2, +x towards +y
    std::string scale = "0.8:1.25";
    std::string shift = "0:0";        // expected t: image 1's centre in image 2 minus image 2's centre, px
    double shift_range_px = 16.0;     // half-width of the square of t searched, px
    bool intensity = false;           // match grey levels instead of entropy images (same sensor)
    // The module's equalisation (docs/entropy.md): 0 whole image, 1..kMaxEqualiseRadius local.
    int equalise_radius_px = entropy::RegistrationConfig{}.equalise_radius_px;
    std::string out;                  // the 2x3 matrix and the figures (text)
    std::string entropy1_png;         // the entropy images (docs: the paper's Fig. 12)
    std::string entropy2_png;
    std::string matches_png;          // image 1 and image 2 through G as a checkerboard (the paper's Fig. 13)
};

CLI::App* addRegisterCommand(CLI::App& app, RegisterOptions& options);
// Runs it; returns the exit code (exit_codes.hpp): 0 registered, 1 an input error or no
// answer (the module's refusal, named), 2 a malformed range.
int runRegister(const RegisterOptions& options);

}  // namespace vtm::tools
