// Limits shared by the detector, the template matcher and the affine refinement (private to
// fsw/features).
#pragma once

#include <cstdint>

namespace vtm::features::detail {

// The largest image side any of the module's configurations accepts.
constexpr std::int32_t kMaxCapacityPx = 4096;

// A local affine warp is trusted only inside these bounds (beyond them the plane is seen
// almost edge-on from one camera, or from its back side by the other): area ratio det M in
// [1/kMaxWarpArea, kMaxWarpArea] and every entry within +-kMaxWarpEntry.
constexpr double kMaxWarpArea = 16.0;
constexpr double kMaxWarpEntry = 8.0;

}  // namespace vtm::features::detail
