// TerrainIntegrator, stage mapmodel: the ICP model drawn from the map (docs/integrator.md
// "The ICP model drawn from the map").
//
// The registration grid is a mean height map at registration_level (finest data wins, as
// every product). Inside the window (the model's guessed (x, y) bounding box grown by
// window_margin_m) a bin made by samples at least as fine as itself gives one point: its
// centre and minus its mean elevation. A bin filled from a coarser level l gives nothing
// unless it is the bin at the centre of its level-l cell (col and row = k/2 mod k, k =
// 2^(registration_level - l)), which gives the coarse cell's centre: so a coarse source
// appears at its own spacing, not as a staircase of copies. More than icp.max_model_points
// candidates are thinned by an integer stride (every s-th in row-major order).
#include "vtm/app/terrain_integrator.hpp"

#include <cmath>

namespace vtm::app {
namespace {

struct Window {
    std::int32_t col0, col1, row0, row1;  // inclusive bin ranges
};

std::int32_t clampIndex(double v, std::int32_t hi) noexcept {
    if (!(v > 0.0)) {
        return 0;
    }
    return v >= static_cast<double>(hi) ? hi : static_cast<std::int32_t>(v);
}

// The bins of `grid` under the model's points moved by the guess, grown by margin_m.
Window windowOf(const ModelInput& model, const terrain::GridConfig& grid, double margin_m) noexcept {
    const RigidPose& g = model.map_from_model_guess;
    double n_lo = 0.0, n_hi = 0.0, e_lo = 0.0, e_hi = 0.0;
    for (std::size_t i = 0U; i < model.points_m.size(); ++i) {  // bound: max_input_points
        const Vec3 p = g.R * model.points_m[i] + g.t_m;
        n_lo = (i == 0U || p.x() < n_lo) ? p.x() : n_lo;
        n_hi = (i == 0U || p.x() > n_hi) ? p.x() : n_hi;
        e_lo = (i == 0U || p.y() < e_lo) ? p.y() : e_lo;
        e_hi = (i == 0U || p.y() > e_hi) ? p.y() : e_hi;
    }
    Window w{};
    w.col0 = clampIndex(std::floor((e_lo - margin_m - grid.west_edge_m) / grid.cell_m), grid.cols - 1);
    w.col1 = clampIndex(std::floor((e_hi + margin_m - grid.west_edge_m) / grid.cell_m), grid.cols - 1);
    w.row0 = clampIndex(std::floor((grid.north_edge_m - (n_hi + margin_m)) / grid.cell_m), grid.rows - 1);
    w.row1 = clampIndex(std::floor((grid.north_edge_m - (n_lo - margin_m)) / grid.cell_m), grid.rows - 1);
    return w;
}

}  // namespace

Status TerrainIntegrator::drawMapModel(const ModelInput& model, std::int32_t& count) noexcept {
    count = 0;
    VTM_RETURN_IF_ERROR(grid_.extract(tree_));
    const terrain::HeightMap& reg_map = grid_.map(0);
    const terrain::GridConfig& grid = reg_map.grid();
    const Window w = windowOf(model, grid, config_.window_margin_m);
    const auto level = static_cast<std::uint32_t>(config_.registration_level);
    // Pass 0 counts the candidates, pass 1 takes every stride-th. Bound: 2 x the window's
    // bins (<= 4^registration_level).
    std::int64_t candidates = 0;
    std::int64_t stride = 1;
    for (std::int32_t pass = 0; pass < 2; ++pass) {
        std::int64_t seen = 0;
        for (std::int32_t row = w.row0; row <= w.row1; ++row) {
            for (std::int32_t col = w.col0; col <= w.col1; ++col) {
                const std::uint8_t data = grid_.dataLevel(0, col, row);
                if (data == octree::kNoLevel) {
                    continue;
                }
                const bool own = data >= level;
                const std::int32_t k = own ? 1 : static_cast<std::int32_t>(1U << (level - std::uint32_t{data}));
                if (!own && ((col % k) != k / 2 || (row % k) != k / 2)) {
                    continue;
                }
                if (pass == 1 && seen % stride == 0 && count < config_.icp.max_model_points) {
                    // Own data: the bin's centre; coarse: the coarse cell's centre, the bin's
                    // north-west corner.
                    const double north = own ? reg_map.centreNorthM(row) : grid.north_edge_m - static_cast<double>(row) * grid.cell_m;
                    const double east = own ? reg_map.centreEastM(col) : grid.west_edge_m + static_cast<double>(col) * grid.cell_m;
                    map_model_[static_cast<std::size_t>(count)] =
                        Vec3(north, east, -static_cast<double>(reg_map.elevation(col, row)));
                    ++count;
                }
                ++seen;
            }
        }
        candidates = seen;
        const std::int64_t cap = config_.icp.max_model_points;
        stride = (candidates + cap - 1) / cap;
        stride = stride < 1 ? 1 : stride;
    }
    if (count < config_.icp.min_correspondences) {
        return Status(StatusCode::kNoData, "integrator: too little of the map under the model", count);
    }
    return Status::ok();
}

}  // namespace vtm::app
