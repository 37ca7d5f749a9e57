// Determinism section "bundle" (fsw/bundle): a 6-station panorama network (tests/bundle's
// builder: vtm::math and vtm::Random only) with 3 % gross mismatches adjusted; every
// station's pose and covariance, every point's position and covariance, every residual and
// state, and the result's figures, hashed by bit pattern (little-endian bytes).
#include <cstdint>
#include <cstring>

#include "determinism_suite.hpp"
#include "vtm/core/hasher.hpp"
#include "panorama_network.hpp"
#include "vtm/bundle/bundle_adjuster.hpp"

namespace vtm::determinism {
namespace {

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
    Hasher h;
    h.addU64(static_cast<std::uint64_t>(adjuster.init(c, arena).code()));
    bundle::BundleResult r;
    const Status s = adjuster.adjust(Span<const NetworkStation>(net.approx.data(), net.approx.size()),
                                     Span<const TieObservation>(net.observations.data(), net.observations.size()),
                                     static_cast<std::uint32_t>(net.points_m.size()), r);
    h.addU64(static_cast<std::uint64_t>(s.code()));
    for (const bundle::StationSolution& st : adjuster.stations()) {
        h.addMatrix(st.site_from_a.R);
        h.addMatrix(st.site_from_a.t_m);
        h.addMatrix(st.covariance);
    }
    for (const bundle::PointSolution& p : adjuster.points()) {
        h.addMatrix(p.position_m);
        h.addMatrix(p.covariance);
        h.addU64(static_cast<std::uint64_t>(p.state) + (static_cast<std::uint64_t>(p.sightings) << 8U));
    }
    for (const bundle::ObservationResidual& o : adjuster.residuals()) {
        h.addMatrix(o.residual_px);
        h.addDouble(o.weight);
        h.addU64(static_cast<std::uint64_t>(o.state));
    }
    const std::int32_t counts[] = {r.points_adjusted, r.points_excluded, r.inliers, r.outliers, r.iterations, r.rounds,
                                   static_cast<std::int32_t>(r.stop)};
    for (const std::int32_t v : counts) {
        h.addU64(static_cast<std::uint64_t>(static_cast<std::int64_t>(v)));
    }
    const double figures[] = {r.rms_before_px, r.rms_after_px, r.sigma0, r.cost_before, r.cost_after};
    for (const double v : figures) {
        h.addDouble(v);
    }
    return h.value();
}

}  // namespace vtm::determinism
