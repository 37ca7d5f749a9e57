// OrdinaryKriging: samples, the variogram of them, and the estimate at a node or a grid.
#include <cmath>

#include "vtm/kriging/kriging_system.hpp"
#include "vtm/kriging/ordinary_kriging.hpp"

namespace vtm::kriging {
namespace {

// The system of one node in covariance form, divided by the sill:
//   [C 1; 1' 0] [w; nu] = [c0; 1],  C_ij = C(|s_i - s_j|) / sill,  c0_i = C(|s_i - x|) / sill.
void fillSystem(const icp::Neighbours& nb, Span<const double> north_m, Span<const double> east_m, double node_north_m,
                double node_east_m, const Variogram& variogram, KrigingSystem& s,
                double (&c0)[kMaxSystemSize]) noexcept {
    const double sill = variogram.sillM2();
    const std::int32_t m = nb.count;
    s.n = m + 1;
    for (std::int32_t i = 0; i < m; ++i) {
        const auto si = static_cast<std::size_t>(nb.index[i]);
        for (std::int32_t j = i; j < m; ++j) {
            const auto sj = static_cast<std::size_t>(nb.index[j]);
            const double dn = north_m[si] - north_m[sj];
            const double de = east_m[si] - east_m[sj];
            const double c = variogram.covariance(std::sqrt(dn * dn + de * de)) / sill;
            s.a[i][j] = c;
            s.a[j][i] = c;
        }
        s.a[i][m] = 1.0;
        s.a[m][i] = 1.0;
        const double dn = north_m[si] - node_north_m;
        const double de = east_m[si] - node_east_m;
        c0[i] = variogram.covariance(std::sqrt(dn * dn + de * de)) / sill;
        s.b[i] = c0[i];
    }
    s.a[m][m] = 0.0;
    s.b[m] = 1.0;
}

bool usable(const Variogram& v) noexcept {
    return v.partial_sill_m2 > 0.0 && v.nugget_m2 >= 0.0 && v.range_m > 0.0 && std::isfinite(v.sillM2()) &&
           std::isfinite(v.range_m);
}

}  // namespace

Status OrdinaryKriging::init(const KrigingConfig& config, Arena& arena) noexcept {
    VTM_RETURN_IF_ERROR(config.validate());
    initialized_ = false;
    count_ = 0U;
    const auto n = static_cast<std::size_t>(config.max_samples);
    north_m_ = arena.allocateArray<double>(n);
    east_m_ = arena.allocateArray<double>(n);
    elevation_m_ = arena.allocateArray<double>(n);
    tree_points_ = arena.allocateArray<icp::TreePoint>(n);
    const bool tree_ok = tree_.init(n, config.tree_leaf_size, config.tree_max_leaves, arena);
    if (north_m_.size() != n || east_m_.size() != n || elevation_m_.size() != n || tree_points_.size() != n ||
        !tree_ok) {
        return Status(StatusCode::kOutOfMemory, "kriging: arena smaller than workspaceBytes(config)",
                      static_cast<std::int64_t>(workspaceBytes(config)));
    }
    VTM_RETURN_IF_ERROR(map_.init(config.grid, arena));
    config_ = config;
    initialized_ = true;
    return Status::ok();
}

Status OrdinaryKriging::setSamples(Span<const Vec3> site_m) noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "kriging: setSamples before init");
    }
    count_ = 0U;
    if (site_m.size() > static_cast<std::size_t>(config_.max_samples)) {
        return Status(StatusCode::kSizeMismatch, "kriging samples: more than max_samples",
                      static_cast<std::int64_t>(site_m.size()));
    }
    for (std::size_t i = 0; i < site_m.size(); ++i) {
        const Vec3& p = site_m[i];
        if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z())) {
            return Status(StatusCode::kInvalidArgument, "kriging samples: a sample is not finite (index in detail)",
                          static_cast<std::int64_t>(i));
        }
    }
    if (site_m.size() < static_cast<std::size_t>(config_.min_samples)) {
        return Status(StatusCode::kNoData, "kriging samples: fewer than min_samples",
                      static_cast<std::int64_t>(site_m.size()));
    }
    for (std::size_t i = 0; i < site_m.size(); ++i) {
        north_m_[i] = site_m[i].x();
        east_m_[i] = site_m[i].y();
        elevation_m_[i] = -site_m[i].z();
    }
    count_ = site_m.size();
    double n0 = 0.0, e0 = 0.0, n1 = 0.0, e1 = 0.0;
    boundingBox(n0, e0, n1, e1);
    origin_north_m_ = 0.5 * (n0 + n1);
    origin_east_m_ = 0.5 * (e0 + e1);
    for (std::size_t i = 0; i < count_; ++i) {
        tree_points_[i] = icp::TreePoint{static_cast<float>(north_m_[i] - origin_north_m_),
                                         static_cast<float>(east_m_[i] - origin_east_m_), 0.0F};
    }
    tree_.build(Span<const icp::TreePoint>(tree_points_.data(), count_));
    return Status::ok();
}

void OrdinaryKriging::boundingBox(double& n0, double& e0, double& n1, double& e1) const noexcept {
    n0 = n1 = count_ > 0U ? north_m_[0] : 0.0;
    e0 = e1 = count_ > 0U ? east_m_[0] : 0.0;
    for (std::size_t i = 1; i < count_; ++i) {
        n0 = north_m_[i] < n0 ? north_m_[i] : n0;
        n1 = north_m_[i] > n1 ? north_m_[i] : n1;
        e0 = east_m_[i] < e0 ? east_m_[i] : e0;
        e1 = east_m_[i] > e1 ? east_m_[i] : e1;
    }
}

double OrdinaryKriging::maxLagM() const noexcept {
    if (config_.variogram_max_lag_m > 0.0) {
        return config_.variogram_max_lag_m;
    }
    double n0 = 0.0, e0 = 0.0, n1 = 0.0, e1 = 0.0;
    boundingBox(n0, e0, n1, e1);
    const double dn = n1 - n0;
    const double de = e1 - e0;
    return 0.5 * std::sqrt(dn * dn + de * de);
}

Status OrdinaryKriging::experimental(ExperimentalVariogram& out) const noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "kriging: experimental variogram before init");
    }
    if (count_ == 0U) {
        return Status(StatusCode::kNoData, "kriging: experimental variogram without samples");
    }
    PairSampling sampling;
    sampling.bins = config_.variogram_bins;
    sampling.max_lag_m = maxLagM();
    sampling.max_pairs = config_.variogram_max_pairs;
    sampling.seed = config_.variogram_seed;
    if (!(sampling.max_lag_m > 0.0)) {
        return Status(StatusCode::kDegenerate, "kriging samples: all at one horizontal position");
    }
    return experimentalVariogram(Span<const double>(north_m_.data(), count_),
                                 Span<const double>(east_m_.data(), count_),
                                 Span<const double>(elevation_m_.data(), count_), sampling, out);
}

Status OrdinaryKriging::fitVariogram(Variogram& out) const noexcept {
    ExperimentalVariogram ev;
    VTM_RETURN_IF_ERROR(experimental(ev));
    return fitVariogramModel(ev, config_.model, config_.zero_nugget, config_.min_sill_m2, out);
}

Status OrdinaryKriging::estimateAt(double north_m, double east_m, const Variogram& variogram, NodeEstimate& out,
                                   bool* truncated) const noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "kriging: estimateAt before init");
    }
    if (count_ == 0U) {
        return Status(StatusCode::kNoData, "kriging: estimateAt without samples");
    }
    if (!std::isfinite(north_m) || !std::isfinite(east_m)) {
        return Status(StatusCode::kInvalidArgument, "kriging: estimate position not finite");
    }
    const double sill = variogram.sillM2();
    if (!usable(variogram)) {
        return Status(StatusCode::kInvalidArgument, "kriging: variogram needs partial sill > 0, nugget >= 0, range > 0");
    }
    out = NodeEstimate{};
    out.elevation_m = static_cast<double>(terrain::kNoData);
    out.variance_m2 = static_cast<double>(terrain::kNoData);
    icp::Neighbours nb;
    const double r = config_.search_radius_m;
    tree_.nearest(north_m - origin_north_m_, east_m - origin_east_m_, 0.0, config_.neighbours, r * r, nb);
    if (truncated != nullptr) {
        *truncated = nb.truncated;
    }
    out.neighbours = nb.count;
    if (nb.count == 0) {
        out.reason = NodeReason::kNoSamples;
        return Status::ok();
    }
    KrigingSystem s;
    double c0[kMaxSystemSize]{};
    fillSystem(nb, north_m_, east_m_, north_m, east_m, variogram, s, c0);
    const std::int32_t m = nb.count;
    double x[kMaxSystemSize]{};
    if (!solveKrigingSystem(s, x)) {
        out.reason = NodeReason::kSingular;
        return Status::ok();
    }
    double z = 0.0;
    double wc = 0.0;
    for (std::int32_t i = 0; i < m; ++i) {
        z += x[i] * elevation_m_[static_cast<std::size_t>(nb.index[i])];
        wc += x[i] * c0[i];
    }
    const double v = sill * (1.0 - wc - x[m]);
    out.elevation_m = z;
    out.variance_m2 = v > 0.0 ? v : 0.0;  // rounding below zero at a sample's position
    out.reason = NodeReason::kEstimated;
    return Status::ok();
}

Status OrdinaryKriging::krigeGrid(const Variogram& variogram, KrigingStats* stats) noexcept {
    return krigeGrid(config_.grid, variogram, stats);
}

Status OrdinaryKriging::krigeGrid(const terrain::GridConfig& grid, const Variogram& variogram,
                                  KrigingStats* stats) noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "kriging: krigeGrid before init");
    }
    VTM_RETURN_IF_ERROR(map_.setGrid(grid));
    KrigingStats st;
    for (std::int32_t row = 0; row < grid.rows; ++row) {
        for (std::int32_t col = 0; col < grid.cols; ++col) {
            NodeEstimate e;
            bool truncated = false;
            VTM_RETURN_IF_ERROR(estimateAt(map_.centreNorthM(row), map_.centreEastM(col), variogram, e, &truncated));
            map_.setNode(col, row, static_cast<float>(e.elevation_m), static_cast<float>(e.variance_m2), e.reason);
            st.estimated += e.reason == NodeReason::kEstimated ? 1 : 0;
            st.no_samples += e.reason == NodeReason::kNoSamples ? 1 : 0;
            st.singular += e.reason == NodeReason::kSingular ? 1 : 0;
            st.truncated += truncated ? 1 : 0;
        }
    }
    if (stats != nullptr) {
        *stats = st;
    }
    return Status::ok();
}

}  // namespace vtm::kriging
