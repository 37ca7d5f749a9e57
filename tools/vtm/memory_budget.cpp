#include "memory_budget.hpp"

#include "hal/event_log.hpp"
#include "hal/file/file_camera.hpp"
#include "hal/file/file_limits.hpp"
#include "hal/file/file_odometry.hpp"
#include "vtm/app/descent_mapper.hpp"
#include "vtm/app/terrain_integrator.hpp"
#include "vtm/app/wide_baseline_mapper.hpp"
#include "vtm/stereo/ml_stereo.hpp"

namespace vtm::tools {
namespace {

constexpr BudgetGroup kF = BudgetGroup::kFlight;
constexpr BudgetGroup kP = BudgetGroup::kPlaybackDriver;

// The dense stereo of the default flight configuration: a 1024 x 1024 Navcam-like pair,
// 128 disparities, default matcher settings (docs/stereo.md).
std::size_t flightStereoWorkspace() {
    stereo::Config c;
    c.max_width = 1024;
    c.max_height = 1024;
    c.d_min = 0;
    c.d_max = 127;
    return stereo::MlStereo::workspaceBytes(c);
}

// The lander's executive in its default configuration: 1024 x 1024 frames, 64 planes,
// window 11, a 512 x 512 elevation grid, refinement on (docs/app.md).
std::size_t flightDescentWorkspace() { return app::DescentMapper::workspaceBytes(app::DescentMapperConfig{}); }

// The rover's executive in its default configuration: 1024 x 1024 frames, 128
// disparities (conservative checks), a 512 x 512 height map (docs/app.md).
std::size_t flightWideBaselineWorkspace() {
    return app::WideBaselineMapper::workspaceBytes(app::WideBaselineMapperConfig{});
}

// The terrain integrator in its default configuration: a 128 m octree of 65,536 nodes,
// its height products, the 0.25 m registration grid and ICP (docs/integrator.md).
std::size_t flightIntegratorWorkspace() {
    return app::TerrainIntegrator::workspaceBytes(app::IntegratorConfig{});
}

const BudgetEntry kEntries[] = {
    {kF, "event log ring (hal::EventLog, 256 events)", "vtm_hal", sizeof(hal::EventLog)},
    {kF, "ML stereo workspace (1024x1024, 128 disparities)", "vtm_stereo", flightStereoWorkspace()},
    {kF, "descent mapper object (app::DescentMapper)", "vtm_app", sizeof(app::DescentMapper)},
    {kF, "descent mapper workspace (1024x1024, 64 planes)", "vtm_app", flightDescentWorkspace()},
    {kF, "wide-baseline mapper object (app::WideBaselineMapper)", "vtm_app", sizeof(app::WideBaselineMapper)},
    {kF, "wide-baseline mapper workspace (1024x1024, coarse to fine)", "vtm_app", flightWideBaselineWorkspace()},
    {kF, "terrain integrator object (app::TerrainIntegrator)", "vtm_app", sizeof(app::TerrainIntegrator)},
    {kF, "terrain integrator workspace (128 m octree, products, ICP)", "vtm_app", flightIntegratorWorkspace()},
    {kP, "hal::FileCamera (1024 frame records)", "vtm_hal_file", sizeof(hal::FileCamera)},
    {kP, "hal::FileOdometry (4096 poses)", "vtm_hal_file", sizeof(hal::FileOdometry)},
    {kP, "frame file buffer (shared)", "vtm_hal_file", hal::file_limits::kMaxFrameFileBytes},
    {kP, "PNG decoder pool (shared)", "vtm_hal_file", hal::file_limits::kPngPoolBytes},
};

}  // namespace

const BudgetEntry* memoryBudget(std::size_t* n) {
    *n = sizeof(kEntries) / sizeof(kEntries[0]);
    return kEntries;
}

std::size_t memoryBudgetTotal(BudgetGroup group) {
    std::size_t total = 0;
    for (const BudgetEntry& e : kEntries) {
        total += (e.group == group) ? e.bytes : 0U;
    }
    return total;
}

}  // namespace vtm::tools
