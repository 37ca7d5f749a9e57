// KrigingConfig::validate and the workspace formula of OrdinaryKriging.
#include <cmath>

#include "vtm/kriging/ordinary_kriging.hpp"

namespace vtm::kriging {
namespace {

Status invalid(const char* reason, std::int64_t value) noexcept {
    return Status(StatusCode::kInvalidConfig, reason, value);
}

bool positive(double v) noexcept { return std::isfinite(v) && v > 0.0; }

// Milli-units of a double field for the detail.
std::int64_t milli(double v) noexcept {
    return std::isfinite(v) && std::fabs(v) < 1e15 ? static_cast<std::int64_t>(v * 1000.0) : -1;
}

Status validateSamples(const KrigingConfig& c) noexcept {
    if (c.max_samples < 16 || c.max_samples > kMaxSamplesLimit) {
        return invalid("kriging.max_samples: must be 16..1048576", c.max_samples);
    }
    if (c.min_samples < 4 || c.min_samples > c.max_samples) {
        return invalid("kriging.min_samples: must be 4..max_samples", c.min_samples);
    }
    if (c.neighbours < 3 || c.neighbours > kMaxKrigingNeighbours) {
        return invalid("kriging.neighbours: must be 3..16", c.neighbours);
    }
    if (!positive(c.search_radius_m)) {
        return invalid("kriging.search_radius_m: must be > 0 (milli-metres in detail)", milli(c.search_radius_m));
    }
    if (c.tree_leaf_size < 2 || c.tree_leaf_size > 64) {
        return invalid("kriging.tree_leaf_size: must be 2..64", c.tree_leaf_size);
    }
    if (c.tree_max_leaves < 1 || c.tree_max_leaves > 4096) {
        return invalid("kriging.tree_max_leaves: must be 1..4096", c.tree_max_leaves);
    }
    return Status::ok();
}

Status validateVariogram(const KrigingConfig& c) noexcept {
    if (c.variogram_bins < 4 || c.variogram_bins > kMaxVariogramBins) {
        return invalid("kriging.variogram_bins: must be 4..64", c.variogram_bins);
    }
    if (!std::isfinite(c.variogram_max_lag_m) || c.variogram_max_lag_m < 0.0) {
        return invalid("kriging.variogram_max_lag_m: must be 0 (automatic) or > 0 (milli-metres in detail)",
                       milli(c.variogram_max_lag_m));
    }
    if (c.variogram_max_pairs < 1000 || c.variogram_max_pairs > 10000000) {
        return invalid("kriging.variogram_max_pairs: must be 1000..10000000", c.variogram_max_pairs);
    }
    if (c.model != ModelChoice::kBest && c.model != ModelChoice::kSpherical && c.model != ModelChoice::kExponential) {
        return invalid("kriging.model: must be best, spherical or exponential", static_cast<std::int64_t>(c.model));
    }
    if (!positive(c.min_sill_m2)) {
        return invalid("kriging.min_sill_m2: must be > 0 (milli in detail)", milli(c.min_sill_m2));
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
