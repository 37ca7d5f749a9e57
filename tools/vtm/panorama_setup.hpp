// What `vtm run`'s panorama (run_panorama.cpp) and `vtm panorama` (panorama_command.cpp)
// share: the executive's configuration for a panorama of given eyes and grid, its raster
// products on disk and the stage-time table of a report. Library vtm_panorama_setup (the
// tests run the executive in process with the same configuration).
#pragma once

#include <cstdint>
#include <string>

#include "vtm/app/panorama_mapper.hpp"
#include "vtm/core/image_network.hpp"

namespace vtm::tools {

// The elevation grid: a square of extent_m around (centre_north_m, centre_east_m), site
// frame, cell_m cells (the side rounded to whole cells).
struct PanoramaGrid {
    double cell_m = 0.25;
    double extent_m = 20.0;
    double centre_north_m = 0.0;
    double centre_east_m = 0.0;
};

// The executive's configuration (docs/panorama-cli.md "Configuration"): the flight defaults
// (docs/app.md) for eyes of 512 px and more; smaller eyes get the small detector grid, one
// matcher level and small stereo windows (as tests/app/panorama_mapper_test.cpp). Ranges
// 1..80 m unless changed by the caller; ring_stations as given (0: one ring).
app::PanoramaMapperConfig panoramaMapperConfig(std::int32_t stations, std::int32_t ring_stations,
                                               std::int32_t width_px, std::int32_t height_px,
                                               const PanoramaGrid& grid);

// Into dir: <prefix>elevation.pfm (kriged, metres up, NaN = no estimate), <prefix>elevation.png
// (shaded relief), <prefix>variance.pfm (kriging variance, m^2), <prefix>orthophoto.png and
// <prefix>left0.png (the first station's left eye). "" or the error naming the file.
std::string writePanoramaRasters(const std::string& dir, const std::string& prefix, const app::PanoramaProducts& p,
                                 const StationImages& first);

// "| tiepoints | bundle | ... |" with the stages' milliseconds (Markdown table, 3 lines).
std::string panoramaStageTable(const app::PanoramaMapper& mapper);

}  // namespace vtm::tools
