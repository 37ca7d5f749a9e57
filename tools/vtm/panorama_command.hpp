// `vtm panorama STATIONS_FILE --out DIR [--cell M] [--extent M] [--centre N:E] [--ring N]
// [--no-dense] [--range MIN:MAX] [--site LAT:LON]`: the mast panorama's executive
// app::PanoramaMapper (fsw/app, docs/app.md) on the user's files: a vtm-panorama-stations 1
// file (docs/panorama-cli.md; `vtm-sim render` writes one for a panorama scenario) naming
// the rig's camera models and every station's two images, approximate pose and pointing
// prior. Products: the kriged elevation map (GeoTIFF and PFM), its kriging variance, the
// orthophoto, the adjusted poses, the tie points and a report. Host only (GDAL).
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace vtm::tools {

struct PanoramaOptions {
    std::string stations;          // the vtm-panorama-stations 1 file
    std::string out_dir;
    double cell_m = 0.25;          // elevation grid cell
    double extent_m = 20.0;        // elevation grid side
    std::string centre;            // "N:E" site metres; default: the mean of the approximate left eyes
    int ring = -1;                 // stations per ring; -1: the file's columns, else one ring
    bool no_dense = false;         // krige the tie points alone
    std::string range = "1:80";    // terrain range along a ray, metres
    std::string site = "0:0";      // site origin (GeoTIFF), planetocentric latitude:east longitude
};

CLI::App* addPanoramaCommand(CLI::App& app, PanoramaOptions& options);
// The exit code (exit_codes.hpp): 0 mapped, 1 an input error or a stage that failed (named),
// 2 a malformed option.
int runPanorama(const PanoramaOptions& options);

}  // namespace vtm::tools
