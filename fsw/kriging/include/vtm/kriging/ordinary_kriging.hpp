// Ordinary kriging of elevation samples into a grid (paper §3; docs/kriging.md).
//
// Samples are site points (x north, y east, z down, metres; elevation = -z), as stereo
// gives them. setSamples() copies them and builds a k-d tree over their horizontal
// positions (fsw/icp's KdTree); fitVariogram() fits the variogram (variogram.hpp);
// estimateAt() estimates the elevation of one horizontal position from its k nearest
// samples within search_radius_m by solving the (k+1)x(k+1) ordinary kriging system
// (covariance form, weights summing to one through a Lagrange multiplier, Gaussian
// elimination with partial pivoting); krigeGrid() does that for every node of the output
// grid. The grid is fsw/terrain's (GridConfig, vtm/terrain/height_map.hpp): node (col,
// row) is the centre of that cell, north = north_edge - (row + 0.5) cell, east =
// west_edge + (col + 0.5) cell.
//
// A node with no sample within the radius, or whose system is singular (samples at one
// position), is NO_DATA: elevation and variance kNoData (NaN) and a reason code.
// Memory from an Arena at init (workspaceBytes); setSamples, fitVariogram, estimateAt and
// krigeGrid never allocate. + - * / sqrt and vtm::math only: the same bits on every target.
#pragma once

#include <cstddef>
#include <cstdint>

#include "vtm/core/arena.hpp"
#include "vtm/core/eigen.hpp"
#include "vtm/core/span.hpp"
#include "vtm/core/status.hpp"
#include "vtm/icp/kd_tree.hpp"
#include "vtm/kriging/kriged_map.hpp"
#include "vtm/kriging/variogram.hpp"
#include "vtm/terrain/height_map.hpp"

namespace vtm::kriging {

// k of one estimate, at most: the system is at most (kMaxKrigingNeighbours + 1) square.
constexpr std::int32_t kMaxKrigingNeighbours = 16;
constexpr std::int32_t kMaxSamplesLimit = 1 << 20;

struct KrigingConfig {
    terrain::GridConfig grid{};        // the output grid (its cols * rows is the map's capacity)
    std::int32_t max_samples = 8192;   // capacity, 16..kMaxSamplesLimit
    std::int32_t min_samples = 16;     // fewer: kNoData refusal; 4..max_samples
    std::int32_t neighbours = 12;      // k, 3..kMaxKrigingNeighbours
    double search_radius_m = 5.0;      // > 0
    // Variogram.
    std::int32_t variogram_bins = 16;        // 4..kMaxVariogramBins
    double variogram_max_lag_m = 0.0;        // 0: half the diagonal of the samples' bounding box; else > 0
    std::int32_t variogram_max_pairs = 200000;  // pairs examined at most, 1000..10,000,000
    std::uint64_t variogram_seed = 1U;       // draws of the pair subsample (vtm::Random)
    ModelChoice model = ModelChoice::kBest;
    bool zero_nugget = false;                // fit with the nugget held at 0
    // Flat terrain: when the experimental semivariance stays below this, the minimum
    // variogram (exponential, nugget 0, sill min_sill_m2, range = max lag) is used.
    double min_sill_m2 = 1e-6;               // > 0 (1 mm^2 default)
    // Neighbour search (fsw/icp KdTree).
    std::int32_t tree_leaf_size = 8;         // 2..64
    std::int32_t tree_max_leaves = 256;      // leaves opened per query at most, 1..4096
    [[nodiscard]] Status validate() const noexcept;  // kInvalidConfig naming the field
};

// One estimate.
struct NodeEstimate {
    double elevation_m = 0.0;   // up; kNoData unless reason == kEstimated
    double variance_m2 = 0.0;   // kriging variance, m^2; kNoData unless kEstimated
    std::int32_t neighbours = 0;  // samples used
    NodeReason reason = NodeReason::kNoSamples;
};

struct KrigingStats {
    std::int32_t estimated = 0;   // nodes with an estimate
    std::int32_t no_samples = 0;  // nodes without a sample in the radius
    std::int32_t singular = 0;    // nodes whose system was singular
    std::int32_t truncated = 0;   // neighbour searches that hit tree_max_leaves (answer approximate)
};

class OrdinaryKriging {
public:
    // Bytes of arena for this configuration (docs/kriging.md "Memory"); 0 if invalid:
    //   samples: max_samples * 3 doubles (north, east, elevation) + max_samples TreePoints,
    //   the k-d tree (KdTree::workspaceBytes), the map (KrigedMap::workspaceBytes(grid)),
    //   each padded to the arena's block.
    [[nodiscard]] static std::size_t workspaceBytes(const KrigingConfig& config) noexcept;
    // kInvalidConfig, or kOutOfMemory when the arena cannot hold workspaceBytes.
    [[nodiscard]] Status init(const KrigingConfig& config, Arena& arena) noexcept;

    // Copies the samples (site frame, z down) and indexes them. kNotInitialized;
    // kSizeMismatch when there are more than max_samples; kInvalidArgument naming a
    // non-finite sample (detail = its index); kNoData when fewer than min_samples. A refused
    // call leaves no samples.
    [[nodiscard]] Status setSamples(Span<const Vec3> site_m) noexcept;

    // The experimental semivariogram of the samples (bins, pair subsample of the config).
    // kNotInitialized; kNoData without samples; kDegenerate when the samples span no
    // distance (all at one position).
    [[nodiscard]] Status experimental(ExperimentalVariogram& out) const noexcept;
    // The fitted model (docs/kriging.md "Variogram"): kDegenerate when fewer than three bins
    // hold kMinPairsPerBin pairs or no model fits with a positive sill; flat samples give the
    // minimum variogram with fallback = true (ok). Also refuses as experimental().
    [[nodiscard]] Status fitVariogram(Variogram& out) const noexcept;

    // Elevation and kriging variance at a horizontal site position. kNotInitialized; kNoData
    // without samples; kInvalidArgument for a non-finite position or a variogram without a
    // positive sill and range. A node without neighbours or with a singular system is not an
    // error: `out.reason` says so (elevation and variance kNoData).
    [[nodiscard]] Status estimateAt(double north_m, double east_m, const Variogram& variogram,
                                    NodeEstimate& out, bool* truncated = nullptr) const noexcept;
    // Every node of the config's grid into map() (or of `grid`, within the capacity:
    // kSizeMismatch beyond it). Refuses as estimateAt.
    [[nodiscard]] Status krigeGrid(const Variogram& variogram, KrigingStats* stats = nullptr) noexcept;
    [[nodiscard]] Status krigeGrid(const terrain::GridConfig& grid, const Variogram& variogram,
                                   KrigingStats* stats = nullptr) noexcept;

    [[nodiscard]] const KrigedMap& map() const noexcept { return map_; }
    [[nodiscard]] std::size_t sampleCount() const noexcept { return count_; }
    [[nodiscard]] const KrigingConfig& config() const noexcept { return config_; }

private:
    void boundingBox(double& n0, double& e0, double& n1, double& e1) const noexcept;
    [[nodiscard]] double maxLagM() const noexcept;
    KrigingConfig config_{};
    bool initialized_ = false;
    std::size_t count_ = 0U;
    double origin_north_m_ = 0.0;  // the tree's points are relative to this
    double origin_east_m_ = 0.0;
    Span<double> north_m_{};
    Span<double> east_m_{};
    Span<double> elevation_m_{};
    Span<icp::TreePoint> tree_points_{};
    icp::KdTree tree_{};
    KrigedMap map_{};
};

}  // namespace vtm::kriging
