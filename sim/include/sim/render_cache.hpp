// Render cache: a store that renderFrame() consults before ray casting a frame, and
// fills after (docs/sim-render.md "Render cache"). None is installed by default.
//
// Why: the simulator is ground equipment. In hardware-in-the-loop it runs natively and
// the flight processor receives its frames; under qemu-user, a cross-compiled test that
// renders its scene spends most of its time emulating the ray caster (on ppc750 about a
// third of the module tests' time). With a cache installed, the host's test run renders
// each frame once and the emulated runs read the same bytes back. The renderer's own
// bits on every target are checked where the cache is never installed: the simulator's
// unit tests and the determinism suite.
//
// A frame is identified by frameKey(): every field of the request that reaches a pixel
// (the terrain's parameters, camera model, pose, lighting, sensor, frame index, band,
// range limit) and which output views are wanted. Equal keys mean equal bytes.
#pragma once

#include <cstdint>

#include "sim/render.hpp"

namespace vtm::sim {

// Key of one renderFrame() call (FNV-1a 64 over the canonical bytes of its inputs).
[[nodiscard]] std::uint64_t frameKey(const FrameRequest& request, const FrameOutput& out) noexcept;

// Which views renderFrame() writes for a request: bits of the image (image16 when the
// sensor's bit depth is 12, image8 otherwise) and of each truth view given.
constexpr std::uint32_t kViewImage16 = 1U;
constexpr std::uint32_t kViewRange = 2U;
constexpr std::uint32_t kViewDepth = 4U;
constexpr std::uint32_t kViewPoint = 8U;
constexpr std::uint32_t kViewNormal = 16U;
[[nodiscard]] std::uint32_t renderedViews(const FrameRequest& request, const FrameOutput& out) noexcept;

// What a cache provides. Both calls get a request that renderFrame() has validated and
// its output views; neither may allocate (renderFrame runs inside no-heap scopes).
class RenderCache {
public:
    RenderCache() = default;
    RenderCache(const RenderCache&) = delete;
    RenderCache& operator=(const RenderCache&) = delete;
    virtual ~RenderCache() = default;

    // Writes the band's rows of every wanted view and the frame's stats, and returns
    // true, when a frame of `key` is stored and intact; false otherwise (a partial write
    // is allowed then: renderFrame renders over it).
    [[nodiscard]] virtual bool load(std::uint64_t key, const FrameRequest& request, const FrameOutput& out,
                                    RenderStats& stats) noexcept = 0;
    // Keeps the band just rendered. Failures are silent (the next load misses).
    virtual void store(std::uint64_t key, const FrameRequest& request, const FrameOutput& out,
                       const RenderStats& stats) noexcept = 0;
};

// Installs `cache` for every later renderFrame() call of the process (nullptr: none).
// Set it before rendering starts, not while other threads render.
void setRenderCache(RenderCache* cache) noexcept;
[[nodiscard]] RenderCache* renderCache() noexcept;

}  // namespace vtm::sim
