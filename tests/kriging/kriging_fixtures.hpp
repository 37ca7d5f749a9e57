// Test scenes of the kriging tests (test code: heap allowed outside NoHeapScope).
//  - an analytic smooth surface (sines and a Gaussian bump);
//  - a realisation of a Gaussian process with exponential covariance
//    C(h) = sigma^2 exp(-h / L) (practical range 3 L), by random Fourier features: the
//    isotropic 2-D spectral density of exp(-h/L) is proportional to (1 + L^2 k^2)^(-3/2),
//    whose radial CDF 1 - (1 + L^2 k^2)^(-1/2) inverts to k = sqrt((1 - u)^-2 - 1) / L;
//  - scattered sample positions; inverse-distance weighting as the peer.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "vtm/core/arena.hpp"
#include "vtm/core/eigen.hpp"
#include "vtm/core/random.hpp"
#include "vtm/kriging/ordinary_kriging.hpp"

namespace vtm::kriging::test {

constexpr double kTwoPi = 6.283185307179586;

// 64 x 64 nodes of 0.5 m: 32 m square, north-west corner (32, 0).
inline terrain::GridConfig testGrid() {
    terrain::GridConfig g;
    g.north_edge_m = 32.0;
    g.west_edge_m = 0.0;
    g.cell_m = 0.5;
    g.cols = 64;
    g.rows = 64;
    return g;
}

// Elevation (up, metres) of the smooth analytic surface.
inline double analyticSurface(double n, double e) {
    const double dn = n - 20.0;
    const double de = e - 12.0;
    return 0.6 * std::sin(kTwoPi * n / 14.0) * std::cos(kTwoPi * e / 11.0) + 0.3 * std::sin(kTwoPi * (n + e) / 23.0) +
           1.0 * std::exp(-(dn * dn + de * de) / 18.0);
}

class ExponentialProcess {
public:
    ExponentialProcess(double sigma_m, double scale_m, int components, std::uint64_t seed)
        : amplitude_(sigma_m * std::sqrt(2.0 / components)) {
        Random r(seed);
        for (int i = 0; i < components; ++i) {
            const double u = r.uniform01();
            const double k = std::sqrt(1.0 / ((1.0 - u) * (1.0 - u)) - 1.0) / scale_m;
            const double dir = kTwoPi * r.uniform01();
            const double phase = kTwoPi * r.uniform01();
            kn_.push_back(k * std::cos(dir));
            ke_.push_back(k * std::sin(dir));
            phase_.push_back(phase);
        }
    }
    double operator()(double n, double e) const {
        double s = 0.0;
        for (std::size_t i = 0; i < kn_.size(); ++i) {
            s += std::cos(kn_[i] * n + ke_[i] * e + phase_[i]);
        }
        return amplitude_ * s;
    }

private:
    double amplitude_;
    std::vector<double> kn_, ke_, phase_;
};

// Uniform positions in [lo, hi]^2 (north, east).
inline std::vector<Vec2> scatteredPositions(std::size_t count, double lo, double hi, std::uint64_t seed) {
    Random r(seed);
    std::vector<Vec2> p;
    for (std::size_t i = 0; i < count; ++i) {
        const double n = lo + (hi - lo) * r.uniform01();
        const double e = lo + (hi - lo) * r.uniform01();
        p.emplace_back(n, e);
    }
    return p;
}

// Site points (z down) of a surface at the positions.
template <typename Surface>
std::vector<Vec3> samplesOf(const std::vector<Vec2>& positions, const Surface& surface) {
    std::vector<Vec3> s;
    for (const Vec2& p : positions) {
        s.emplace_back(p.x(), p.y(), -surface(p.x(), p.y()));
    }
    return s;
}

// The peer: inverse-distance weighting (power 2) of the k nearest samples within the
// radius, by brute force; NaN without a sample in the radius.
inline double idwEstimate(const std::vector<Vec3>& samples, double n, double e, int k, double radius_m) {
    std::vector<std::pair<double, std::size_t>> d;
    for (std::size_t i = 0; i < samples.size(); ++i) {
        const double dn = samples[i].x() - n;
        const double de = samples[i].y() - e;
        const double d2 = dn * dn + de * de;
        if (d2 <= radius_m * radius_m) {
            d.emplace_back(d2, i);
        }
    }
    if (d.empty()) {
        return std::nan("");
    }
    const auto kk = std::min(d.size(), static_cast<std::size_t>(k));
    std::partial_sort(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(kk), d.end());
    double sw = 0.0, sz = 0.0;
    for (std::size_t i = 0; i < kk; ++i) {
        if (d[i].first == 0.0) {
            return -samples[d[i].second].z();
        }
        const double w = 1.0 / d[i].first;
        sw += w;
        sz += w * -samples[d[i].second].z();
    }
    return sz / sw;
}

// A kriging instance in a pool of its workspace (plus the alignment the arena may pad the
// pool's first block by: the heap aligns to 8 bytes only on the 32-bit targets).
struct Kriger {
    explicit Kriger(const KrigingConfig& config)
        : pool(OrdinaryKriging::workspaceBytes(config) + Arena::kDefaultAlignment), arena(pool.data(), pool.size()) {
        const Status s = kriging.init(config, arena);
        EXPECT_TRUE(s.isOk()) << s.reason();
        arena.freeze();
    }
    std::vector<std::byte> pool;
    Arena arena;
    OrdinaryKriging kriging;
};

}  // namespace vtm::kriging::test
