// Tests of the point-to-plane ICP (fsw/icp, docs/icp.md) against ground truth: synthetic
// terrain clouds moved by known rigid motions (icp_scene.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "icp_scene.hpp"
#include "no_heap_guard.hpp"
#include "vtm/icp/icp.hpp"

namespace vtm::icp {
namespace {

using test::Patch;

// A module with its arena on the heap (before any NoHeapScope).
struct Fixture {
    explicit Fixture(const IcpConfig& c = IcpConfig{})
        : bytes(PointToPlaneIcp::workspaceBytes(c)), pool(new std::byte[bytes]), arena(pool.get(), bytes) {
        status = icp.init(c, arena);
    }
    std::size_t bytes;
    std::unique_ptr<std::byte[]> pool;
    Arena arena;
    PointToPlaneIcp icp;
    Status status;
};

// Test capacities: the data clouds below (2,500-3,600 points) are subsampled to 2,048.
IcpConfig smallConfig() {
    IcpConfig c;
    c.max_model_points = 8192;
    c.max_data_points = 2048;
    return c;
}

const Patch kModelPatch{-10.0, 10.0, -10.0, 10.0};   // 20 m x 20 m
const Patch kDataPatch{-2.0, 18.0, -10.0, 10.0};     // 60 % of it over the model

std::vector<Vec3> modelCloud(std::uint64_t seed, bool flat = false, double spacing_m = 0.25) {
    return test::sampleCloud(kModelPatch, spacing_m, seed, 0.01, RigidPose{}, flat);
}

Span<const Vec3> span(const std::vector<Vec3>& v) { return Span<const Vec3>(v.data(), v.size()); }

// One terrain model (4,356 points, 1 cm noise) and one module holding it, built once per
// process: the tests run under qemu on every target, where building the cloud and its
// normals is most of their time.
const std::vector<Vec3>& sharedModel() {
    static const std::vector<Vec3> model = modelCloud(1U, false, 0.3);
    return model;
}

PointToPlaneIcp& sharedIcp() {
    static Fixture f(smallConfig());
    static const bool ready = f.status.isOk() && f.icp.setModel(span(sharedModel())).isOk();
    EXPECT_TRUE(ready);
    return f.icp;
}

TEST(PointToPlaneIcp, RecoversAKnownMotionWithNoiseAndPartialOverlap) {
    PointToPlaneIcp& icp = sharedIcp();
    const RigidPose truth = test::motion(1.0, -0.8, 2.5, Vec3(0.4, -0.3, 0.12));
    const std::vector<Vec3> data = test::sampleCloud(kDataPatch, 0.33, 2U, 0.01, truth);
    IcpResult r;
    const Status s = icp.registerData(span(data), RigidPose{}, r);
    ASSERT_TRUE(s.isOk()) << s.reason() << " " << s.detail();
    const double rotDeg = test::rotationErrorDeg(r.model_from_data.R, truth.R);
    const double transM = (r.model_from_data.t_m - truth.t_m).norm();
    std::printf("[ MEASURED ] rotation %.5f deg, translation %.5f m, rms %.4f m, overlap %.3f, iterations %d, "
                "eigen ratio %.4f, data %d\n",
                rotDeg, transM, r.rms_residual_m, r.overlap, r.iterations, r.eigen_ratio, r.data_points_used);
    EXPECT_LE(rotDeg, 0.05);
    EXPECT_LE(transM, 0.01);
    EXPECT_EQ(r.stop, StopReason::kConverged);
    // 3,600 points subsampled to the capacity.
    ASSERT_EQ(data.size(), 3600U);
    EXPECT_EQ(r.data_points_used, 2048);
    // The data patch overlaps the model patch over 12 of its 20 m.
    EXPECT_NEAR(r.overlap, 0.6, 0.05);
    // Noise of 1 cm per axis in both clouds: the point-to-plane residual is about 1.4 cm.
    EXPECT_GT(r.rms_residual_m, 0.008);
    EXPECT_LT(r.rms_residual_m, 0.025);
}

TEST(PointToPlaneIcp, CovarianceIsConsistentWithTheErrorsOverSeededDraws) {
    PointToPlaneIcp& icp = sharedIcp();
    int within = 0;
    int beyond4 = 0;
    int total = 0;
    double chi2 = 0.0;
    for (std::uint64_t seed = 0; seed < 5U; ++seed) {
        const RigidPose truth = test::motion(0.5 * static_cast<double>(seed) - 1.0, 0.7, 1.5 - 0.6 * static_cast<double>(seed),
                                             Vec3(0.3 - 0.1 * static_cast<double>(seed), 0.2, -0.1));
        const std::vector<Vec3> data = test::sampleCloud(kDataPatch, 0.5, 100U + seed, 0.01, truth);
        IcpResult r;
        ASSERT_TRUE(icp.registerData(span(data), RigidPose{}, r).isOk());
        Vec6 e;
        e.head<3>() = test::rotationErrorVector(r.model_from_data.R, truth.R);
        e.tail<3>() = r.model_from_data.t_m - truth.t_m;
        chi2 += e.dot(r.covariance.ldlt().solve(e));
        std::printf("\n[ MEASURED ] seed %d: sigmas rot %.4f %.4f %.4f deg, t %.4f %.4f %.4f m; e/sigma: ", static_cast<int>(seed),
                    std::sqrt(r.covariance(0, 0)) * 57.3, std::sqrt(r.covariance(1, 1)) * 57.3, std::sqrt(r.covariance(2, 2)) * 57.3,
                    std::sqrt(r.covariance(3, 3)), std::sqrt(r.covariance(4, 4)), std::sqrt(r.covariance(5, 5)));
        for (int i = 0; i < 6; ++i) {
            const double sigma = std::sqrt(r.covariance(i, i));
            ASSERT_GT(sigma, 0.0);
            within += std::fabs(e(i)) <= 3.0 * sigma ? 1 : 0;
            beyond4 += std::fabs(e(i)) > 4.0 * sigma ? 1 : 0;
            std::printf("%+.2f ", e(i) / sigma);
            ++total;
        }
    }
    std::printf("[ MEASURED ] %d of %d error components within 3 sigma; mean chi2 per draw %.2f (6 expected)\n",
                within, total, chi2 / 5.0);
    // Bounds a consistent covariance meets with probability > 0.99: no component beyond
    // 4 sigma (P(|z| > 4) = 6.3e-5 each, 30 of them) and the sum of the five Mahalanobis
    // squares (chi-square, 30 degrees of freedom) below 60 (P = 0.001), mean below 12.
    EXPECT_EQ(beyond4, 0);
    EXPECT_LT(chi2 / 5.0, 12.0);
    EXPECT_GE(within, total - 3);
}

TEST(PointToPlaneIcp, FlatPlaneIsRefusedAsAmbiguous) {
    Fixture f(smallConfig());
    ASSERT_TRUE(f.status.isOk());
    const std::vector<Vec3> model = modelCloud(3U, true, 0.4);
    ASSERT_TRUE(f.icp.setModel(span(model)).isOk());
    const RigidPose guess = test::motion(0.0, 0.0, 1.0, Vec3(0.2, 0.1, 0.0));
    const RigidPose truth = test::motion(0.0, 0.0, 0.0, Vec3(0.0, 0.0, 0.05));
    const std::vector<Vec3> data = test::sampleCloud(kDataPatch, 0.4, 4U, 0.01, truth, true);
    IcpResult r;
    const Status s = f.icp.registerData(span(data), guess, r);
    std::printf("[ MEASURED ] flat plane: eigen ratio %.2e\n", r.eigen_ratio);
    EXPECT_EQ(s.code(), StatusCode::kDegenerate);
    EXPECT_NE(std::string(s.reason()).find("ambiguous"), std::string::npos);
    // The weakest direction is a translation in the plane or the rotation about its normal.
    EXPECT_TRUE(s.detail() == 2 || s.detail() == 3 || s.detail() == 4) << s.detail();
    EXPECT_EQ(r.stop, StopReason::kRefused);
    // Nothing published: the guess back, no covariance.
    EXPECT_EQ(r.model_from_data.t_m, guess.t_m);
    EXPECT_EQ(r.covariance, Mat6::Zero());
}

TEST(PointToPlaneIcp, DisjointAndBarelyOverlappingCloudsAreRefusedForOverlap) {
    PointToPlaneIcp& icp = sharedIcp();
    const std::vector<Vec3> far = test::sampleCloud(Patch{40.0, 60.0, -10.0, 10.0}, 0.6, 6U, 0.01, RigidPose{});
    IcpResult r;
    Status s = icp.registerData(span(far), RigidPose{}, r);
    EXPECT_EQ(s.code(), StatusCode::kDegenerate);
    EXPECT_NE(std::string(s.reason()).find("overlap"), std::string::npos);
    EXPECT_EQ(s.detail(), 0);
    // 2 m of a 20 m patch over the model: 10 %, below min_overlap 0.3.
    const std::vector<Vec3> edge = test::sampleCloud(Patch{8.0, 28.0, -10.0, 10.0}, 0.6, 7U, 0.01, RigidPose{});
    s = icp.registerData(span(edge), RigidPose{}, r);
    EXPECT_EQ(s.code(), StatusCode::kDegenerate);
    EXPECT_NE(std::string(s.reason()).find("overlap"), std::string::npos);
    EXPECT_LT(s.detail(), 300);
    EXPECT_EQ(r.covariance, Mat6::Zero());
}

TEST(PointToPlaneIcp, BadInputsGiveNamedStatuses) {
    IcpConfig c = smallConfig();
    c.max_model_points = 2000;
    Fixture f(c);
    ASSERT_TRUE(f.status.isOk());
    std::vector<Vec3> model = test::sampleCloud(Patch{-5.0, 5.0, -5.0, 5.0}, 0.3, 8U, 0.01, RigidPose{});
    IcpResult r;
    EXPECT_EQ(f.icp.registerData(span(model), RigidPose{}, r).code(), StatusCode::kNotInitialized);
    PointToPlaneIcp uninitialised;
    EXPECT_EQ(uninitialised.setModel(span(model)).code(), StatusCode::kNotInitialized);
    // Too many points: the count in the detail.
    const std::vector<Vec3>& big = sharedModel();
    Status s = f.icp.setModel(span(big));
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(s.detail(), static_cast<std::int64_t>(big.size()));
    EXPECT_NE(std::string(s.reason()).find("max_model_points"), std::string::npos);
    // A NaN: its index.
    model[123].y() = std::nan("");
    s = f.icp.setModel(span(model));
    EXPECT_EQ(s.code(), StatusCode::kCorruptData);
    EXPECT_EQ(s.detail(), 123);
    model[123].y() = 0.0;
    ASSERT_TRUE(f.icp.setModel(span(model)).isOk());
    std::vector<Vec3> data = model;
    data[77].z() = std::numeric_limits<double>::infinity();
    s = f.icp.registerData(span(data), RigidPose{}, r);
    EXPECT_EQ(s.code(), StatusCode::kCorruptData);
    EXPECT_EQ(s.detail(), 77);
    EXPECT_EQ(f.icp.registerData(Span<const Vec3>(), RigidPose{}, r).code(), StatusCode::kInvalidArgument);
    RigidPose scaled;
    scaled.R *= 1.1;
    s = f.icp.registerData(span(model), scaled, r);
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
    EXPECT_NE(std::string(s.reason()).find("model_from_data_guess"), std::string::npos);
    RigidPose nanPose;
    nanPose.t_m.x() = std::nan("");
    EXPECT_EQ(f.icp.registerData(span(model), nanPose, r).code(), StatusCode::kInvalidArgument);
    // Too few points to fit.
    EXPECT_EQ(f.icp.setModel(Span<const Vec3>(model.data(), 50)).code(), StatusCode::kInvalidArgument);
}

TEST(PointToPlaneIcp, TwoRunsGiveTheSameBitsAndTouchNoHeap) {
    Fixture f(smallConfig());
    ASSERT_TRUE(f.status.isOk());
    const std::vector<Vec3> model = test::sampleCloud(Patch{-6.0, 6.0, -6.0, 6.0}, 0.3, 14U, 0.01, RigidPose{});
    const RigidPose truth = test::motion(-0.5, 0.4, 1.2, Vec3(0.2, 0.1, -0.05));
    const std::vector<Vec3> data = test::sampleCloud(Patch{-3.0, 9.0, -6.0, 6.0}, 0.4, 15U, 0.01, truth);
    IcpResult a;
    IcpResult b;
    {
        vtm::test::NoHeapScope guard;
        ASSERT_TRUE(f.icp.setModel(span(model)).isOk());
        ASSERT_TRUE(f.icp.registerData(span(data), RigidPose{}, a).isOk());
        ASSERT_TRUE(f.icp.setModel(span(model)).isOk());
        ASSERT_TRUE(f.icp.registerData(span(data), RigidPose{}, b).isOk());
        EXPECT_EQ(guard.heapCalls(), 0U);
    }
    EXPECT_EQ(std::memcmp(a.model_from_data.R.data(), b.model_from_data.R.data(), sizeof(Mat3)), 0);
    EXPECT_EQ(std::memcmp(a.model_from_data.t_m.data(), b.model_from_data.t_m.data(), sizeof(Vec3)), 0);
    EXPECT_EQ(std::memcmp(a.covariance.data(), b.covariance.data(), sizeof(Mat6)), 0);
    EXPECT_EQ(a.iterations, b.iterations);
}

}  // namespace
}  // namespace vtm::icp
