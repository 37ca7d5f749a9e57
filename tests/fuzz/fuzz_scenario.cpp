// libFuzzer target (4): sim::parseScenario, the scenario files (.scn) that vtm-sim, vtm run
// and the simulated drivers read (docs/sim-scenarios.md). A scenario it accepts must also
// pass validateScenario (parseScenario promises a checked scenario). Properties: no crash,
// no sanitizer report, no assertion.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "sim/scenario.hpp"
#include "vtm/core/assert.hpp"

namespace {
void abortOnAssert(const vtm::AssertInfo&) { std::abort(); }
vtm::sim::Scenario scenario;  // static: a Scenario is a fixed-size record of several KB
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    (void)vtm::setAssertHook(abortOnAssert);
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    if (vtm::sim::parseScenario(text, scenario).isOk() && !vtm::sim::validateScenario(scenario).isOk()) {
        std::abort();
    }
    return 0;
}
