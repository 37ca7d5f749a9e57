#include "memory_budget.hpp"

#include "hal/event_log.hpp"
#include "hal/file/file_camera.hpp"
#include "hal/file/file_limits.hpp"
#include "hal/file/file_odometry.hpp"

namespace vtm::tools {
namespace {

constexpr BudgetGroup kF = BudgetGroup::kFlight;
constexpr BudgetGroup kP = BudgetGroup::kPlaybackDriver;

const BudgetEntry kEntries[] = {
    {kF, "event log ring (hal::EventLog, 256 events)", "vtm_hal", sizeof(hal::EventLog)},
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
