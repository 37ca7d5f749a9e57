// Determinism section "bundle" (fsw/bundle): a 6-station panorama network (tests/bundle's
// builder: vtm::math and vtm::Random only) with 3 % gross mismatches adjusted; every
// station's pose and covariance, every point's position and covariance, every residual and
// state, and the result's figures, hashed by bit pattern (little-endian bytes).
#include <cstdint>
#include <cstring>

#include "determinism_suite.hpp"
#include "panorama_network.hpp"
#include "vtm/bundle/bundle_adjuster.hpp"

namespace vtm::determinism {
namespace {

std::uint64_t fnv(std::uint64_t h, std::uint64_t v) noexcept {
    for (int i = 0; i < 8; ++i) {  // bound: 8 bytes, least significant first
        h ^= (v >> (8 * i)) & 0xFFU;
        h *= 0x100000001B3ULL;
    }
    return h;
}

std::uint64_t fnvDouble(std::uint64_t h, double d) noexcept {
    std::uint64_t bits = 0U;
    std::memcpy(&bits, &d, sizeof bits);
    return fnv(h, bits);
}

template <typename M>
std::uint64_t fnvMatrix(std::uint64_t h, const M& m) noexcept {
    for (Eigen::Index i = 0; i < m.size(); ++i) {  // bound: the matrix's size
        h = fnvDouble(h, m.data()[i]);
    }
    return h;
}

}  // namespace

std::uint64_t bundleSection() noexcept {
    bundle::test::NetworkSpec spec;
    spec.azimuths = 3;
    spec.hfov_deg = 100.0;
    spec.image_px = 256U;
    spec.candidate_points = 120;
    spec.outlier_fraction = 0.03;
    spec.seed = 77U;
    const bundle::test::Network net = bundle::test::makeNetwork(spec);
    bundle::BundleConfig c;
    c.max_stations = 6;
    c.max_points = 128;
    c.max_observations = 1024;
    static std::byte pool[1U << 20U];
    Arena arena(pool, sizeof pool);
    static bundle::BundleAdjuster adjuster;
    std::uint64_t h = 0xCBF29CE484222325ULL;
    h = fnv(h, static_cast<std::uint64_t>(adjuster.init(c, arena).code()));
    bundle::BundleResult r;
    const Status s = adjuster.adjust(Span<const NetworkStation>(net.approx.data(), net.approx.size()),
                                     Span<const TieObservation>(net.observations.data(), net.observations.size()),
                                     static_cast<std::uint32_t>(net.points_m.size()), r);
    h = fnv(h, static_cast<std::uint64_t>(s.code()));
    for (const bundle::StationSolution& st : adjuster.stations()) {
        h = fnvMatrix(h, st.site_from_a.R);
        h = fnvMatrix(h, st.site_from_a.t_m);
        h = fnvMatrix(h, st.covariance);
    }
    for (const bundle::PointSolution& p : adjuster.points()) {
        h = fnvMatrix(h, p.position_m);
        h = fnvMatrix(h, p.covariance);
        h = fnv(h, static_cast<std::uint64_t>(p.state) + (static_cast<std::uint64_t>(p.sightings) << 8U));
    }
    for (const bundle::ObservationResidual& o : adjuster.residuals()) {
        h = fnvMatrix(h, o.residual_px);
        h = fnvDouble(h, o.weight);
        h = fnv(h, static_cast<std::uint64_t>(o.state));
    }
    const std::int32_t counts[] = {r.points_adjusted, r.points_excluded, r.inliers, r.outliers, r.iterations, r.rounds,
                                   static_cast<std::int32_t>(r.stop)};
    for (const std::int32_t v : counts) {
        h = fnv(h, static_cast<std::uint64_t>(static_cast<std::int64_t>(v)));
    }
    const double figures[] = {r.rms_before_px, r.rms_after_px, r.sigma0, r.cost_before, r.cost_after};
    for (const double v : figures) {
        h = fnvDouble(h, v);
    }
    return h;
}

}  // namespace vtm::determinism
