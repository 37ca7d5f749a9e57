// Tests of the ICP's parts (fsw/icp, docs/icp.md): the k-d tree against brute force, the
// Jacobi eigen-decomposition against a constructed matrix, the configuration and the
// workspace formula.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "vtm/core/random.hpp"
#include "vtm/icp/icp.hpp"
#include "vtm/icp/kd_tree.hpp"
#include "vtm/icp/symmetric_eigen.hpp"

namespace vtm::icp {
namespace {

std::vector<TreePoint> randomPoints(std::size_t n, std::uint64_t seed) {
    Random rng(seed);
    std::vector<TreePoint> pts(n);
    for (TreePoint& p : pts) {
        // A terrain-like slab: wide in x, y, thin in z, with duplicates every 97th point.
        p = TreePoint{static_cast<float>(rng.uniform01() * 20.0 - 10.0), static_cast<float>(rng.uniform01() * 20.0 - 10.0),
                      static_cast<float>(rng.uniform01() * 0.5)};
    }
    for (std::size_t i = 97; i < n; i += 97) {
        pts[i] = pts[i - 1];
    }
    return pts;
}

TEST(KdTree, NearestNeighboursEqualBruteForce) {
    const std::vector<TreePoint> pts = randomPoints(2001, 1U);
    std::vector<std::byte> pool(KdTree::workspaceBytes(pts.size(), 8));
    Arena arena(pool.data(), pool.size());
    KdTree tree;
    ASSERT_TRUE(tree.init(pts.size(), 8, 4096, arena));
    tree.build(Span<const TreePoint>(pts.data(), pts.size()));
    Random rng(2U);
    for (int q = 0; q < 200; ++q) {
        const double x = rng.uniform01() * 22.0 - 11.0;
        const double y = rng.uniform01() * 22.0 - 11.0;
        const double z = rng.uniform01() * 1.0 - 0.25;
        const std::int32_t k = 1 + q % 12;
        const double radius2 = (q % 3 == 0) ? 0.09 : 1e9;
        std::vector<std::pair<double, std::int32_t>> all;
        for (std::size_t i = 0; i < pts.size(); ++i) {
            const double dx = static_cast<double>(pts[i].x) - x;
            const double dy = static_cast<double>(pts[i].y) - y;
            const double dz = static_cast<double>(pts[i].z) - z;
            const double d2 = dx * dx + dy * dy + dz * dz;
            if (d2 <= radius2) {
                all.emplace_back(d2, static_cast<std::int32_t>(i));
            }
        }
        std::sort(all.begin(), all.end());
        Neighbours nb;
        tree.nearest(x, y, z, k, radius2, nb);
        ASSERT_EQ(nb.count, std::min<std::int32_t>(k, static_cast<std::int32_t>(all.size()))) << q;
        EXPECT_FALSE(nb.truncated);
        for (std::int32_t j = 0; j < nb.count; ++j) {
            EXPECT_EQ(nb.index[j], all[static_cast<std::size_t>(j)].second) << q << " " << j;
            EXPECT_EQ(nb.distance2[j], all[static_cast<std::size_t>(j)].first);
        }
    }
}

TEST(KdTree, BoundedQueriesSayWhenTheyStoppedEarly) {
    const std::vector<TreePoint> pts = randomPoints(4000, 3U);
    std::vector<std::byte> pool(KdTree::workspaceBytes(pts.size(), 4));
    Arena arena(pool.data(), pool.size());
    KdTree tree;
    ASSERT_TRUE(tree.init(pts.size(), 4, 1, arena));
    tree.build(Span<const TreePoint>(pts.data(), pts.size()));
    // k = 32 from a leaf of at most 4 points cannot be exact after one leaf.
    Neighbours nb;
    tree.nearest(0.0, 0.0, 0.25, 32, 1e9, nb);
    EXPECT_TRUE(nb.truncated);
    EXPECT_LE(nb.count, 4);
    EXPECT_GE(nb.count, 1);
}

TEST(SymmetricEigen, RecoversAConstructedDecomposition) {
    Random rng(5U);
    for (int trial = 0; trial < 50; ++trial) {
        Eigen::Matrix<double, 6, 6> m;
        for (int i = 0; i < 36; ++i) {
            m(i / 6, i % 6) = rng.uniform01() - 0.5;
        }
        // An orthonormal basis by Gram-Schmidt (Eigen's HouseholderQR trips a GCC loop
        // warning on the 32-bit SPARC build).
        Eigen::Matrix<double, 6, 6> q = m;
        for (int c = 0; c < 6; ++c) {
            for (int prev = 0; prev < c; ++prev) {
                q.col(c) -= q.col(prev).dot(q.col(c)) * q.col(prev);
            }
            q.col(c).normalize();
        }
        Eigen::Matrix<double, 6, 1> lambda;
        lambda << 1e-6, 0.01, 0.5, 1.0, 3.0, 100.0;
        const Eigen::Matrix<double, 6, 6> a = q * lambda.asDiagonal() * q.transpose();
        Eigen::Matrix<double, 6, 1> values;
        Eigen::Matrix<double, 6, 6> vectors;
        symmetricEigen<6>(a, values, vectors);
        for (int i = 0; i < 6; ++i) {
            EXPECT_NEAR(values(i), lambda(i), 1e-12 * 100.0) << trial;
            EXPECT_NEAR(std::fabs(vectors.col(i).dot(q.col(i))), 1.0, 1e-9) << trial << " " << i;
        }
    }
    // A 3x3 plane scatter: the normal is the smallest eigenvector.
    Mat3 s = Mat3::Zero();
    s.diagonal() << 4.0, 1e-4, 2.0;
    Vec3 v;
    Mat3 vec;
    symmetricEigen<3>(s, v, vec);
    EXPECT_EQ(v(0), 1e-4);
    EXPECT_EQ(std::fabs(vec(1, 0)), 1.0);
}

TEST(IcpConfig, EveryBadFieldIsNamedAndTheWorkspaceFits) {
    const std::vector<std::pair<void (*)(IcpConfig&), const char*>> cases = {
        {[](IcpConfig& c) { c.max_model_points = 8; }, "icp.max_model_points"},
        {[](IcpConfig& c) { c.max_data_points = 1 << 20; }, "icp.max_data_points"},
        {[](IcpConfig& c) { c.leaf_size = 1; }, "icp.leaf_size"},
        {[](IcpConfig& c) { c.max_leaves = 0; }, "icp.max_leaves"},
        {[](IcpConfig& c) { c.normal_neighbours = 40; }, "icp.normal_neighbours"},
        {[](IcpConfig& c) { c.normal_radius_m = 0.0; }, "icp.normal_radius_m"},
        {[](IcpConfig& c) { c.max_surface_variation = 0.5; }, "icp.max_surface_variation"},
        {[](IcpConfig& c) { c.min_gate_m = std::nan(""); }, "icp.min_gate_m"},
        {[](IcpConfig& c) { c.initial_gate_m = 0.1; }, "icp.initial_gate_m"},
        {[](IcpConfig& c) { c.gate_shrink = 1.5; }, "icp.gate_shrink"},
        {[](IcpConfig& c) { c.huber_k = -1.0; }, "icp.huber_k"},
        {[](IcpConfig& c) { c.min_sigma_m = 0.0; }, "icp.min_sigma_m"},
        {[](IcpConfig& c) { c.max_iterations = 0; }, "icp.max_iterations"},
        {[](IcpConfig& c) { c.converge_rotation_rad = 0.0; }, "icp.converge_rotation_rad"},
        {[](IcpConfig& c) { c.converge_translation_m = -1.0; }, "icp.converge_translation_m"},
        {[](IcpConfig& c) { c.min_overlap = 0.0; }, "icp.min_overlap"},
        {[](IcpConfig& c) { c.min_correspondences = 5; }, "icp.min_correspondences"},
        {[](IcpConfig& c) { c.min_eigen_ratio = 1.0; }, "icp.min_eigen_ratio"},
    };
    for (const auto& [mutate, name] : cases) {
        IcpConfig c;
        mutate(c);
        const Status s = c.validate();
        EXPECT_EQ(s.code(), StatusCode::kInvalidConfig) << name;
        EXPECT_EQ(std::string(s.reason()).rfind(name, 0), 0U) << s.reason();
        EXPECT_EQ(PointToPlaneIcp::workspaceBytes(c), 0U) << name;
        PointToPlaneIcp icp;
        std::byte one[16];
        Arena tiny(one, sizeof one);
        EXPECT_EQ(icp.init(c, tiny).code(), StatusCode::kInvalidConfig) << name;
    }
    // The default flight configuration: an arena of exactly workspaceBytes is enough (with a
    // pool misaligned by 1..15 bytes too), half of it is kOutOfMemory.
    const IcpConfig c;
    ASSERT_TRUE(c.validate().isOk());
    const std::size_t bytes = PointToPlaneIcp::workspaceBytes(c);
    std::printf("[ MEASURED ] default workspace %zu bytes\n", bytes);
    std::unique_ptr<std::byte[]> pool(new std::byte[bytes + 16U]);
    for (std::size_t shift : {0U, 1U, 8U, 15U}) {
        Arena exact(pool.get() + shift, bytes);
        PointToPlaneIcp icp;
        EXPECT_TRUE(icp.init(c, exact).isOk()) << shift;
    }
    Arena half(pool.get(), bytes / 2U);
    PointToPlaneIcp icp;
    const Status s = icp.init(c, half);
    EXPECT_EQ(s.code(), StatusCode::kOutOfMemory);
    EXPECT_EQ(s.detail(), static_cast<std::int64_t>(bytes));
}

}  // namespace
}  // namespace vtm::icp
