// The OpenCV peer of the traverse-and-descent evaluation: cv::ppf_match_3d::ICP and
// fsw/icp's PointToPlaneIcp on the same clouds from the same guess (stop k, odometry guess,
// against stop k-1 at its true pose; the descent map, identity guess, against every stop
// at its true pose). Prints the table and who wins where; a skip line without the contrib
// module. Host only (traverse_fusion_evaluation.cpp).
#pragma once

#include <vector>

#include "fusion_measures.hpp"
#include "vtm/icp/icp.hpp"

namespace vtm::traverse {

void comparePeer(const Truth& truth, const icp::IcpConfig& config, const std::vector<app::AddResult>& integrated);

}  // namespace vtm::traverse
