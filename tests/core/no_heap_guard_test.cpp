// The guard itself must catch every way code can reach the heap; otherwise a zero
// count in a module test would prove nothing.
// This file deliberately uses Eigen's dynamic matrices to prove the guard sees them.
#undef EIGEN_NO_MALLOC
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/LU>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "no_heap_guard.hpp"

namespace {

template <typename F>
std::uint64_t heapCallsOf(F&& f) {
    vtm::test::NoHeapScope guard;
    f();
    return guard.heapCalls();
}

// Opaque to the optimiser, so that allocation/free pairs are not elided.
void* volatile g_sink = nullptr;

TEST(NoHeapGuard, CountsOperatorNewAndDelete) {
    EXPECT_GE(heapCallsOf([] {
                  int* p = new int(3);
                  g_sink = p;
                  delete p;
              }),
              2U);
    EXPECT_GE(heapCallsOf([] {
                  auto* p = new double[10];
                  g_sink = p;
                  delete[] p;
              }),
              2U);
}

TEST(NoHeapGuard, CountsCAllocator) {
    EXPECT_GE(heapCallsOf([] {
                  void* p = std::malloc(16);
                  g_sink = p;
                  std::free(p);
              }),
              2U);
    EXPECT_GE(heapCallsOf([] {
                  void* p = std::calloc(4, 4);
                  g_sink = p;
                  p = std::realloc(p, 64);
                  g_sink = p;
                  std::free(p);
              }),
              3U);
}

TEST(NoHeapGuard, CountsLibraryContainersAndEigenDynamicMatrices) {
    EXPECT_GT(heapCallsOf([] {
                  std::vector<int> v(100, 1);
                  g_sink = v.data();
              }),
              0U);
    EXPECT_GT(heapCallsOf([] {
                  std::string s(200, 'x');
                  g_sink = s.data();
              }),
              0U);
    EXPECT_GT(heapCallsOf([] {
                  auto p = std::make_unique<long[]>(8);
                  g_sink = p.get();
              }),
              0U);
    EXPECT_GT(heapCallsOf([] {
                  Eigen::MatrixXd m = Eigen::MatrixXd::Identity(5, 5);
                  g_sink = m.data();
              }),
              0U);
}

TEST(NoHeapGuard, FixedSizeWorkIsNotCounted) {
    EXPECT_EQ(heapCallsOf([] {
                  Eigen::Matrix3d a = Eigen::Matrix3d::Identity() * 2.0;
                  Eigen::Vector3d b(1.0, 2.0, 3.0);
                  Eigen::Vector3d x = a.lu().solve(b);
                  static double out[3] = {};
                  out[0] = x.sum();
                  g_sink = out;
              }),
              0U);
}

}  // namespace
