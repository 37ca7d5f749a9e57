// Epipolar rectification of a camera pair (Fusiello, Trucco, Verri 2000, with the
// principal-point shift of the 2003 revision) and resampling through fixed-point remap
// tables that also remove lens distortion. docs/rectify.md.
//
// Geometry convention (shared with fsw/features and fsw/motion): a vtm::CameraPair
// (vtm/core/pose.hpp): camera A ("left", the first image) and camera B ("right", the
// second), each a vtm::CameraModel in its own reference frame, and b_from_a:
// X_b = R X_a + t_m. Pixel (0, 0) is the centre of the top-left pixel.
//
// Memory: two remap tables of max_width x max_height entries (two int16 each), carved
// from an Arena at init(); compute(), remap() and the point maps never allocate.
// Deterministic: the tables come from camera-model code that uses only + - * / sqrt,
// rounded to fixed point with floor; resampling is integer arithmetic.
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
#include "vtm/rectify/linear_camera.hpp"

namespace vtm::rectify {

// Largest input or rectified image side: positions must fit int16 with 3 fraction bits.
constexpr std::int32_t kMaxImageSide = 4094;
// Table entry of a rectified pixel whose ray leaves the input image (or has no pixel).
constexpr std::int16_t kOutsideInput = INT16_MIN;

struct Config {
    std::int32_t max_width = 1024, max_height = 1024;  // capacity of the remap tables, 1..kMaxImageSide
    std::int32_t out_width = 0, out_height = 0;        // rectified size; 0: A's size (both 0 or both set)
    double range_min_m = 2.0, range_max_m = 200.0;     // for the disparity-range report; 0 < min < max
    double min_baseline_angle_deg = 30.0;  // baseline vs A's optical axis: below -> kDegenerate; [0, 90)
    // kOk, or kInvalidConfig naming the field (detail: the integer value, if any).
    [[nodiscard]] Status validate() const noexcept;
};

struct RectifyInput {
    CameraPair pair{};  // the two input models and b_from_a
};

struct RectifiedPair {
    // The two rectified cameras: undistorted pinholes (kPinholeBrown, k = p = 0) of the
    // rectified size, same fx, fy, cy; cx_a and cx_b differ (each image's centre ray lands
    // on its rectified image's centre column).
    CameraModel model_a{}, model_b{};
    // Rotation from each input camera's reference frame to the common rectified frame
    // (A's rectified optical frame: origin at A's projection centre, x along the
    // baseline, z forward, y down; B's rectified optical frame is the same rotation).
    Mat3 R_rect_from_a = Mat3::Identity(), R_rect_from_b = Mat3::Identity();
    Vec3 centre_b_rect_m = Vec3::Zero();  // B's projection centre in the rectified frame: (+-baseline_m, 0, 0)
    // A's projection centre (the rectified frame's origin) in A's reference frame:
    // linearizeCamera(model A).centre_ref_m, i.e. 0 for a pinhole, C for CAHV(OR). With
    // R_rect_from_a and A's site pose it places the rectified pair in the site frame
    // (terrain::rectifiedGeometry).
    Vec3 centre_a_ref_m = Vec3::Zero();
    double baseline_m = 0.0;              // |c_b - c_a|
    // Disparity d = x_a - x_b (rectified pixels): B's match of A's (x, y) is (x - d, y),
    // fsw/stereo's convention. The rectified x axis is +-(c_b - c_a), the sign chosen so
    // that it points along A's +x (images are never mirrored): when B lies to A's left,
    // centre_b_rect_m.x() < 0 and disparities are negative. [d_min, d_max] holds d of
    // every point at range [range_min_m, range_max_m] from A's centre in view of A
    // (floor/ceil, then a 1 px margin each side).
    std::int32_t d_min = 0, d_max = 0;
    double convergence_deg = 0.0;  // angle between the two input optical axes (report)
};

class Rectifier {
public:
    enum class Side : std::uint8_t { kA = 0, kB = 1 };

    // Bytes of arena for this configuration: 2 tables x max_width x max_height x 2 int16
    // (plus alignment padding). 0 for an invalid config.
    [[nodiscard]] static std::size_t workspaceBytes(const Config& config) noexcept;

    // kInvalidConfig (bad field) or kOutOfMemory (arena too small).
    [[nodiscard]] Status init(const Config& config, Arena& arena) noexcept;

    // Fusiello geometry, disparity range and both remap tables (each entry: back-project
    // the rectified pixel's ray, rotate it into the input camera's frame and project it
    // through the FULL input model). Errors, after which the point maps and remap() answer
    // kNotInitialized until a compute() succeeds:
    //   kNotInitialized  init() has not succeeded;
    //   kInvalidArgument an invalid model (validateCameraModel's reason), a model
    //                    side above kMaxImageSide, pair.b_from_a.R not a rotation (1e-9)
    //                    or a non-finite pose, a mirrored CAHV;
    //   kSizeMismatch    rectified size (out_* or A's size) above max_width/max_height;
    //   kDegenerate      baseline below 1e-9 m, or within min_baseline_angle_deg of A's
    //                    optical axis, or an image centre ray behind the rectified plane.
    [[nodiscard]] Status compute(const RectifyInput& input, RectifiedPair& out) noexcept;

    // Bilinear resampling through the fixed-point table: output(x, y) = input at the
    // table position; pixels marked kOutsideInput get `fill`. Input must be the side's
    // model size, output the rectified size (kSizeMismatch); empty views kInvalidArgument.
    [[nodiscard]] Status remap(Side side, const ImageView<const std::uint8_t>& input,
                               const ImageView<std::uint8_t>& output, std::uint8_t fill = 0U) const noexcept;

    // Exact (floating point) point maps between an input image and its rectified image,
    // pixels. kDegenerate when the ray has no pixel on the other side (behind the plane,
    // beyond the distortion's fold); points outside the images are mapped all the same.
    [[nodiscard]] Status rectifyPixel(Side side, const Vec2& input_px, Vec2& rectified_px) const noexcept;
    [[nodiscard]] Status unrectifyPixel(Side side, const Vec2& rectified_px, Vec2& input_px) const noexcept;

    // The tables, for modules that resample themselves and for tests: F, and the entry of
    // rectified pixel (x, y) (input position * 2^F, rounded to nearest, or kOutsideInput).
    // F is the largest of {5, 4, 3} with (largest input side + 1) << F <= 32767.
    [[nodiscard]] std::int32_t fractionBits() const noexcept { return fraction_bits_; }
    [[nodiscard]] Status tableEntry(Side side, std::int32_t x, std::int32_t y, std::int16_t& x_q,
                                    std::int16_t& y_q) const noexcept;

private:
    struct SideState {
        CameraModel model{};                   // the full input model (copied)
        Mat3 R_rect_from_ref = Mat3::Identity();
        Vec3 centre_ref_m = Vec3::Zero();      // projection centre in the model's frame
        double cx_px = 0.0;                    // rectified principal point column
        Span<std::int16_t> table;              // interleaved (x_q, y_q), out_width_ per row
    };
    struct Geometry;

    [[nodiscard]] Status checkInput(const RectifyInput& input) const noexcept;
    [[nodiscard]] Status setIntrinsics(const Geometry& g) noexcept;
    [[nodiscard]] Status toInput(const SideState& side, const Vec2& rectified_px, Vec2& input_px) const noexcept;
    void buildTable(const SideState& side) const noexcept;
    [[nodiscard]] const SideState& state(Side side) const noexcept;
    void fillPair(const Geometry& g, RectifiedPair& out) const noexcept;

    Config config_{};
    SideState sides_[2]{};
    double fx_px_ = 0.0, fy_px_ = 0.0, cy_px_ = 0.0;
    std::int32_t out_width_ = 0, out_height_ = 0;
    std::int32_t fraction_bits_ = 0;
    bool initialized_ = false;
    bool ready_ = false;
};

}  // namespace vtm::rectify
