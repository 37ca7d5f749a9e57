// TerrainIntegrator: configuration, memory plan and initialisation (docs/integrator.md).
#include "vtm/app/terrain_integrator.hpp"

#include <new>

#include "request_support.hpp"
#include "vtm/core/config_check.hpp"

namespace vtm::app {
namespace {

// The registration grid: one mean product at registration_level.
octree::ProductConfig gridConfig(const IntegratorConfig& c) noexcept {
    octree::ProductConfig g;
    g.levels = {{c.registration_level, 0, 0, 0, 0, 0}};
    g.count = 1;
    g.reducer = terrain::Reducer::kMean;
    return g;
}

}  // namespace

icp::IcpConfig integratorIcpConfig() noexcept {
    // The module's defaults fit a model drawn at 0.2-0.25 m (min_gate_m a little over the
    // spacing, normals from 12 neighbours within 0.75 m); a model holds 64 m x 64 m of
    // 0.25 m bins, and 16,384 data points are enough for a 6-DOF fit.
    return icp::IcpConfig{};
}

Status IntegratorConfig::validate() const noexcept {
    VTM_RETURN_IF_ERROR(octree.validate());
    VTM_RETURN_IF_ERROR(products.validate(octree));
    VTM_RETURN_IF_ERROR(icp.validate());
    const std::int32_t top = octree.max_depth < octree::kMaxProductLevel ? octree.max_depth : octree::kMaxProductLevel;
    if (registration_level < 0 || registration_level > top) {
        return Status(StatusCode::kInvalidConfig,
                      "integrator.registration_level: outside 0..min(octree.max_depth, 12)", registration_level);
    }
    if (!isInRange(window_margin_m, 0.0, 1e4)) {
        return Status(StatusCode::kInvalidConfig, "integrator.window_margin_m: outside [0, 1e4]");
    }
    if (max_input_points < 1 || max_input_points > kMaxInputPointsLimit) {
        return Status(StatusCode::kInvalidConfig, "integrator.max_input_points: outside 1..2^24", max_input_points);
    }
    return Status::ok();
}

std::size_t TerrainIntegrator::workspaceBytes(const IntegratorConfig& config) noexcept {
    if (!config.validate().isOk()) {
        return 0U;
    }
    return octree::Octree::workspaceBytes(config.octree) +
           octree::HeightProducts::workspaceBytes(config.products, config.octree) +
           octree::HeightProducts::workspaceBytes(gridConfig(config), config.octree) +
           icp::PointToPlaneIcp::workspaceBytes(config.icp) +
           Arena::blockBytes(sizeof(Vec3) * static_cast<std::size_t>(config.icp.max_model_points),
                             Arena::kDefaultAlignment);
}

Status TerrainIntegrator::init(const IntegratorConfig& config, Arena& arena, const hal::Clock& clock,
                               hal::EventLog& events) noexcept {
    initialized_ = false;
    published_ = false;
    models_ = 0;
    VTM_RETURN_IF_ERROR(config.validate());
    config_ = config;
    clock_ = &clock;
    events_ = &events;
    VTM_RETURN_IF_ERROR(tree_.init(config.octree, arena));
    VTM_RETURN_IF_ERROR(products_.init(config.products, config.octree, arena));
    VTM_RETURN_IF_ERROR(grid_.init(gridConfig(config), config.octree, arena));
    VTM_RETURN_IF_ERROR(icp_.init(config.icp, arena));
    // Vec3 is not trivial (Arena::allocateArray refuses it): raw storage, constructed in place.
    const auto n = static_cast<std::size_t>(config.icp.max_model_points);
    void* block = arena.allocate(sizeof(Vec3) * n, Arena::kDefaultAlignment);
    if (block == nullptr) {
        return Status(StatusCode::kOutOfMemory, "integrator: arena too small for the ICP model buffer");
    }
    Vec3* points = static_cast<Vec3*>(block);
    for (std::size_t i = 0U; i < n; ++i) {  // bound: icp.max_model_points
        ::new (static_cast<void*>(points + i)) Vec3(0.0, 0.0, 0.0);
    }
    map_model_ = Span<Vec3>(points, n);
    stages_.clear();
    initialized_ = true;
    return Status::ok();
}

Status TerrainIntegrator::finish(Stage stage, const Status& status, std::int64_t quality,
                                 std::uint64_t t0_ns) noexcept {
    return detail::recordStage(stages_, *events_, *clock_, stage, status, quality, t0_ns);
}

}  // namespace vtm::app
