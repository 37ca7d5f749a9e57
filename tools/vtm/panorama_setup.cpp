#include "panorama_setup.hpp"

#include <cmath>
#include <cstdio>

#include "vtm/ground/image_io.hpp"
#include "vtm/ground/pfm.hpp"
#include "vtm/ground/terrain_products.hpp"

namespace vtm::tools {

app::PanoramaMapperConfig panoramaMapperConfig(std::int32_t stations, std::int32_t ring_stations,
                                               std::int32_t width_px, std::int32_t height_px,
                                               const PanoramaGrid& grid) {
    app::PanoramaMapperConfig c;
    c.max_stations = stations;
    c.image_width = width_px;
    c.image_height = height_px;
    c.max_observations = 16384;
    c.ring_stations = ring_stations;
    c.range_min_m = 1.0;
    c.range_max_m = 80.0;
    if (std::max(width_px, height_px) < 512) {
        c.tiepoints.detector.grid_cols = c.tiepoints.detector.grid_rows = 8;
        c.tiepoints.detector.per_cell = 2;
        c.tiepoints.detector.max_features = 128;
        c.tiepoints.matcher.pyramid_levels = 1;
        c.tiepoints.intra_grid.cols = c.tiepoints.intra_grid.rows = 8;
        c.tiepoints.inter_grid.cols = c.tiepoints.inter_grid.rows = 8;
        c.tiepoints.parallax.max_radius_px = 50.0;
        c.tiepoints.map_side = 48;
        c.stereo.coarse_disparities = 64;
        c.stereo.coarse_window = 7;
        c.stereo.fine_radius_px = 4;
        c.stereo.matcher.window = 9;
    }
    const double cells = std::round(grid.extent_m / grid.cell_m);
    const std::int32_t side = cells >= 1.0 && cells <= 1.0e6 ? static_cast<std::int32_t>(cells) : 0;
    c.kriging.grid.cell_m = grid.cell_m;
    c.kriging.grid.cols = c.kriging.grid.rows = side;
    c.kriging.grid.north_edge_m = grid.centre_north_m + 0.5 * side * grid.cell_m;
    c.kriging.grid.west_edge_m = grid.centre_east_m - 0.5 * side * grid.cell_m;
    return c;
}

std::string writePanoramaRasters(const std::string& dir, const std::string& prefix, const app::PanoramaProducts& p,
                                 const StationImages& first) {
    const kriging::KrigedMap& map = *p.elevation;
    const terrain::GridConfig& g = map.grid();
    ground::FloatImage elevation(g.cols, g.rows, 1, std::nanf(""));
    ground::FloatImage variance(g.cols, g.rows, 1, std::nanf(""));
    ground::GreyImage ortho(g.cols, g.rows);
    for (std::int32_t r = 0; r < g.rows; ++r) {
        for (std::int32_t c = 0; c < g.cols; ++c) {
            elevation.at(c, r) = map.elevation(c, r);
            variance.at(c, r) = map.variance(c, r);
            ortho.at(c, r) = p.orthophoto.row(r)[c];
        }
    }
    ground::GreyImage left(first.left.width(), first.left.height());
    for (std::int32_t y = 0; y < left.height; ++y) {
        for (std::int32_t x = 0; x < left.width; ++x) left.at(x, y) = first.left.row(y)[x];
    }
    const std::string base = dir + "/" + prefix;
    ground::Outcome o = ground::writePfm(base + "elevation.pfm", elevation);
    if (o.ok) o = ground::writePng(base + "elevation.png", ground::shadedRelief(elevation, g.cell_m));
    if (o.ok) o = ground::writePfm(base + "variance.pfm", variance);
    if (o.ok) o = ground::writePng(base + "orthophoto.png", ortho);
    if (o.ok) o = ground::writePng(base + "left0.png", left);
    return o.ok ? "" : o.error;
}

std::string panoramaStageTable(const app::PanoramaMapper& mapper) {
    std::string head = "|", rule = "|", times = "|";
    char b[64];
    for (std::size_t i = 0; i < mapper.stages().size(); ++i) {
        head += std::string(" ") + app::stageName(mapper.stages().at(i).stage) + " |";
        rule += "---|";
        std::snprintf(b, sizeof b, " %.1f |", 1e-6 * static_cast<double>(mapper.stages().at(i).duration_ns));
        times += b;
    }
    return head + "\n" + rule + "\n" + times + "\n";
}

}  // namespace vtm::tools
