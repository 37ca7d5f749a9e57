// libFuzzer target (8): the panorama stations file (tools/ground panorama_stations.hpp),
// which `vtm panorama` takes from the user (docs/panorama-cli.md). The input is the file's
// text. A file the parser accepts must hold what it promises: 2..64 stations, each with
// image names, a rigid approximate pose and a prior that checkPointingPrior accepts; and
// formatting it and parsing it again must be accepted too. Properties: no crash, no
// sanitizer report, no uncaught exception.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "vtm/ground/panorama_stations.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    const auto r = vtm::ground::parsePanoramaStations(text);
    if (!r.ok) return 0;
    const std::size_t n = r.value.stations.size();
    if (n < 2U || n > static_cast<std::size_t>(vtm::ground::kMaxPanoramaFileStations)) std::abort();
    for (const auto& s : r.value.stations) {
        if (s.left_image.empty() || s.right_image.empty()) std::abort();
        if (!vtm::ground::checkPointingPrior(s.prior).empty()) std::abort();
        if ((s.approx.R.transpose() * s.approx.R - vtm::Mat3::Identity()).norm() > 1e-9) std::abort();
    }
    if (!vtm::ground::parsePanoramaStations(vtm::ground::formatPanoramaStations(r.value, {"again"})).ok) std::abort();
    return 0;
}
