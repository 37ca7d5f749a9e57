// PDS3 image files with an attached label, as the MER cameras' EDR/RDR products are
// archived (e.g. 1N491020376ILFCNY9P0706L0M1.IMG): the image, the camera model of the
// label's GEOMETRIC_CAMERA_MODEL group and the rover's pose in the site frame
// (docs/pds.md has the fields, the conventions and how they were verified).
//
// Image: the OBJECT = IMAGE of the label at ^IMAGE (a 1-based record number times
// RECORD_BYTES, or "N <BYTES>", a 1-based byte number), LINES x LINE_SAMPLES samples,
// BANDS = 1, no line prefix/suffix bytes, SAMPLE_BITS 8 (UNSIGNED_INTEGER,
// MSB_UNSIGNED_INTEGER, LSB_UNSIGNED_INTEGER) or 16 (MSB_INTEGER, MSB_UNSIGNED_INTEGER,
// UNSIGNED_INTEGER, LSB_INTEGER, LSB_UNSIGNED_INTEGER, with their explicit byte order);
// a negative sample of a signed type is refused. Rows from the top, as stored.
//
// Camera model (in the frame REFERENCE_COORD_SYSTEM_NAME names, ROVER_FRAME on MER):
// MODEL_TYPE CAHV (MODEL_COMPONENT_1..4 = C A H V) or CAHVOR (1..6 = C A H V O R) ->
// vtm::CameraModel kCahv / kCahvor, width/height = LINE_SAMPLES/LINES. The label prints
// 6 significant digits, so |A| differs from 1 by up to ~1e-6: A, H and V are divided by
// |A|, which leaves the projection x = (P-C).H / (P-C).A exactly as it was (|A| must be
// within 1e-3 of 1). The model must then pass vtm::validateCameraModel.
//
// Rover pose: the group whose COORDINATE_SYSTEM_NAME is ROVER_FRAME and whose
// REFERENCE_COORD_SYSTEM_NAME is SITE_FRAME (other groups carry the same keys for the
// arm and the mast, in the rover frame): ORIGIN_OFFSET_VECTOR = t (the rover frame's
// origin in the site frame, metres) and ORIGIN_ROTATION_QUATERNION = (s, v1, v2, v3),
// the rotation of the rover frame into the site frame: X_site = R(q) X_rover + t, R(q)
// the usual (Hamilton) rotation matrix of the unit quaternion s + v1 i + v2 j + v3 k.
// |q| must be within 1e-3 of 1 (normalised). Checked on the real frames in
// tests/tools/pds_image_test.cpp against the label's own site-frame pointing.
//
// Errors: one line naming the file, the field and the reason, e.g.
// "x.IMG: PDS label: LINES in OBJECT IMAGE must be an integer 1..16384, got \"-3\"".
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "vtm/core/camera_model.hpp"
#include "vtm/core/pose.hpp"
#include "vtm/ground/image.hpp"
#include "vtm/ground/pds_label.hpp"

namespace vtm::ground {

constexpr std::uint64_t kMaxPdsImageSide = 16384;
constexpr std::uint64_t kMaxPdsFileBytes = std::uint64_t{1} << 30;  // 1 GiB

// The label's pointing of the instrument in one frame, degrees; `valid` false when the
// label has no such group or says "NULL" (MER's Hazcam frames). MER labels count
// azimuth clockwise from +x towards +y, and ELEVATION POSITIVE DOWNWARDS (towards +z of
// the z-down frames) although their coordinate-system groups say
// POSITIVE_ELEVATION_DIRECTION = UP: verified on the data (docs/pds.md).
struct PdsPointing {
    bool valid = false;
    double azimuth_deg = 0.0;
    double elevation_deg = 0.0;
};

struct PdsImageInfo {
    std::uint64_t record_bytes = 0;    // RECORD_BYTES
    std::uint64_t image_offset = 0;    // byte of the first sample (from ^IMAGE)
    std::int32_t lines = 0;            // LINES
    std::int32_t line_samples = 0;     // LINE_SAMPLES
    std::int32_t sample_bits = 0;      // SAMPLE_BITS: 8 or 16
    std::string sample_type;           // SAMPLE_TYPE, e.g. MSB_INTEGER
    std::string instrument_id;         // INSTRUMENT_ID, e.g. NAVCAM_LEFT ("" if absent)
    std::string start_time;            // START_TIME, UTC text ("" if absent)
    std::string product_id;            // PRODUCT_ID ("" if absent)
    std::string model_type;            // MODEL_TYPE of the camera model group ("" if none)
    std::string model_frame;           // its REFERENCE_COORD_SYSTEM_NAME
    PdsPointing rover_pointing;        // ROVER_DERIVED_GEOMETRY_PARMS INSTRUMENT_AZIMUTH/ELEVATION
    PdsPointing site_pointing;         // SITE_DERIVED_GEOMETRY_PARMS
};

struct PdsImage {
    PdsImageInfo info;
    Grey16Image pixels;                // the samples as stored (8-bit samples widened)
    bool has_camera_model = false;
    CameraModel camera_model{};        // in info.model_frame (ROVER_FRAME on MER)
    bool has_rover_pose = false;
    RigidPose site_from_rover{};
};

// What must be present. A frame without it (the Hazcam's CAHVORE model, say) is refused
// naming what is missing; with the flag off it is read without.
struct PdsReadOptions {
    bool require_camera_model = true;
    bool require_rover_pose = true;
};

// From the bytes of a whole file; `name` (usually the path) starts the errors.
Result<PdsImage> decodePdsImage(const std::vector<unsigned char>& bytes, const std::string& name,
                                const PdsReadOptions& options = PdsReadOptions{});
Result<PdsImage> readPdsImage(const std::string& path, const PdsReadOptions& options = PdsReadOptions{});

// The label's parts on their own (decodePdsImage uses them, and checks the camera model and
// the pose before it checks that the file holds the samples).
Result<PdsImageInfo> pdsImageInfo(const PdsLabel& label, const std::string& name);
// kCahv/kCahvor from the label's camera model group; validated.
Result<CameraModel> pdsCameraModel(const PdsLabel& label, std::int32_t width, std::int32_t height,
                                   const std::string& name);
// site_from_rover from the ROVER_FRAME group (see above).
Result<RigidPose> pdsSiteFromRover(const PdsLabel& label, const std::string& name);

// An 8-bit view for the feature matcher: a linear stretch of [lo, hi] to [0, 255]
// (rounded, clamped), lo and hi the samples at the low_fraction and high_fraction
// quantiles of the image's histogram (default 0.5 % and 99.5 %: a few hot pixels or
// shadows do not set the contrast). Integer arithmetic: the same bytes on every host.
GreyImage pdsStretchToGrey8(const Grey16Image& image, double low_fraction = 0.005, double high_fraction = 0.995);

}  // namespace vtm::ground
