// Configuration checks, the workspace formula and init() of the ICP.
#include <cmath>

#include "vtm/core/config_check.hpp"
#include "vtm/icp/icp.hpp"

namespace vtm::icp {
namespace {

Status validateCapacities(const IcpConfig& c) noexcept {
    if (c.max_model_points < 16 || c.max_model_points > kMaxModelPointsLimit) {
        return invalidConfig("icp.max_model_points: must be 16..1048576", c.max_model_points);
    }
    if (c.max_data_points < 16 || c.max_data_points > kMaxDataPointsLimit) {
        return invalidConfig("icp.max_data_points: must be 16..262144", c.max_data_points);
    }
    if (c.leaf_size < 2 || c.leaf_size > 64) {
        return invalidConfig("icp.leaf_size: must be 2..64", c.leaf_size);
    }
    if (c.max_leaves < 1 || c.max_leaves > 4096) {
        return invalidConfig("icp.max_leaves: must be 1..4096", c.max_leaves);
    }
    if (c.normal_neighbours < 6 || c.normal_neighbours > kMaxNeighbours) {
        return invalidConfig("icp.normal_neighbours: must be 6..32", c.normal_neighbours);
    }
    if (!isPositiveFinite(c.normal_radius_m)) {
        return invalidConfig("icp.normal_radius_m: must be > 0 (milli-metres in detail)", milliUnits(c.normal_radius_m));
    }
    if (!isPositiveFinite(c.max_surface_variation) || c.max_surface_variation > 1.0 / 3.0) {
        return invalidConfig("icp.max_surface_variation: must be in (0, 1/3] (milli in detail)", milliUnits(c.max_surface_variation));
    }
    return Status::ok();
}

Status validateFit(const IcpConfig& c) noexcept {
    if (!isPositiveFinite(c.min_gate_m)) {
        return invalidConfig("icp.min_gate_m: must be > 0 (milli-metres in detail)", milliUnits(c.min_gate_m));
    }
    if (!isPositiveFinite(c.initial_gate_m) || c.initial_gate_m < c.min_gate_m) {
        return invalidConfig("icp.initial_gate_m: must be >= min_gate_m (milli-metres in detail)", milliUnits(c.initial_gate_m));
    }
    if (!isPositiveFinite(c.gate_shrink) || c.gate_shrink > 1.0) {
        return invalidConfig("icp.gate_shrink: must be in (0, 1] (milli in detail)", milliUnits(c.gate_shrink));
    }
    if (!isPositiveFinite(c.huber_k)) {
        return invalidConfig("icp.huber_k: must be > 0 (milli in detail)", milliUnits(c.huber_k));
    }
    if (!isPositiveFinite(c.min_sigma_m)) {
        return invalidConfig("icp.min_sigma_m: must be > 0 (milli-metres in detail)", milliUnits(c.min_sigma_m));
    }
    if (c.max_iterations < 1 || c.max_iterations > 200) {
        return invalidConfig("icp.max_iterations: must be 1..200", c.max_iterations);
    }
    if (!isPositiveFinite(c.converge_rotation_rad)) {
        return invalidConfig("icp.converge_rotation_rad: must be > 0", milliUnits(c.converge_rotation_rad));
    }
    if (!isPositiveFinite(c.converge_translation_m)) {
        return invalidConfig("icp.converge_translation_m: must be > 0", milliUnits(c.converge_translation_m));
    }
    if (!isPositiveFinite(c.min_overlap) || c.min_overlap > 1.0) {
        return invalidConfig("icp.min_overlap: must be in (0, 1] (milli in detail)", milliUnits(c.min_overlap));
    }
    if (c.min_correspondences < 12 || c.min_correspondences > c.max_data_points) {
        return invalidConfig("icp.min_correspondences: must be 12..max_data_points", c.min_correspondences);
    }
    if (!isPositiveFinite(c.min_eigen_ratio) || c.min_eigen_ratio >= 1.0) {
        return invalidConfig("icp.min_eigen_ratio: must be in (0, 1) (milli in detail)", milliUnits(c.min_eigen_ratio));
    }
    return Status::ok();
}

}  // namespace

Status IcpConfig::validate() const noexcept {
    VTM_RETURN_IF_ERROR(validateCapacities(*this));
    return validateFit(*this);
}

std::size_t PointToPlaneIcp::workspaceBytes(const IcpConfig& config) noexcept {
    if (!config.validate().isOk()) {
        return 0U;
    }
    const auto model = static_cast<std::size_t>(config.max_model_points);
    const auto data = static_cast<std::size_t>(config.max_data_points);
    // Term by term, in the order init() carves them.
    return Arena::arrayBytes<TreePoint>(model)                  // model points (float, relative to the origin)
           + Arena::arrayBytes<TreePoint>(model)                // their normals
           + KdTree::workspaceBytes(model, config.leaf_size)    // permutation and splitting planes
           + Arena::arrayBytes<std::int32_t>(data)              // model index matched to each data point
           + Arena::arrayBytes<double>(data)                    // its point-to-plane residual
           + Arena::arrayBytes<double>(data);                   // |residuals| for the median
}

Status PointToPlaneIcp::init(const IcpConfig& config, Arena& arena) noexcept {
    initialized_ = false;
    hasModel_ = false;
    VTM_RETURN_IF_ERROR(config.validate());
    config_ = config;
    const auto model = static_cast<std::size_t>(config.max_model_points);
    const auto data = static_cast<std::size_t>(config.max_data_points);
    model_ = arena.allocateArray<TreePoint>(model);
    normals_ = arena.allocateArray<TreePoint>(model);
    const bool tree = tree_.init(model, config.leaf_size, config.max_leaves, arena);
    match_ = arena.allocateArray<std::int32_t>(data);
    residual_ = arena.allocateArray<double>(data);
    scratch_ = arena.allocateArray<double>(data);
    if (model_.size() != model || normals_.size() != model || !tree || match_.size() != data ||
        residual_.size() != data || scratch_.size() != data) {
        return Status(StatusCode::kOutOfMemory, "PointToPlaneIcp::init: arena smaller than workspaceBytes(config)",
                      static_cast<std::int64_t>(workspaceBytes(config)));
    }
    initialized_ = true;
    return Status::ok();
}

}  // namespace vtm::icp
