// Förstner interest operator (Förstner & Gülch 1987) as a flight module: the tie points
// that fsw/motion refines the rover's relative motion with (docs/features.md).
//
// Per pixel: gradients by central differences (integer), the structure tensor
// N = sum over a window x window box of [gx^2 gx*gy; gx*gy gy^2] (integer box sums, exact),
// precision w = det N / tr N and roundness q = 4 det N / (tr N)^2 in [0, 1]. Features are
// the 3x3 local maxima of w with q >= min_roundness and w >= min_strength_ratio times the
// best w of the allowed part (inside border_px; with a mask, where it is nonzero); they are
// spread over a grid (the best per_cell by w in each cell) that spans the image, or with a
// mask the mask's bounding box, and then capped at max_features by w.
// Subpixel location: DetectorConfig::subpixel.
//
// Output order is deterministic: by cell (row-major), then by w (descending), ties by
// position (row, then column). Integer arithmetic up to w and q, which are computed from
// exact integers with one correctly rounded IEEE division each: the same bits on every target.
// Memory: workspaceBytes(config), carved at init(); detect() never allocates.
#pragma once

#include <cstddef>
#include <cstdint>

#include "vtm/core/arena.hpp"
#include "vtm/core/eigen.hpp"
#include "vtm/core/image.hpp"
#include "vtm/core/span.hpp"
#include "vtm/core/status.hpp"

namespace vtm::features {

// Capacity of a FeatureSet / MatchSet (the motion refiner's fixed maximum).
constexpr std::int32_t kMaxFeatures = 1024;

// One interest point. pixel: image coordinates (x = column, y = row, (0, 0) = centre of the
// top-left pixel), subpixel. strength: w at the maximum (grey levels^2, window-sum units).
// roundness: q at the maximum, 0..1 (1 = isotropic corner).
struct Feature {
    Vec2 pixel = Vec2::Zero();
    float strength = 0.f;
    float roundness = 0.f;
};

struct FeatureSet {
    Feature items[kMaxFeatures];
    std::int32_t count = 0;
};

// How a feature's subpixel position is found from its integer maximum of w.
enum class Subpixel : std::uint8_t {
    // 2D quadratic fit of w over the 3x3 neighbourhood of the maximum, offset clamped to
    // +-0.5 px per axis. Cheap; biased where w has a plateau (box windows over X-junctions).
    kQuadraticFit = 0,
    // Förstner's point estimate: the point closest (least squares) to every edge line in
    // the window at the maximum, x* = N^-1 sum(g g^T x). Exact for straight edges through a
    // corner (L-, X-junctions); used when it lies within the window (|offset| <= window/2
    // per axis), else falls back to kQuadraticFit.
    kEdgeIntersection = 1,
};

struct DetectorConfig {
    std::int32_t max_width = 1024, max_height = 1024;  // capacity, pixels: 1..4096
    std::int32_t window = 5;                           // odd, 3..31: side of the structure-tensor box
    float min_roundness = 0.5f;                        // q threshold, (0, 1]
    std::int32_t grid_cols = 16, grid_rows = 16;       // spreading grid, 1..64 each
    std::int32_t per_cell = 2;                         // best features kept per cell, 1..64
    std::int32_t border_px = 12;                       // no features closer to the edge; >= window/2 + 2
    float min_strength_ratio = 0.002f;                 // w >= ratio * best w of the image, [0, 1]
    std::int32_t max_features = 512;                   // 1..kMaxFeatures
    Subpixel subpixel = Subpixel::kEdgeIntersection;   // see Subpixel
    // After the subpixel step, a feature closer than this to a stronger one is dropped (the
    // point estimate can pull neighbouring maxima of w onto one corner; a duplicate would
    // count twice in motion refinement). 0 keeps them all. 0..16 px.
    float min_separation_px = 2.0F;
    // kOk, or kInvalidConfig naming the field, detail = its value (for floats: 0).
    // This configuration with another capacity (what a module that states the capacity once
    // for several sub-modules hands down).
    [[nodiscard]] DetectorConfig withCapacity(std::int32_t width, std::int32_t height) const noexcept {
        DetectorConfig c = *this;
        c.max_width = width;
        c.max_height = height;
        return c;
    }
    [[nodiscard]] Status validate() const noexcept;
};

// candidates: local maxima of w that passed the roundness and strength thresholds;
// kept: features written (after spreading and the max_features cap).
struct DetectorStats {
    std::int32_t candidates = 0;
    std::int32_t kept = 0;
};

class ForstnerDetector {
public:
    // Arena bytes init() takes for this configuration (0 for an invalid one).
    [[nodiscard]] static std::size_t workspaceBytes(const DetectorConfig& config) noexcept;
    // Validates the config (kInvalidConfig) and carves the workspace (kOutOfMemory).
    [[nodiscard]] Status init(const DetectorConfig& config, Arena& arena) noexcept;
    // Features of an 8-bit image. kNotInitialized before init(); kInvalidArgument for an
    // empty view; kSizeMismatch when the image exceeds the capacity or is smaller than
    // 2 * border_px + 3 in either direction. A texture-less image gives ok() and count 0.
    // `out` is fully rewritten on success (count = 0 on failure).
    // mask (optional, the image's size, else kSizeMismatch): features only where it is
    // nonzero, e.g. the part of image A that image B can see (predictVisibility in
    // visibility.hpp); the grid then spans that part's bounding box and the strength
    // threshold is relative to the best w inside it, so a small or faint visible part
    // still gets grid_cols x grid_rows cells of features.
    [[nodiscard]] Status detect(const ImageView<const std::uint8_t>& image, FeatureSet& out,
                                DetectorStats* stats = nullptr,
                                const ImageView<const std::uint8_t>& mask = {}) noexcept;

    [[nodiscard]] const DetectorConfig& config() const noexcept { return config_; }

    // A local maximum kept in a grid cell (public only so the workspace can hold it).
    struct Candidate {
        float w;
        float q;
        std::int32_t x;
        std::int32_t y;
    };

private:
    void computeStrength(const ImageView<const std::uint8_t>& image) noexcept;
    [[nodiscard]] std::int32_t selectCandidates(std::int32_t width, std::int32_t height,
                                                const ImageView<const std::uint8_t>& mask) noexcept;
    void emitFeatures(FeatureSet& out) noexcept;
    [[nodiscard]] Vec2 subpixelOffset(const ImageView<const std::uint8_t>& image, std::int32_t x,
                                      std::int32_t y, std::int32_t width) const noexcept;
    [[nodiscard]] bool pointEstimate(const ImageView<const std::uint8_t>& image, std::int32_t x, std::int32_t y,
                                     Vec2& offset) const noexcept;
    static void dropDuplicates(FeatureSet& out, float min_separation_px) noexcept;
    [[nodiscard]] Vec2 quadraticOffset(std::int32_t x, std::int32_t y, std::int32_t width) const noexcept;

    DetectorConfig config_{};
    bool initialized_ = false;
    float best_w_ = 0.f;
    Span<float> w_{};                 // w per pixel, max_width * max_height (row stride = width)
    Span<float> q_{};                 // q per pixel
    Span<std::int32_t> columns_{};    // 3 * max_width: running column sums of gx^2, gy^2, gx*gy
    Span<Candidate> cells_{};         // grid_cols * grid_rows * per_cell, each cell sorted by w
    Span<std::int32_t> cellCount_{};  // grid_cols * grid_rows
    Span<std::int32_t> rank_{};       // slot indices, for the max_features cap
    Span<std::uint8_t> keep_{};       // per slot: survives the cap
};

}  // namespace vtm::features
