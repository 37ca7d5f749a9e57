// A simulated world on the ground side: a scenario parsed, its terrain built into a pool
// of exactly its size and its frames laid out (sim/). One loader for the command lines
// that render or fly scenarios (vtm-sim render, vtm run). Host only (heap).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "sim/scenario.hpp"
#include "vtm/core/arena.hpp"

namespace vtm::ground {

struct SimWorld {
    std::string text;  // the scenario as parsed
    sim::Scenario scenario;
    std::vector<std::byte> storage;  // the terrain's pool
    std::unique_ptr<Arena> arena;
    sim::Terrain terrain;
    std::unique_ptr<sim::ScenarioFrames> frames = std::make_unique<sim::ScenarioFrames>();
    double terrain_seconds = 0.0;
};

// Parses `text`, builds the terrain and the frames. "" on success, otherwise one line
// without the input's name: "line N: <reason>" (parse), "terrain: <reason>", or the
// frames' reason; callers put the file or label in front.
std::string buildSimWorld(const std::string& text, SimWorld& world);

// The world's frame taken at `t_ns` (a scenario timestamp), or nullptr.
const sim::ScenarioFrame* frameAt(const SimWorld& world, std::uint64_t t_ns);

// Replaces the value of the first `key` at a line start in scenario text (the rest of the
// text kept); false, text unchanged, when there is none.
bool setScenarioValue(std::string& text, const std::string& key, const std::string& value);

}  // namespace vtm::ground
