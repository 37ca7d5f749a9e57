#include <gtest/gtest.h>

#include <cstring>

#include "vtm/core/status.hpp"

namespace vtm {
namespace {

Status failWhenNegative(int v) {
    if (v < 0) {
        return Status(StatusCode::kInvalidArgument, "v: must be >= 0", v);
    }
    return Status::ok();
}

Status chain(int v, int* reached) {
    VTM_RETURN_IF_ERROR(failWhenNegative(v));
    *reached = 1;
    return Status::ok();
}

TEST(Status, DefaultIsOkWithEmptyReason) {
    const Status s;
    EXPECT_TRUE(s.isOk());
    EXPECT_EQ(s.code(), StatusCode::kOk);
    EXPECT_STREQ(s.reason(), "");
    EXPECT_EQ(s.detail(), 0);
}

TEST(Status, CarriesCodeReasonAndDetail) {
    const Status s = failWhenNegative(-7);
    EXPECT_FALSE(s.isOk());
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
    EXPECT_STREQ(s.reason(), "v: must be >= 0");
    EXPECT_EQ(s.detail(), -7);
}

TEST(Status, NullReasonBecomesEmptyString) {
    const Status s(StatusCode::kTimeout, nullptr);
    ASSERT_NE(s.reason(), nullptr);
    EXPECT_STREQ(s.reason(), "");
}

TEST(Status, ReturnIfErrorStopsAtFirstFailure) {
    int reached = 0;
    EXPECT_EQ(chain(-1, &reached).code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(reached, 0);
    EXPECT_TRUE(chain(3, &reached).isOk());
    EXPECT_EQ(reached, 1);
}

TEST(Status, EveryCodeHasADistinctName) {
    const StatusCode codes[] = {
        StatusCode::kOk,          StatusCode::kInvalidArgument, StatusCode::kInvalidConfig,
        StatusCode::kOutOfMemory, StatusCode::kSizeMismatch,    StatusCode::kNoData,
        StatusCode::kTimeout,     StatusCode::kCorruptData,     StatusCode::kNotInitialized,
        StatusCode::kDegenerate,  StatusCode::kUnsupported,     StatusCode::kIoError,
        StatusCode::kOutOfOrder};
    for (std::size_t i = 0; i < sizeof(codes) / sizeof(codes[0]); ++i) {
        EXPECT_STRNE(statusCodeName(codes[i]), "unknown");
        for (std::size_t j = 0; j < i; ++j) {
            EXPECT_STRNE(statusCodeName(codes[i]), statusCodeName(codes[j]));
        }
    }
    EXPECT_STREQ(statusCodeName(static_cast<StatusCode>(200)), "unknown");
}

}  // namespace
}  // namespace vtm
