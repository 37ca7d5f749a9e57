#include "vtm/app/stage_log.hpp"

#include "vtm/core/assert.hpp"

namespace vtm::app {

const char* stageName(Stage stage) noexcept {
    switch (stage) {
        case Stage::kCapture1: return "capture1";
        case Stage::kPose1: return "pose1";
        case Stage::kCapture2: return "capture2";
        case Stage::kPose2: return "pose2";
        case Stage::kGeometry: return "geometry";
        case Stage::kRefine: return "refine";
        case Stage::kSweep: return "sweep";
        case Stage::kGrid: return "grid";
        case Stage::kRectify: return "rectify";
        case Stage::kStereo: return "stereo";
        case Stage::kTriangulate: return "triangulate";
        case Stage::kMapModel: return "mapmodel";
        case Stage::kRegister: return "register";
        case Stage::kInsert: return "insert";
        case Stage::kExtract: return "extract";
        case Stage::kLocate: return "locate";
        case Stage::kTiePoints: return "tiepoints";
        case Stage::kBundle: return "bundle";
        case Stage::kDense: return "dense";
        case Stage::kKrige: return "krige";
        case Stage::kOrthophoto: return "orthophoto";
        case Stage::kNone: break;
    }
    return "none";
}

void StageLog::add(const StageRecord& record) noexcept {
    VTM_ASSERT(count_ < kCapacity, static_cast<std::int64_t>(count_));
    if (count_ < kCapacity) {
        records_[count_] = record;
        ++count_;
    }
}

const StageRecord& StageLog::at(std::size_t i) const noexcept {
    VTM_ASSERT(i < count_, static_cast<std::int64_t>(i), static_cast<std::int64_t>(count_));
    return records_[i < kCapacity ? i : 0U];
}

const StageRecord* StageLog::failed() const noexcept {
    for (std::size_t i = 0U; i < count_; ++i) {
        if (!records_[i].status.isOk()) {
            return &records_[i];
        }
    }
    return nullptr;
}

std::uint64_t StageLog::totalNs() const noexcept {
    std::uint64_t sum = 0U;
    for (std::size_t i = 0U; i < count_; ++i) {
        sum += records_[i].duration_ns;
    }
    return sum;
}

}  // namespace vtm::app
