// TerrainIntegrator: one model per request, checked, registered to the map, inserted
// (docs/integrator.md).
#include "vtm/app/terrain_integrator.hpp"

#include "vtm/core/math.hpp"

namespace vtm::app {
namespace {

constexpr double kRotationTolerance = 1e-6;

bool finitePoint(const Vec3& p) noexcept {
    return math::isFinite(p.x()) && math::isFinite(p.y()) && math::isFinite(p.z());
}

// Angle of Ra Rb^T, radians (atan2 of the half skew vector's norm and the half trace - 1/2).
double rotationBetweenRad(const Mat3& a, const Mat3& b) noexcept {
    const Mat3 d = a * b.transpose();
    const Vec3 v(d(2, 1) - d(1, 2), d(0, 2) - d(2, 0), d(1, 0) - d(0, 1));
    return math::atan2(0.5 * math::sqrt(v.dot(v)), 0.5 * (d.trace() - 1.0));
}

Status checkFootprintRule(const FootprintRule& f, std::size_t points) noexcept {
    switch (f.kind) {
        case FootprintKind::kFixed:
            if (!(math::isFinite(f.footprint_m) && f.footprint_m > 0.0)) {
                return Status(StatusCode::kInvalidArgument, "integrator: footprint.footprint_m not finite and > 0");
            }
            return Status::ok();
        case FootprintKind::kPerPoint:
            if (f.per_point_m.size() != points) {
                return Status(StatusCode::kSizeMismatch, "integrator: footprint.per_point_m size differs from points",
                              static_cast<std::int64_t>(f.per_point_m.size()));
            }
            return Status::ok();
        case FootprintKind::kRangeTimesAngle:
            if (!(math::isFinite(f.pixel_angle_rad) && f.pixel_angle_rad > 0.0) || !finitePoint(f.sensor_m)) {
                return Status(StatusCode::kInvalidArgument,
                              "integrator: footprint.pixel_angle_rad not finite and > 0, or sensor_m not finite");
            }
            return Status::ok();
    }
    return Status(StatusCode::kInvalidArgument, "integrator: footprint.kind unknown", static_cast<std::int64_t>(f.kind));
}

}  // namespace

double TerrainIntegrator::footprintOf(const ModelInput& model, std::size_t i) const noexcept {
    const FootprintRule& f = model.footprint;
    if (f.kind == FootprintKind::kPerPoint) {
        return static_cast<double>(f.per_point_m[i]);
    }
    if (f.kind == FootprintKind::kRangeTimesAngle) {
        const Vec3 d = model.points_m[i] - f.sensor_m;
        return math::sqrt(d.dot(d)) * f.pixel_angle_rad;
    }
    return f.footprint_m;
}

// Everything about the input that can be checked before anything changes; the points'
// centroid (model frame) for the correction figure.
Status TerrainIntegrator::checkInput(const ModelInput& model, Vec3& centroid_m) const noexcept {
    const std::size_t n = model.points_m.size();
    if (n == 0U || n > static_cast<std::size_t>(config_.max_input_points)) {
        return Status(StatusCode::kInvalidArgument, "integrator: points empty or more than max_input_points",
                      static_cast<std::int64_t>(n));
    }
    VTM_RETURN_IF_ERROR(checkRigidPose(model.map_from_model_guess, kRotationTolerance,
                                       "integrator: map_from_model_guess not a rotation or not finite"));
    if (model.source >= octree::kMaxSources) {
        return Status(StatusCode::kInvalidArgument, "integrator: source >= 16", model.source);
    }
    VTM_RETURN_IF_ERROR(checkFootprintRule(model.footprint, n));
    Vec3 sum = Vec3::Zero();
    for (std::size_t i = 0U; i < n; ++i) {  // bound: max_input_points
        if (!finitePoint(model.points_m[i])) {
            return Status(StatusCode::kCorruptData, "integrator: a point is not finite", static_cast<std::int64_t>(i));
        }
        const double f = footprintOf(model, i);
        if (!(math::isFinite(f) && f > 0.0)) {
            return Status(StatusCode::kInvalidArgument, "integrator: a point's footprint is not finite and > 0",
                          static_cast<std::int64_t>(i));
        }
        sum += model.points_m[i];
    }
    centroid_m = sum / static_cast<double>(n);
    return Status::ok();
}

Status TerrainIntegrator::addModel(const ModelInput& model, AddResult& result) noexcept {
    result = AddResult{};
    result.map_from_model = model.map_from_model_guess;
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "integrator: addModel before init");
    }
    stages_.clear();
    published_ = false;
    Vec3 centroid = Vec3::Zero();
    VTM_RETURN_IF_ERROR(checkInput(model, centroid));
    const bool register_it = model.register_model && tree_.stats().inserted > 0;
    if (register_it) {
        std::uint64_t t0 = clock_->monotonicNs();
        std::int32_t map_points = 0;
        const Status drawn = finish(Stage::kMapModel, drawMapModel(model, map_points), map_points, t0);
        result.map_model_points = map_points;
        VTM_RETURN_IF_ERROR(drawn);
        t0 = clock_->monotonicNs();
        const Status fit = registerModel(model, map_points, result);
        VTM_RETURN_IF_ERROR(finish(Stage::kRegister, fit, result.icp.correspondences, t0));
        const RigidPose& g = model.map_from_model_guess;
        const RigidPose& r = result.map_from_model;
        result.correction_rad = rotationBetweenRad(r.R, g.R);
        const Vec3 moved = (r.R * centroid + r.t_m) - (g.R * centroid + g.t_m);
        result.correction_m = math::sqrt(moved.dot(moved));
    }
    const std::uint64_t t0 = clock_->monotonicNs();
    const Status inserted = insertModel(model, result);
    ++models_;
    return finish(Stage::kInsert, inserted, result.inserted, t0);
}

Status TerrainIntegrator::registerModel(const ModelInput& model, std::int32_t map_points, AddResult& result) noexcept {
    VTM_RETURN_IF_ERROR(icp_.setModel(Span<const Vec3>(map_model_.data(), static_cast<std::size_t>(map_points))));
    VTM_RETURN_IF_ERROR(icp_.registerData(model.points_m, model.map_from_model_guess, result.icp));
    result.map_from_model = result.icp.model_from_data;
    result.registered = true;
    return Status::ok();
}

// Every point, moved by result.map_from_model, into the octree at its footprint's level.
// Points outside the cube are counted and skipped; a full pool is reported after the rest.
Status TerrainIntegrator::insertModel(const ModelInput& model, AddResult& result) noexcept {
    const RigidPose& pose = result.map_from_model;
    const std::size_t n = model.points_m.size();
    for (std::size_t i = 0U; i < n; ++i) {  // bound: max_input_points (checkInput)
        octree::Sample s;
        s.site_m = pose.R * model.points_m[i] + pose.t_m;
        s.footprint_m = footprintOf(model, i);
        s.source = model.source;
        const Status st = tree_.insert(s);
        if (st.isOk()) {
            ++result.inserted;
        } else if (st.code() == StatusCode::kOutOfMemory) {
            ++result.refused_pool_full;
        } else {
            ++result.refused_outside;  // the only other refusal left after checkInput
        }
    }
    if (result.refused_pool_full > 0) {
        return Status(StatusCode::kOutOfMemory, "integrator: the octree's node pool refused samples",
                      result.refused_pool_full);
    }
    return Status::ok();
}

Status TerrainIntegrator::extractProducts() noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "integrator: extractProducts before init");
    }
    stages_.clear();
    const std::uint64_t t0 = clock_->monotonicNs();
    const Status st = products_.extract(tree_);
    const std::int32_t last = products_.count() - 1;
    const std::int64_t filled = st.isOk() ? products_.map(last).filledCells() : 0;
    published_ = st.isOk();
    return finish(Stage::kExtract, st, filled, t0);
}

}  // namespace vtm::app
