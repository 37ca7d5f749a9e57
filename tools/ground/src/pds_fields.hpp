// Field access with the error messages of the PDS readers (pds_image.cpp, pds_geometry.cpp):
// every message names the input, the field with its GROUP/OBJECT and the reason.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "vtm/ground/pds_label.hpp"

namespace vtm::ground::detail {

struct PdsFields {
    const PdsLabel& label;
    const std::string& name;

    // "LINES in OBJECT IMAGE" / "RECORD_BYTES" (top level): scopes as written.
    [[nodiscard]] static std::string where(const std::string& scope, const std::string& key);
    [[nodiscard]] std::string missing(const std::string& scope, const std::string& key) const;
    [[nodiscard]] std::string bad(const PdsStatement& s, const std::string& reason) const;
    // Required unsigned integer in [min_value, max_value].
    [[nodiscard]] std::string unsignedField(const std::string& scope, const std::string& key, std::uint64_t min_value,
                                            std::uint64_t max_value, std::uint64_t& out) const;
    // Required list of n finite reals.
    [[nodiscard]] std::string realsField(const std::string& scope, const std::string& key, std::size_t n,
                                         std::vector<double>& out) const;
};

// The scope of the camera model group (GEOMETRIC_CAMERA_MODEL on MER,
// GEOMETRIC_CAMERA_MODEL_PARMS on MSL), "" if the label has none.
std::string pdsCameraModelGroup(const PdsLabel& label);
// The scope of the group with COORDINATE_SYSTEM_NAME = ROVER_FRAME and
// REFERENCE_COORD_SYSTEM_NAME = SITE_FRAME (the first, in label order), "" if none.
std::string pdsRoverFrameGroup(const PdsLabel& label);
inline bool pdsHasRoverFrame(const PdsLabel& label) { return !pdsRoverFrameGroup(label).empty(); }

}  // namespace vtm::ground::detail
