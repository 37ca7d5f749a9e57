// Shared by the Middlebury tests of this folder: where the data is, and scoring a
// disparity image with vtm_ground's evaluator (non-occluded masks, no match = bad).
#pragma once

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "test_data.hpp"
#include "vtm/ground/disparity_evaluation.hpp"
#include "vtm/ground/middlebury.hpp"
#include "vtm/peer/peer_stereo.hpp"

namespace vtm::peer::fixture {

// The shared data root (tests/support/test_data.hpp); loadMiddleburyPair finds middlebury/SET in it.
inline std::string dataDir() { return vtm::test::testDataRoot(); }

// Skips the test (fails under VTM_REQUIRE_DATA=1) when the set is not there.
#define VTM_REQUIRE_MIDDLEBURY(set) VTM_REQUIRE_TEST_DATA(vtm::test::testDataSet("middlebury") + (set))

// Largest known ground-truth disparity of the pair, pixels (numDisparities follows it).
inline double maxKnownDisparity(const ground::MiddleburyPair& pair) {
    double m = 0.0;
    for (const float d : pair.truth.disparity_px.pixels) {
        m = ground::isKnownDisparity(d) && d > m ? d : m;
    }
    return m;
}

inline ground::FloatImage toFloatImage(const cv::Mat& disparity_px) {
    ground::FloatImage px(disparity_px.cols, disparity_px.rows);
    copyDisparity(disparity_px, px.view());
    return px;
}

// bad>1 (and the rest) over `mask`, or the pair's non-occluded mask.
inline ground::DisparityErrors score(const ground::FloatImage& estimate, const ground::MiddleburyPair& pair,
                                     const ground::GreyImage* mask = nullptr) {
    const auto r = ground::evaluateDisparity(estimate, pair.truth.disparity_px,
                                             mask != nullptr ? mask : &pair.truth.nonoccluded);
    EXPECT_TRUE(r.ok) << r.error;
    return r.value;
}

}  // namespace vtm::peer::fixture
