// Determinism section "panorama" (sim/panorama.hpp): the true and approximate stations,
// the prior covariances and some cross-covariances of a small seeded panorama over an
// analytic plane, hashed by bit pattern (little-endian bytes, so byte order does not matter).
#include <cstdint>
#include <cstring>
#include <string_view>

#include "determinism_suite.hpp"
#include "vtm/core/hasher.hpp"
#include "sim/panorama.hpp"
#include "sim/scenario.hpp"
#include "vtm/core/arena.hpp"

namespace vtm::determinism {
namespace {

constexpr std::string_view kPanoramaText =
    "name det_panorama\nkind panorama\nseed 77\n"
    "[terrain]\nkind plane\nfinest_cell_m 1\nsamples_log2 4\nlevels 4\nplane_slope_north 0.04\n"
    "[camera]\nmodel pinhole\nwidth_px 64\nheight_px 48\nhfov_deg 60\nmount_position_m 0.3 0.1 -1.9\n"
    "[motion]\nstart_m 2 -1\nheading_deg 33\ncolumns 7\ntier_tilts_deg -12 -40 -65\n"
    "[pointing]\npan_sigma_deg 0.1\ntilt_sigma_deg 0.1\nmast_tilt_sigma_deg 0.2\nhead_offset_sigma_m 0.005\n"
    "rover_roll_sigma_deg 0.3\nrover_pitch_sigma_deg 0.3\nrover_heading_sigma_deg 1\n";

}  // namespace

std::uint64_t panoramaSection() noexcept {
    Hasher h;
    static sim::Scenario scenario;
    const Status parsed = sim::parseScenario(kPanoramaText, scenario);
    h.addU64(static_cast<std::uint64_t>(parsed.code()));
    static std::byte pool[1U << 20U];
    Arena arena(pool, sizeof pool);
    static sim::Terrain terrain;
    if (!parsed.isOk() || !sim::buildScenarioTerrain(scenario, arena, terrain).isOk()) {
        h.addU64(1U);
        return h.value();
    }
    static sim::Panorama panorama;
    const Status built = sim::buildPanorama(scenario, terrain, panorama);
    h.addU64(static_cast<std::uint64_t>(built.code()));
    for (std::int32_t k = 0; built.isOk() && k < panorama.count; ++k) {  // bound: <= kMaxPanoramaStations
        const sim::PanoramaStation& s = panorama.stations[k];
        h.addPose(s.truth.site_from_a);
        h.addPose(s.approx.site_from_a);
        for (int i = 0; i < 36; ++i) {  // bound: 6x6
            h.addDouble(s.approx.prior_covariance(i / 6, i % 6));
        }
    }
    for (std::int32_t k = 1; built.isOk() && k < panorama.count; k += 5) {  // bound: <= kMaxPanoramaStations / 5
        const Mat6 cross = sim::panoramaCrossCovariance(scenario, panorama, 0, k);
        for (int i = 0; i < 36; ++i) {  // bound: 6x6
            h.addDouble(cross(i / 6, i % 6));
        }
    }
    return h.value();
}

}  // namespace vtm::determinism
