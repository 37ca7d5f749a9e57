#include "vtm/ground/sim_world.hpp"

#include <chrono>

namespace vtm::ground {

bool setScenarioValue(std::string& text, const std::string& key, const std::string& value) {
    const std::size_t at = text.find("\n" + key + " ");
    if (at == std::string::npos) return false;
    const std::size_t end = text.find('\n', at + 1);
    text.replace(at + 1, (end == std::string::npos ? text.size() : end) - at - 1, key + " " + value);
    return true;
}

std::string buildSimWorld(const std::string& text, SimWorld& w) {
    w.text = text;
    const Status parsed = sim::parseScenario(w.text, w.scenario);
    if (!parsed.isOk()) {
        return "line " + std::to_string(parsed.detail()) + ": " + parsed.reason();
    }
    const auto start = std::chrono::steady_clock::now();
    w.storage.assign(sim::scenarioTerrainBytes(w.scenario), std::byte{0});
    w.arena = std::make_unique<Arena>(w.storage.data(), w.storage.size());
    const Status built = sim::buildScenarioTerrain(w.scenario, *w.arena, w.terrain);
    if (!built.isOk()) {
        return std::string("terrain: ") + built.reason();
    }
    w.terrain_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const Status framed = sim::buildScenarioFrames(w.scenario, w.terrain, *w.frames);
    if (!framed.isOk()) {
        return framed.reason();
    }
    return "";
}

const sim::ScenarioFrame* frameAt(const SimWorld& world, std::uint64_t t_ns) {
    for (std::int32_t i = 0; i < world.frames->count; ++i) {
        if (world.frames->frames[i].timestamp_ns == t_ns) return &world.frames->frames[i];
    }
    return nullptr;
}

}  // namespace vtm::ground
