// Per-stage records of one mapping request (issue 7): which stage ran, its Status, one
// quality figure and its time. The executives (DescentMapper, WideBaselineMapper,
// PanoramaMapper) fill a StageLog per request and mirror every record to hal::EventLog as one event:
//   id   = kEventStageBase + stage
//   args = {status code, status detail, quality, duration in microseconds}
// severity kInfo for a stage that succeeded, kError for the one that ended the request.
// docs/app.md lists the stages and what each quality figure is.
#pragma once

#include <cstddef>
#include <cstdint>

#include "vtm/core/status.hpp"

namespace vtm::app {

// Stable values: they are event ids (kEventStageBase + value) in telemetry.
enum class Stage : std::uint8_t {
    kNone = 0,
    // DescentMapper
    kCapture1 = 1,  // quality: frame sequence number
    kPose1 = 2,     // quality: position sigma, millimetres (sqrt of the covariance trace)
    kCapture2 = 3,
    kPose2 = 4,
    kGeometry = 5,  // quality: camera 1's height above the site datum, centimetres
    kRefine = 6,    // quality: inliers of the refined relative pose (failed: the matches found)
    kSweep = 7,     // quality: pixels with a depth
    kGrid = 8,      // quality: grid cells with an elevation (height map cells, WideBaselineMapper)
    // WideBaselineMapper (also kCapture1 .. kRefine and kGrid; geometry's quality there is
    // the baseline in millimetres)
    kRectify = 9,      // quality: convergence of the refined pair, centidegrees
    kStereo = 10,      // quality: pixels with a disparity
    kTriangulate = 11, // quality: points triangulated
    // TerrainIntegrator
    kMapModel = 12,    // quality: points of the ICP model drawn from the map
    kRegister = 13,    // quality: ICP correspondences at the final pose
    kInsert = 14,      // quality: samples inserted into the octree
    kExtract = 15,     // quality: bins with data in the finest product
    // DescentMapper, after refine (orbital.enabled)
    kLocate = 16,      // quality: frames of the pair located in the orbital map and used (0: the navigation's answer kept)
    // PanoramaMapper
    kTiePoints = 17,   // quality: tie points of the network (all rings)
    kBundle = 18,      // quality: image RMS after the adjustment, millipixels
    kDense = 19,       // quality: dense samples (sample cells kept)
    kKrige = 20,       // quality: elevation nodes estimated
    kOrthophoto = 21,  // quality: orthophoto nodes with a grey value
};
constexpr std::uint16_t kEventStageBase = 0x0A00U;

// "capture1", "pose1", ... ("none" for kNone and unknown values).
[[nodiscard]] const char* stageName(Stage stage) noexcept;

struct StageRecord {
    Stage stage = Stage::kNone;
    Status status{};              // its outcome (reason is a static string)
    std::int64_t quality = 0;     // per stage, see Stage
    std::uint64_t duration_ns = 0U;
};

class StageLog {
public:
    static constexpr std::size_t kCapacity = 16U;

    void clear() noexcept { count_ = 0U; }
    // Appends; a record beyond kCapacity is a programmer error (VTM_ASSERT).
    void add(const StageRecord& record) noexcept;
    [[nodiscard]] std::size_t size() const noexcept { return count_; }
    [[nodiscard]] const StageRecord& at(std::size_t i) const noexcept;
    // The record that ended the request (the first whose status is not ok), or nullptr.
    [[nodiscard]] const StageRecord* failed() const noexcept;
    // Sum of the recorded durations.
    [[nodiscard]] std::uint64_t totalNs() const noexcept;

private:
    StageRecord records_[kCapacity]{};
    std::size_t count_ = 0U;
};

}  // namespace vtm::app
