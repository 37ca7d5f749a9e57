// Local-entropy images (paper §5; Olson, "Image registration by aligning entropies", CVPR
// 2001), as a flight module.
//
// Every pixel becomes the Shannon entropy of the histogram of the grey levels in the
// window x window square centred on it (borders replicated, so every window holds
// N = window^2 samples). Two images of one scene taken by different sensors (visible and
// thermal infrared, a descent camera and an orbital map) rarely agree on intensities, but
// both show texture where the scene has structure and none where it is uniform: their
// entropy images can be matched by normalised correlation.
//
//   H = log2 N - (1/N) sum_b c_b log2 c_b      (bits; c_b: count of bin b)
//
// Fixed point, identical bits on every target: c log2 c is tabulated for c = 0..N in
// units of 2^-16 bit (kTableFractionBits), built at init() from vtm::math::log; the sum runs
// in integers. The output is 8-bit: round(255 * H / log2 bins), so 255 is the entropy of a
// window whose samples spread evenly over all bins (0: a flat window).
//
// Running histograms (Perreault and Hebert's column histograms): one histogram per image
// column over the window's rows, moved down one row per image row (one sample out, one
// in); the window's histogram moves right by adding the entering column's histogram and
// subtracting the leaving one's. Cost per pixel: O(bins), whatever the window side.
//
// Memory: the column histograms (max_width * bins 16-bit counts) and the table
// (window^2 + 1 32-bit entries), from an Arena at init(); compute() never allocates.
#pragma once

#include <cstddef>
#include <cstdint>

#include "vtm/core/arena.hpp"
#include "vtm/core/image.hpp"
#include "vtm/core/span.hpp"
#include "vtm/core/status.hpp"

namespace vtm::entropy {

constexpr std::int32_t kMaxBins = 64;
constexpr std::int32_t kMaxWindow = 31;
// Fraction bits of the tabulated n log2 n.
constexpr std::int32_t kTableFractionBits = 16;

struct EntropyConfig {
    // Capacity, pixels: 8..8192.
    std::int32_t max_width = 1024;
    std::int32_t max_height = 1024;
    // Window side, odd, 3..kMaxWindow px. Larger windows give smoother, more stable entropy
    // images at a coarser resolution. 5 (with 8 bins): the best of 3..15 x 4..32 on the
    // optical-infrared pairs (docs/entropy.md).
    std::int32_t window = 5;
    // Histogram bins, a power of two, 2..kMaxBins. Grey level v falls in bin v >> (input_bits - log2 bins).
    std::int32_t bins = 8;
    // Significant bits of 16-bit inputs (8..16; 8-bit inputs always use 8). A 16-bit grey
    // level at or above 2^input_bits is refused.
    std::int32_t input_bits = 12;

    // kOk, or kInvalidConfig naming the field ("entropy.window: ...", value in detail).
    [[nodiscard]] Status validate() const noexcept;
};

class LocalEntropy {
public:
    // Bytes of arena for this configuration (every buffer and its padding), 0 if invalid.
    [[nodiscard]] static std::size_t workspaceBytes(const EntropyConfig& config) noexcept;

    // Validates the config, carves the workspace and builds the n log2 n table.
    // kInvalidConfig, kOutOfMemory.
    [[nodiscard]] Status init(const EntropyConfig& config, Arena& arena) noexcept;

    // Entropy image of src into dst (same size, within capacity): 0..255 = 0..log2(bins)
    // bits. kNotInitialized; kInvalidArgument (empty view; a 16-bit grey level >=
    // 2^input_bits); kSizeMismatch. Never allocates.
    [[nodiscard]] Status compute(const ImageView<const std::uint8_t>& src,
                                 const ImageView<std::uint8_t>& dst) noexcept;
    [[nodiscard]] Status compute(const ImageView<const std::uint16_t>& src,
                                 const ImageView<std::uint8_t>& dst) noexcept;

    // round(n log2 n * 2^kTableFractionBits) for n = 0..window^2 (0 outside): the table
    // compute() uses, for tests.
    [[nodiscard]] std::uint32_t nLog2n(std::int32_t n) const noexcept;
    // The output value of a window histogram with these counts (bins() of them, summing to
    // window^2): what compute() writes for it, for tests. 0 if the counts are malformed.
    [[nodiscard]] std::uint8_t outputOf(const std::int32_t* counts) const noexcept;

    [[nodiscard]] const EntropyConfig& config() const noexcept { return config_; }

private:
    template <typename T>
    [[nodiscard]] Status run(const ImageView<const T>& src, const ImageView<std::uint8_t>& dst,
                             std::int32_t shift) noexcept;
    template <typename T>
    void columnsForRow(const ImageView<const T>& src, std::int32_t y, std::int32_t shift) noexcept;
    void entropyRow(std::uint8_t* out, std::int32_t width) noexcept;
    [[nodiscard]] std::uint8_t quantise(std::int64_t sumTable) const noexcept;

    EntropyConfig config_{};
    bool initialized_ = false;
    std::int32_t radius_ = 0;
    std::int32_t samples_ = 0;     // window^2
    std::int32_t binsLog2_ = 0;
    std::int64_t denominator_ = 0; // samples * log2(bins) << kTableFractionBits
    Span<std::uint32_t> table_{};  // n log2 n, n = 0..samples
    Span<std::uint16_t> columns_{};// max_width * bins column histograms
    std::int32_t window_[kMaxBins] = {};
};

}  // namespace vtm::entropy
