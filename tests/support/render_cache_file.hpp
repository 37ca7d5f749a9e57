// FileRenderCache: the simulator's render cache (sim/render_cache.hpp) over a directory,
// one file per frame, written by the host's test run and read by every later run of the
// same tree: the sanitizer and valgrind runs and the cross targets under qemu
// (docs/sim-render.md "Render cache"). Heap-free (POSIX calls and stack buffers only), so
// it works inside the no-heap scopes that SimCamera renders in.
//
// File <dir>/<key as 16 hex digits>.frame, little-endian: "VTMRCF01", key (u64), width,
// height, first row, rows, view mask, 0 (u32 each), the five RenderStats counters (i64),
// then the band's rows of each wanted view in the order image (u8 or u16), range, depth,
// point, normal (f32 bit patterns), and the CRC-32 of everything before it. A file that
// does not match the request in every header field or fails its CRC is a miss.
#pragma once

#include <atomic>
#include <cstdint>

#include "sim/render_cache.hpp"

namespace vtm::test {

class FileRenderCache final : public sim::RenderCache {
public:
    static constexpr int kMaxDirChars = 512;

    // Creates `dir` if it is missing (its parent must exist). usable() is false when the
    // path is empty or longer than kMaxDirChars - 1.
    explicit FileRenderCache(const char* dir) noexcept;

    [[nodiscard]] bool usable() const noexcept { return usable_; }
    [[nodiscard]] bool load(std::uint64_t key, const sim::FrameRequest& request, const sim::FrameOutput& out,
                            sim::RenderStats& stats) noexcept override;
    void store(std::uint64_t key, const sim::FrameRequest& request, const sim::FrameOutput& out,
               const sim::RenderStats& stats) noexcept override;

    // Counters since construction (frames read back, frames written, loads that missed).
    [[nodiscard]] std::uint32_t hits() const noexcept { return hits_.load(); }
    [[nodiscard]] std::uint32_t stores() const noexcept { return stores_.load(); }
    [[nodiscard]] std::uint32_t misses() const noexcept { return misses_.load(); }

    // The file of `key`, <dir>/<key as 16 hex digits>.frame, into path (capacity chars with
    // the terminator; kMaxDirChars + 32 is enough); false if it does not fit.
    [[nodiscard]] bool framePath(std::uint64_t key, char* path, int capacity) const noexcept;

private:

    char dir_[kMaxDirChars] = {};
    bool usable_ = false;
    std::atomic<std::uint32_t> hits_{0U};
    std::atomic<std::uint32_t> stores_{0U};
    std::atomic<std::uint32_t> misses_{0U};
    std::atomic<std::uint32_t> temp_counter_{0U};
};

}  // namespace vtm::test
