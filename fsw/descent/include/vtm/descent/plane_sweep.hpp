// Descent plane sweep (Xiong, Olson, Matthies; paper §4), as a flight module.
//
// Two nadir images of a descending lander: image 1 (earlier, higher) is the reference,
// image 2 (later, closer) is warped onto it. With the relative pose X2 = R X1 + t of the
// two camera frames, every virtual plane n . X1 = z_k perpendicular to camera 1's optical
// axis (n = +z of camera 1) induces the homography from image 1 to image 2
//     H_k = K (R + t n^T / z_k) K^-1
// (a point on the plane has n . X1 / z_k = 1, so X2 = R X1 + t (n . X1) / z_k; papers
// that write "R - t n^T / d" use the plane n . X + d = 0). The planes are uniform in
// inverse depth between depth_min_m and depth_max_m. For each plane, image 2 — low-passed
// once per pair to the scale the homographies imply, because it is the closer image —
// is sampled bilinearly at H_k p for every pixel p of image 1, and a box-filtered window
// score (SAD or normalised correlation) compares it with image 1. Each pixel keeps its
// best plane; a parabola through the neighbouring planes' scores refines it in inverse
// depth. Pixels whose parallax over the whole depth range is below min_parallax_px (near
// the focus of expansion) are flagged, as are pixels whose window leaves either image.
//
// Memory: the prefiltered image 2 (max_width * max_height, 16 bit) plus buffers for one
// band of band_rows rows of image 1; workspaceBytes(config) from an Arena at init();
// compute() never allocates. Deterministic: integer window sums (held exactly in doubles), double geometry with
// + - * / only, the prefilter's weights quantised at run start; bit-identical on every
// target. docs/descent.md has the method, the memory formula and the measured accuracy.
#pragma once

#include <cstddef>
#include <cstdint>

#include "vtm/core/arena.hpp"
#include "vtm/core/camera_model.hpp"
#include "vtm/core/eigen.hpp"
#include "vtm/core/image.hpp"
#include "vtm/core/pose.hpp"
#include "vtm/core/span.hpp"
#include "vtm/core/status.hpp"
#include "vtm/terrain/height_map.hpp"

namespace vtm::descent {

// Largest grey level accepted: 12-bit sensors (8-bit images are accepted as they are).
constexpr std::uint16_t kMaxGreyLevel = 4095U;
constexpr std::int32_t kMaxPlanes = 256;
// Largest prefilter radius (taps each side): enough for a scale change of about 8.
constexpr std::int32_t kMaxPrefilterRadius = 8;

// Window score.
enum class Score : std::uint8_t {
    kSad = 0,  // mean absolute grey-level difference over the window (cost, lower is better)
    kNcc = 1,  // normalised cross-correlation; the cost kept is 1 - ncc (0 .. 2)
};

// Why a pixel has no depth (kValid when it has one). Values are stable (telemetry).
enum class Reason : std::uint8_t {
    kValid = 0,
    kBorder = 1,        // the window leaves image 1
    kOutOfView = 2,     // the window leaves image 2 for some plane of the range
    kLowParallax = 3,   // parallax over the depth range below min_parallax_px (focus of expansion)
    kOutOfRange = 4,    // best plane is the first or the last one
    kNoTexture = 5,     // flat score (no curvature at the best plane, or zero variance for NCC)
};
constexpr std::int32_t kReasonCount = 6;

struct Config {
    // Capacity, pixels. The prefiltered image 2 takes 2 * max_width * max_height bytes.
    std::int32_t max_width = 1024;   // 16..4096
    std::int32_t max_height = 1024;  // 16..4096
    std::int32_t planes = 64;        // 3..kMaxPlanes
    // Depth range along camera 1's optical axis, metres: 0 < depth_min_m < depth_max_m.
    double depth_min_m = 1500.0;
    double depth_max_m = 2500.0;
    // Window side, odd, 3..31 px. 11: with 7 the simulated descent misses RMS <= 0.5 % of
    // the altitude where the terrain's finest texture sits at image 1's pixel size
    // (docs/descent.md "Accuracy"); the sweep's cost does not depend on the window.
    std::int32_t window = 11;
    Score score = Score::kNcc;  // NCC: insensitive to the exposure and gain changes between frames
    // Pixels whose image-2 positions for depth_min_m and depth_max_m are closer than this
    // (image-2 pixels) are kLowParallax. 0..1000.
    double min_parallax_px = 8.0;
    // Rows of image 1 processed together: memory grows with band_rows, per-band overhead
    // (window - 1 extra rows warped per plane) shrinks. 1..max_height.
    std::int32_t band_rows = 32;
    // 0: compute() sweeps `planes` planes. > 0 (image-2 pixels, at most 1000): it sweeps only
    // as many (at least 3, at most `planes`) as keep the step between neighbouring planes
    // at most this far in image 2 where the parallax over the depth range is largest (on a
    // 33 x 33 grid of image 1, among the points image 2 sees at both ends of the range):
    // the planes stay uniform in 1/z over the same range, fewer where the parallax is small.
    double max_plane_step_px = 0.0;

    // kOk, or kInvalidConfig naming the field (value in detail; 0 for non-integers).
    [[nodiscard]] Status validate() const noexcept;
};

// The pair's geometry: one camera (both images) and where it was for each image: its
// reference (optical) frame in the site frame (x north, y east, z down) as
// vtm::RigidPose site_from_cam (vtm/core/pose.hpp): p_site = R p_cam + t_m.
struct PairGeometry {
    // An undistorted pinhole (kPinholeBrown, k1 = k2 = k3 = p1 = p2 = 0) whose size is the
    // images' size. Distorted and CAHV(OR) models are kUnsupported: undistort first.
    CameraModel camera{};
    RigidPose site_from_cam1{};  // image 1 (reference, earlier and higher)
    RigidPose site_from_cam2{};  // image 2 (later, closer)
};

// Caller-provided outputs, image 1's size (score and reason may be empty views).
struct SweepOutput {
    ImageView<float> depth_m;       // along camera 1's optical axis; NaN where reason != kValid
    ImageView<float> score;         // best plane's cost (SAD: grey levels; NCC: 1 - ncc); NaN if none or kBorder / kOutOfView
    ImageView<std::uint8_t> reason; // Reason
};

struct SweepStats {
    std::int32_t valid_pixels = 0;
    std::int32_t reason_counts[kReasonCount] = {};
    // Scale of image 2 relative to image 1 at the image centre (middle plane), and the
    // Gaussian sigma (image-2 pixels) of the anti-alias prefilter it gave.
    double scale = 0.0;
    double prefilter_sigma_px = 0.0;
    // The largest parallax over the depth range where image 2 sees image 1 (image-2
    // pixels) and the planes swept (Config::max_plane_step_px).
    double max_parallax_px = 0.0;
    std::int32_t planes = 0;
};

// kOk for a camera the sweep accepts (an undistorted, valid pinhole); kUnsupported or
// kInvalidArgument naming what is wrong. compute() and addDepthToHeightMap() check the same;
// an executive checks it once when it learns its camera.
[[nodiscard]] Status checkCamera(const CameraModel& camera) noexcept;

class PlaneSweep {
public:
    // Bytes of arena for this configuration (every buffer and its padding), 0 if invalid.
    [[nodiscard]] static std::size_t workspaceBytes(const Config& config) noexcept;

    // Validates the config and carves the workspace. kInvalidConfig, kOutOfMemory.
    [[nodiscard]] Status init(const Config& config, Arena& arena) noexcept;

    // Retargets an initialised sweep to another depth range and focus-of-expansion
    // threshold for the next compute() (a lander's altitude changes from pair to pair; the
    // workspace does not depend on them). kNotInitialized; kInvalidConfig naming the field
    // as Config::validate() does. A refused call leaves the previous range in force.
    [[nodiscard]] Status setDepthRange(double depth_min_m, double depth_max_m, double min_parallax_px) noexcept;
    // Depth of every pixel of image 1. Images: grey levels 0..kMaxGreyLevel, same size,
    // within capacity. kNotInitialized; kInvalidArgument (empty view, a grey level above
    // 4095, a pose that is not a rotation or not finite, camera 2 at camera 1's
    // position); kUnsupported (camera not an undistorted pinhole); kSizeMismatch (images
    // or outputs of other sizes, camera size differs); kDegenerate (a plane of the range
    // passes behind camera 2). Never allocates.
    [[nodiscard]] Status compute(const ImageView<const std::uint16_t>& image1,
                                 const ImageView<const std::uint16_t>& image2, const PairGeometry& geometry,
                                 const SweepOutput& out, SweepStats* stats = nullptr) noexcept;

    // Image 2 after the anti-alias prefilter of the last compute(), grey levels x 16
    // (4 fractional bits): for peer comparisons. Empty before the first compute().
    [[nodiscard]] ImageView<const std::uint16_t> prefilteredImage2() const noexcept;
    // Homography of plane k (image 1 pixel -> image 2 pixel, homogeneous) and its depth,
    // as used by the last compute(). 0 <= k < planesSwept().
    [[nodiscard]] Mat3 homography(std::int32_t k) const noexcept;
    [[nodiscard]] double planeDepth(std::int32_t k) const noexcept;

    [[nodiscard]] const Config& config() const noexcept { return config_; }
    // Planes of the last compute() (Config::max_plane_step_px); 0 before the first.
    [[nodiscard]] std::int32_t planesSwept() const noexcept { return planes_; }

private:
    [[nodiscard]] Status prepare(const ImageView<const std::uint16_t>& image1,
                                 const ImageView<const std::uint16_t>& image2, const PairGeometry& geometry,
                                 const SweepOutput& out) noexcept;
    void prefilter(const ImageView<const std::uint16_t>& image2, double sigma_px) noexcept;
    void sweepBand(const ImageView<const std::uint16_t>& image1, std::int32_t y0, std::int32_t y1) noexcept;
    void loadImage1Rows(const ImageView<const std::uint16_t>& image1, std::int32_t y0, std::int32_t y1) noexcept;
    void warpRows(std::int32_t k, std::int32_t yFirst, std::int32_t rows, std::int32_t x0, std::int32_t x1) noexcept;
    void inViewColumns(std::int32_t y0, std::int32_t y1, std::int32_t& p0, std::int32_t& p1) const noexcept;
    void scorePlane(std::int32_t k, std::int32_t y0, std::int32_t y1, std::int32_t p0, std::int32_t p1) noexcept;
    void scoreRow(std::int32_t k, std::int32_t bandRow, std::int32_t p0, std::int32_t p1) noexcept;
    void imageSums(std::int32_t y0, std::int32_t y1) noexcept;
    void markRow(std::int32_t y, const SweepOutput& out, SweepStats& stats) noexcept;
    void decideBand(const ImageView<const std::uint16_t>& image1, std::int32_t y0, std::int32_t y1,
                    const SweepOutput& out, SweepStats& stats) noexcept;

    double scale_ = 0.0;           // prepare(): image-2 scale at the centre (SweepStats::scale)
    double prefilterSigma_ = 0.0;  // prepare(): anti-alias sigma (SweepStats::prefilter_sigma_px)
    double maxParallax_ = 0.0;     // prepare(): SweepStats::max_parallax_px
    std::int32_t planes_ = 0;      // prepare(): planes swept, 3..config_.planes
    Config config_{};
    bool initialized_ = false;
    std::int32_t width_ = 0;
    std::int32_t height_ = 0;
    std::int32_t radius_ = 0;
    Span<double> homographies_{};  // planes * 9, row-major
    Span<double> inverseDepth_{};  // planes, 1 / z_k (k = 0: depth_max_m)
    Span<std::uint16_t> image2_{}; // prefiltered image 2, grey x 16, width_ * height_ packed
    Span<std::int32_t> filterRow_{};   // prefilter: one row of the vertical pass
    // Image 1 (levels x 16) and the warped image 2 (levels x 16, 4 fractional bits of the
    // bilinear weights) of the band plus the window's margin, (band_rows + window - 1) rows
    // each, as floats: every value is an integer below 2^16, exact in a float, and loads
    // into a floating-point register without the int-to-double sequence the 750 needs.
    Span<float> image1Rows_{};
    Span<float> warped_{};
    // The window sums are integers held in doubles: every one is below 2^52 (levels x 16 <
    // 2^16, window <= 31), so each sum, product and difference the score takes is exact,
    // the same values the int64 arithmetic gave, at one floating-point instruction each on
    // the 32-bit targets (an int64 multiply or conversion is a sequence or a libgcc call).
    Span<double> colA_{};              // column sums: SAD, or sum of w (NCC)
    Span<double> colB_{};              // NCC: sum of w^2
    Span<double> colC_{};              // NCC: sum of i * w
    Span<double> sumI_{};              // NCC: window sums of image 1 (band), exact integers
    Span<double> varI_{};              // NCC: n * sum(i^2) - sum(i)^2 per band pixel, exact
    // Per band pixel, the score to maximise (SAD: -sum |i - w|; NCC: ncc * |ncc|, which
    // orders the planes as ncc does without a square root per pixel and plane); kNoScore
    // where there is none.
    Span<float> bestScore_{};
    Span<float> prevScore_{};          // at the previous plane
    Span<float> belowScore_{};         // at best - 1
    Span<float> aboveScore_{};         // at best + 1
    Span<std::int16_t> bestIndex_{};   // -1: none yet
};

// ---- Depth to the height map ------------------------------------------------------------

// The descent's side of the elevation product: every valid depth pixel of camera 1
// becomes its site point, X_site = R (K^-1 (x, y, 1) depth) + t_m with site_from_cam, and
// is added to `map` (terrain::HeightMap: its grid and reducer decide the cells and their
// elevation; docs/terrain.md has the convention). The map is not cleared first. Pixels
// with NaN depth are skipped; points outside the grid are counted in stats->outside (stats
// may be null). Errors: kInvalidArgument (empty view, bad pose), kUnsupported (camera not
// an undistorted pinhole), kSizeMismatch (depth size != camera size), the map's
// kNotInitialized. Never allocates.
[[nodiscard]] Status addDepthToHeightMap(const ImageView<const float>& depth_m, const CameraModel& camera,
                                         const RigidPose& site_from_cam, terrain::HeightMap& map,
                                         terrain::HeightMapStats* stats = nullptr) noexcept;

}  // namespace vtm::descent
