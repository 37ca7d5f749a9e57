// setModel(): the model's copy (float, relative to its bounding-box centre), its k-d tree
// and a normal per point from a plane fit to its neighbourhood.
#include <cmath>

#include "vtm/icp/icp.hpp"
#include "vtm/icp/symmetric_eigen.hpp"

namespace vtm::icp {
namespace {

// A neighbourhood is planar when its scatter's smallest eigenvalue is a small share of the
// total and clearly below the middle one (otherwise the normal's direction is undefined:
// a line, or an isotropic blob). The factor 4 is fixed: a config field would add a knob
// nobody tunes (docs/icp.md "Normals").
constexpr double kMinMiddleOverSmallest = 4.0;
constexpr std::int32_t kMinNormalSupport = 6;

}  // namespace

Status PointToPlaneIcp::setModel(Span<const Vec3> model_m) noexcept {
    hasModel_ = false;
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "PointToPlaneIcp::setModel: init() has not succeeded");
    }
    const std::size_t n = model_m.size();
    if (n > static_cast<std::size_t>(config_.max_model_points)) {
        return Status(StatusCode::kInvalidArgument, "icp.setModel: model has more points than max_model_points",
                      static_cast<std::int64_t>(n));
    }
    if (n < static_cast<std::size_t>(config_.min_correspondences)) {
        return Status(StatusCode::kInvalidArgument, "icp.setModel: model has fewer points than min_correspondences",
                      static_cast<std::int64_t>(n));
    }
    Vec3 lo = model_m[0];
    Vec3 hi = model_m[0];
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3& p = model_m[i];
        if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z()) || p.cwiseAbs().maxCoeff() > 1e7) {
            return Status(StatusCode::kCorruptData, "icp.setModel: model point not finite (or beyond 1e7 m)",
                          static_cast<std::int64_t>(i));
        }
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    origin_m_ = (lo + hi) * 0.5;
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3 d = model_m[i] - origin_m_;
        model_[i] = TreePoint{static_cast<float>(d.x()), static_cast<float>(d.y()), static_cast<float>(d.z())};
    }
    tree_.build(Span<const TreePoint>(model_.data(), n));
    computeNormals();
    if (normalCount_ < config_.min_correspondences) {
        return Status(StatusCode::kDegenerate, "icp.setModel: too few model points with a planar neighbourhood",
                      normalCount_);
    }
    hasModel_ = true;
    return Status::ok();
}

void PointToPlaneIcp::computeNormals() noexcept {
    normalCount_ = 0;
    const double radius2 = config_.normal_radius_m * config_.normal_radius_m;
    Neighbours nb;
    for (std::size_t i = 0; i < tree_.size(); ++i) {
        const TreePoint& q = model_[i];
        normals_[i] = TreePoint{0.0F, 0.0F, 0.0F};
        tree_.nearest(static_cast<double>(q.x), static_cast<double>(q.y), static_cast<double>(q.z),
                      config_.normal_neighbours, radius2, nb);
        if (nb.count < kMinNormalSupport) {
            continue;
        }
        Vec3 mean = Vec3::Zero();
        for (std::int32_t j = 0; j < nb.count; ++j) {
            const TreePoint& p = model_[static_cast<std::size_t>(nb.index[j])];
            mean += Vec3(static_cast<double>(p.x), static_cast<double>(p.y), static_cast<double>(p.z));
        }
        mean /= static_cast<double>(nb.count);
        Mat3 scatter = Mat3::Zero();
        for (std::int32_t j = 0; j < nb.count; ++j) {
            const TreePoint& p = model_[static_cast<std::size_t>(nb.index[j])];
            const Vec3 d = Vec3(static_cast<double>(p.x), static_cast<double>(p.y), static_cast<double>(p.z)) - mean;
            scatter += d * d.transpose();
        }
        Vec3 values;
        Mat3 vectors;
        symmetricEigen<3>(scatter, values, vectors);
        const double total = values.sum();
        if (!(total > 0.0) || values(0) > config_.max_surface_variation * total ||
            values(1) < kMinMiddleOverSmallest * values(0)) {
            continue;
        }
        Vec3 normal = vectors.col(0).normalized();
        if (normal.z() > 0.0) {
            normal = -normal;  // up in the z-down site frame: one sign for every target
        }
        normals_[i] = TreePoint{static_cast<float>(normal.x()), static_cast<float>(normal.y()),
                                static_cast<float>(normal.z())};
        ++normalCount_;
    }
}

}  // namespace vtm::icp
