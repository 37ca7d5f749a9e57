// KrigingConfig::validate and the workspace formula of OrdinaryKriging.
#include <cmath>

#include "vtm/core/config_check.hpp"
#include "vtm/kriging/ordinary_kriging.hpp"

namespace vtm::kriging {
namespace {

Status validateSamples(const KrigingConfig& c) noexcept {
    if (c.max_samples < 16 || c.max_samples > kMaxSamplesLimit) {
        return invalidConfig("kriging.max_samples: must be 16..1048576", c.max_samples);
    }
    if (c.min_samples < 4 || c.min_samples > c.max_samples) {
        return invalidConfig("kriging.min_samples: must be 4..max_samples", c.min_samples);
    }
    if (c.neighbours < 3 || c.neighbours > kMaxKrigingNeighbours) {
        return invalidConfig("kriging.neighbours: must be 3..16", c.neighbours);
    }
    if (!isPositiveFinite(c.search_radius_m)) {
        return invalidConfig("kriging.search_radius_m: must be > 0 (milli-metres in detail)", milliUnits(c.search_radius_m));
    }
    if (c.tree_leaf_size < 2 || c.tree_leaf_size > 64) {
        return invalidConfig("kriging.tree_leaf_size: must be 2..64", c.tree_leaf_size);
    }
    if (c.tree_max_leaves < 1 || c.tree_max_leaves > 4096) {
        return invalidConfig("kriging.tree_max_leaves: must be 1..4096", c.tree_max_leaves);
    }
    return Status::ok();
}

Status validateVariogram(const KrigingConfig& c) noexcept {
    if (c.variogram_bins < 4 || c.variogram_bins > kMaxVariogramBins) {
        return invalidConfig("kriging.variogram_bins: must be 4..64", c.variogram_bins);
    }
    if (!std::isfinite(c.variogram_max_lag_m) || c.variogram_max_lag_m < 0.0) {
        return invalidConfig("kriging.variogram_max_lag_m: must be 0 (automatic) or > 0 (milli-metres in detail)",
                       milliUnits(c.variogram_max_lag_m));
    }
    if (c.variogram_max_pairs < 1000 || c.variogram_max_pairs > 10000000) {
        return invalidConfig("kriging.variogram_max_pairs: must be 1000..10000000", c.variogram_max_pairs);
    }
    if (c.model != ModelChoice::kBest && c.model != ModelChoice::kSpherical && c.model != ModelChoice::kExponential) {
        return invalidConfig("kriging.model: must be best, spherical or exponential", static_cast<std::int64_t>(c.model));
    }
    if (!isPositiveFinite(c.min_sill_m2)) {
        return invalidConfig("kriging.min_sill_m2: must be > 0 (milli in detail)", milliUnits(c.min_sill_m2));
    }
    return Status::ok();
}

}  // namespace

Status KrigingConfig::validate() const noexcept {
    VTM_RETURN_IF_ERROR(grid.validate());
    VTM_RETURN_IF_ERROR(validateSamples(*this));
    return validateVariogram(*this);
}

std::size_t OrdinaryKriging::workspaceBytes(const KrigingConfig& config) noexcept {
    if (!config.validate().isOk()) {
        return 0U;
    }
    const auto n = static_cast<std::size_t>(config.max_samples);
    std::size_t bytes = 3U * Arena::arrayBytes<double>(n);          // north, east, elevation
    bytes += Arena::arrayBytes<icp::TreePoint>(n);                   // the tree's points
    bytes += icp::KdTree::workspaceBytes(n, config.tree_leaf_size);  // nodes and permutation
    bytes += KrigedMap::workspaceBytes(config.grid);                 // the output grid
    return bytes;
}

}  // namespace vtm::kriging
