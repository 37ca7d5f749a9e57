// The descent's absolute fix from an orbital map (issue 24 item 4, paper §5): the
// DescentMapper's "locate" stage. Each frame of a pair is registered to a georeferenced
// orbital image by its local-entropy image (entropy::EntropyRegistration), around the
// place the navigation pose predicts; the registration puts every refined feature of the
// pair on the ground in site coordinates, and a least-squares fit of the features'
// navigation-scale offsets to those ground positions gives the camera's absolute
// horizontal position and the pair's metric scale (the baseline length images alone
// cannot observe: docs/refine.md). docs/app.md "Orbital fix" has the method and figures.
//
// No heap after init, no exceptions, bounded loops, deterministic (double geometry with
// + - * / and vtm::math only; the registration's own integer sums).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "vtm/core/arena.hpp"
#include "vtm/core/camera_model.hpp"
#include "vtm/core/eigen.hpp"
#include "vtm/core/image.hpp"
#include "vtm/core/pose.hpp"
#include "vtm/core/status.hpp"
#include "vtm/entropy/registration.hpp"
#include "vtm/refine/pair_refiner.hpp"

namespace vtm::app {

// Where an orbital image lies in the site frame: pixel (col, row), (0, 0) = the centre of
// the NORTH-WEST corner pixel, columns go east, rows go south (a map with north up):
//   north = north0_m - row * cell_m,   east = east0_m + col * cell_m.
struct OrbitalMapGeoreference {
    double north0_m = 0.0;  // site north of pixel (0, 0)'s centre, metres
    double east0_m = 0.0;   // site east of pixel (0, 0)'s centre, metres
    double cell_m = 1.0;    // ground size of a pixel, metres, 1e-3..1e3
};

// The orbital reference: an 8-bit image (image8) or a deeper one (image16 with
// bit_depth 9..16 significant bits), not both. The caller's memory: it must stay valid and
// unchanged while the mapper uses it (static, set once before the requests).
struct OrbitalMap {
    ImageView<const std::uint8_t> image8{};
    ImageView<const std::uint16_t> image16{};
    std::uint8_t bit_depth = 8;
    OrbitalMapGeoreference geo{};
};

// kOk, or kInvalidArgument naming the field ("orbital map: ...").
[[nodiscard]] Status validateOrbitalMap(const OrbitalMap& map) noexcept;

// The registration's defaults with equalisation over the whole image.
[[nodiscard]] inline entropy::RegistrationConfig orbitalRegistrationDefaults() noexcept {
    entropy::RegistrationConfig c;
    c.equalise_radius_px = 0;
    return c;
}

struct OrbitalFixConfig {
    // The locate stage runs (and its memory is planned) only when enabled; it needs the
    // refine stage's inliers (refine_pose).
    bool enabled = false;
    // true: a request whose fix fails ends at locate with the reason; false: the request
    // goes on with the navigation's answer and the stage record says so (quality 0).
    bool required = false;
    // The registration (its capacity bounds both the reduced frame and the orbital cut-out;
    // 3 levels, window 5, 8 bins by default). validate() of its own names its fields.
    // Equalised over the whole frame (equalise_radius_px 0), not the registration's local
    // default: on descent_orbital.scn the local rank put request 2's second frame 6.6
    // orbital px off (docs/app.md "Orbital fix").
    entropy::RegistrationConfig registration = orbitalRegistrationDefaults();
    // Search around the navigation's prediction: rotation +- angle_range_rad (the heading
    // error, 0..pi), scale x (1 +- scale_range) (the altitude error and the relief,
    // 0.01..0.9), shift +- (shift_sigmas x the pose's horizontal position sigma / cell +
    // shift_margin_px) orbital pixels.
    // The frame is halved (2 x 2 means) until its pixel covers at least this fraction of
    // an orbital cell (and it fits the registration's capacity), 0.1..4.
    double min_pixel_cells = 0.5;
    double angle_range_rad = 0.05;
    double scale_range = 0.15;
    double shift_sigmas = 3.0;     // 0..10
    double shift_margin_px = 6.0;  // 0..1000
    // Confidence (besides the registration's own refusals): a frame is used only when its
    // peak NCC reaches min_ncc, its second peak stays below max_peak_ratio of it, and its
    // features fit the located ground within max_residual_px (RMS, orbital pixels). The
    // scale is applied to the baseline only when both frames are used and their scales
    // agree within max_scale_disagreement (a frame's scale is only as good as its
    // registration over its footprint: 0.1-1.6 % measured, docs/app.md).
    double min_ncc = 0.2;                   // 0..1
    double max_peak_ratio = 0.9;            // (0, 1]
    double max_residual_px = 2.0;           // > 0
    double max_scale_disagreement = 0.005;  // > 0, relative
    // ... and only when it changes the navigation's baseline length by at most this
    // fraction (0.5 % +- 0.2 % in the simulator's odometry model: 2 % is a gross error;
    // two frames of 30-40 orbital px once agreed on a scale 2.5 % wrong), (0, 1].
    double max_scale_change = 0.02;
    // The fix is applied only when BOTH frames are used and put camera 1 at places within
    // this many orbital pixels of each other (frame 2's camera moved back by the
    // navigation's baseline): one frame alone was wrong by 11 px once in the evaluation.
    double max_position_disagreement_px = 1.5;  // > 0

    // kOk, or kInvalidConfig naming the field ("orbital.min_ncc: ...").
    [[nodiscard]] Status validate() const noexcept;
};

// One frame located in the orbital map.
struct LocatedFrame {
    Status status{};              // kOk when used; otherwise why not (refusal, confidence)
    bool used = false;
    entropy::Registration registration{};  // reduced frame -> orbital cut-out (diagnosis)
    std::int32_t reduction = 0;   // times the frame was halved before registration
    Vec2 cut_origin_px = Vec2::Zero();  // orbital pixel of the cut-out's pixel (0, 0)
    Vec2 predicted_px = Vec2::Zero();   // the camera's nadir point the navigation predicted, orbital px
    // From this frame alone: the camera's horizontal site position (north, east, metres),
    // the metric scale of the navigation's baseline, and the features' RMS misfit (orbital px).
    Vec2 position_ne_m = Vec2::Zero();
    double scale = 0.0;
    double residual_px = 0.0;
    std::int32_t features = 0;
};

// What the locate stage found and did.
struct OrbitalFix {
    Status status{};              // kOk when the fix was usable; otherwise why not
    bool attempted = false;       // an orbital map was set and the stage ran
    bool applied = false;         // the camera poses were replaced
    std::array<LocatedFrame, 2> frames{};
    // The located scale of the navigation's baseline and whether it was applied: only when
    // both frames were used and agree within max_scale_disagreement (otherwise the
    // navigation's baseline length stays; the position fix does not depend on it).
    double scale = 1.0;
    bool scale_applied = false;
    Vec2 camera1_ne_m = Vec2::Zero();  // camera 1's located horizontal position (applied)
    Vec2 correction_ne_m = Vec2::Zero();  // located minus navigation, camera 1
    double residual_px = 0.0;     // joint fit's RMS misfit, orbital pixels
};

// What locate() reads: the pair as the refine stage left it.
struct LocateInput {
    CameraModel model{};                  // both frames (undistorted pinhole)
    // The frames as captured (8..16 significant bits, the model's size). They are stretched
    // to 8 bits between their own 1st and 99th percentiles before registration: the top 8
    // of 12 bits leave a dim descent frame a few dozen grey levels.
    ImageView<const std::uint16_t> frame1{};
    ImageView<const std::uint16_t> frame2{};
    std::uint8_t bit_depth1 = 12;
    std::uint8_t bit_depth2 = 12;
    RigidPose site_from_cam1{};           // navigation
    RigidPose site_from_cam2{};           // refined relative pose, navigation baseline length
    const refine::Result* refine = nullptr;  // inliers: pixels in both frames, ranges along cam 1's rays
    double position_sigma_m[2] = {0.0, 0.0};  // horizontal 1-sigma of each pose, metres
};

class OrbitalLocator {
public:
    // Arena bytes for this configuration and frame capacity, 0 if invalid.
    [[nodiscard]] static std::size_t workspaceBytes(const OrbitalFixConfig& config, std::int32_t frame_width,
                                                    std::int32_t frame_height) noexcept;
    [[nodiscard]] Status init(const OrbitalFixConfig& config, std::int32_t frame_width, std::int32_t frame_height,
                              Arena& arena) noexcept;
    // Keeps the view (validateOrbitalMap); kNotInitialized before init().
    [[nodiscard]] Status setMap(const OrbitalMap& map) noexcept;
    [[nodiscard]] bool hasMap() const noexcept { return has_map_; }

    // Locates both frames and fits the pair's scale and camera 1's position. Returns kOk
    // when the fix is usable (fix.applied is left to the caller), otherwise the reason
    // (the first frame's, or the pair's); `fix` is filled either way.
    [[nodiscard]] Status locate(const LocateInput& in, OrbitalFix& fix) noexcept;

private:
    [[nodiscard]] Status locateFrame(const LocateInput& in, std::int32_t index, LocatedFrame& out) noexcept;
    [[nodiscard]] Status reduceFrame(const ImageView<const std::uint8_t>& frame, double ground_px_m,
                                     LocatedFrame& out, ImageView<const std::uint8_t>& reduced) noexcept;
    [[nodiscard]] Status predict(const LocateInput& in, std::int32_t index, const ImageView<const std::uint8_t>& reduced,
                                 LocatedFrame& out, entropy::RegistrationRequest& rq,
                                 ImageView<const std::uint8_t>& cut) noexcept;
    [[nodiscard]] Status cutOrbital(const Vec2& lo, const Vec2& hi, LocatedFrame& out,
                                    ImageView<const std::uint8_t>& cut) noexcept;
    [[nodiscard]] bool planeOffset(const LocateInput& in, std::int32_t index, std::size_t j, const Vec3& from,
                                   Vec2& out) const noexcept;
    void fitFrame(const LocateInput& in, std::int32_t index, LocatedFrame& out) const noexcept;
    [[nodiscard]] Status acceptFrame(const LocateInput& in, std::int32_t index, LocatedFrame& out) const noexcept;
    [[nodiscard]] Status fitPair(const LocateInput& in, OrbitalFix& fix) const noexcept;
    // Site north/east of a feature seen at full-resolution `pixel` of frame `index`, through
    // that frame's registration.
    [[nodiscard]] Vec2 groundOf(const LocatedFrame& f, const Vec2& pixel) const noexcept;

    OrbitalFixConfig config_{};
    entropy::EntropyRegistration registration_{};
    OrbitalMap map_{};
    void stretchFrame(const ImageView<const std::uint16_t>& frame, std::uint8_t bit_depth) noexcept;

    ImageView<std::uint8_t> stretched_{};  // the frame at 8 bits (capacity = the frame size)
    Span<std::uint32_t> histogram_{};      // 1024 bins of the frame's top 10 bits
    Span<std::uint8_t> reduce_{};  // the frame's halvings, one after another
    ImageView<std::uint8_t> cut_{};  // the orbital cut-out, 8 bit (capacity)
    double ground_z_m_ = 0.0;       // site z of the inliers' mean (the ground)
    bool initialized_ = false;
    bool has_map_ = false;
};

}  // namespace vtm::app
