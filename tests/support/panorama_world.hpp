// A simulated mast panorama with its images rendered, for the tests of the panorama chain
// (tests/app/panorama_mapper_test.cpp, tests/panorama/panorama_chain_evaluation.cpp):
// scenario text -> terrain -> stations (sim/panorama.hpp) -> the first `stations` stations'
// two eyes rendered (8-bit), optionally with the left eyes' range truth. Header only: the
// including test links the simulator.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "sim/panorama.hpp"
#include "sim/render.hpp"
#include "sim/scenario.hpp"
#include "vtm/core/arena.hpp"
#include "vtm/core/image_network.hpp"

namespace vtm::test {

struct PanoramaWorld {
    sim::Scenario scenario;
    std::vector<std::byte> terrain_pool;
    std::unique_ptr<Arena> terrain_arena;
    sim::Terrain terrain;
    sim::Panorama panorama;
    std::unique_ptr<sim::ScenarioFrames> frames = std::make_unique<sim::ScenarioFrames>();
    std::vector<std::vector<std::uint8_t>> pixels;  // frame k: station k / 2, eye k % 2
    std::vector<std::vector<float>> range;          // left eyes' range truth (when asked for), else empty
    std::vector<NetworkStation> approx;             // the rendered stations' approximate poses and priors
    std::vector<StationImages> images;              // their eyes, views of pixels
    std::int32_t side = 0;                          // eye width = height, pixels
};

// Builds `w` from scenario text; `stations` < 0: every station. False on any failure (the
// parse, the terrain, the panorama, a frame's rendering).
inline bool buildPanoramaWorld(const std::string& text, PanoramaWorld& w, std::int32_t stations = -1,
                               bool left_range = false) {
    if (!sim::parseScenario(text, w.scenario).isOk()) return false;
    w.terrain_pool.assign(sim::scenarioTerrainBytes(w.scenario), std::byte{0});
    w.terrain_arena = std::make_unique<Arena>(w.terrain_pool.data(), w.terrain_pool.size());
    if (!sim::buildScenarioTerrain(w.scenario, *w.terrain_arena, w.terrain).isOk()) return false;
    if (!sim::buildPanorama(w.scenario, w.terrain, w.panorama).isOk()) return false;
    if (!sim::buildScenarioFrames(w.scenario, w.terrain, *w.frames).isOk()) return false;
    const std::int32_t count = stations < 0 || stations > w.panorama.count ? w.panorama.count : stations;
    w.side = w.frames->frames[0].model.width_px;
    const auto px = static_cast<std::size_t>(w.side) * static_cast<std::size_t>(w.side);
    const auto n = static_cast<std::size_t>(2 * count);
    w.pixels.assign(n, std::vector<std::uint8_t>(px, 0U));
    w.range.assign(n, std::vector<float>());
    for (std::size_t k = 0; k < n; ++k) {
        const sim::FrameRequest rq =
            sim::scenarioFrameRequest(w.scenario, w.terrain, w.frames->frames[static_cast<std::int32_t>(k)]);
        sim::FrameOutput out;
        out.image8 = ImageView<std::uint8_t>(w.pixels[k].data(), w.side, w.side);
        if (left_range && k % 2 == 0) {
            w.range[k].assign(px, 0.0F);
            out.truth.range_m = ImageView<float>(w.range[k].data(), w.side, w.side);
        }
        if (!sim::renderFrame(rq, out, nullptr).isOk()) return false;
    }
    for (std::int32_t s = 0; s < count; ++s) {
        w.approx.push_back(w.panorama.stations[s].approx);
        StationImages im;
        im.left = ImageView<const std::uint8_t>(w.pixels[static_cast<std::size_t>(2 * s)].data(), w.side, w.side);
        im.right = ImageView<const std::uint8_t>(w.pixels[static_cast<std::size_t>(2 * s + 1)].data(), w.side, w.side);
        w.images.push_back(im);
    }
    return true;
}

}  // namespace vtm::test
