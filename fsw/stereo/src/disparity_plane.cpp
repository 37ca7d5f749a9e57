// fitDisparityPlane, fillDisparityPlane (vtm/stereo/disparity_plane.hpp).
#include "vtm/stereo/disparity_plane.hpp"

#include <cmath>

#include "vtm/core/math.hpp"
#include "vtm/stereo/ml_stereo.hpp"

namespace vtm::stereo {
namespace {

// Refits at most (each keeps the samples near the last fit); they stop when the kept set
// stops changing in size.
constexpr std::int32_t kPlaneRefits = 8;

// Insertion sort, ascending (O(n^2): n is at most a feature set).
void sortAscending(double* d, std::int32_t n) noexcept {
    for (std::int32_t i = 1; i < n; ++i) {
        const double v = d[i];
        std::int32_t k = i;
        for (; k > 0 && d[k - 1] > v; --k) {
            d[k] = d[k - 1];
        }
        d[k] = v;
    }
}

// Least squares over the samples whose |residual| in `residuals` (if given) is at most
// `keep`; false when they lie on a line (or fewer than 3).
bool solvePlane(Span<const Vec3> samples, const double* residuals, double keep, DisparityPlane& plane) noexcept {
    Mat3 normal = Mat3::Zero();
    Vec3 rhs = Vec3::Zero();
    std::int32_t used = 0;
    for (std::size_t i = 0U; i < samples.size(); ++i) {
        if (residuals != nullptr && std::fabs(residuals[i]) > keep) {
            continue;
        }
        const Vec3 row(samples[i].x(), samples[i].y(), 1.0);
        normal += row * row.transpose();
        rhs += row * samples[i].z();
        ++used;
    }
    // Conditioning: the determinant of the normal matrix against the scale of its entries
    // (a line of samples gives a singular matrix).
    const double scale = normal.cwiseAbs().maxCoeff();
    if (used < 3 || !(std::fabs(normal.determinant()) > 1e-12 * scale * scale * scale)) {
        return false;
    }
    const Vec3 abc = normal.ldlt().solve(rhs);
    plane.a = abc.x();
    plane.b = abc.y();
    plane.c = abc.z();
    plane.used = used;
    return math::isFinite(plane.a) && math::isFinite(plane.b) && math::isFinite(plane.c);
}

// Median of |r| over the first n residuals (r is overwritten: |r|, sorted).
double medianAbs(double* r, std::int32_t n) noexcept {
    for (std::int32_t i = 0; i < n; ++i) {
        r[i] = std::fabs(r[i]);
    }
    sortAscending(r, n);
    return n > 0 ? r[n / 2] : 0.0;
}

}  // namespace

Status fitDisparityPlane(Span<const Vec3> samples, Span<double> scratch, DisparityPlane& plane) noexcept {
    if (samples.size() < 3U) {
        return Status(StatusCode::kInvalidArgument, "fitDisparityPlane: samples: fewer than 3",
                      static_cast<std::int64_t>(samples.size()));
    }
    if (scratch.size() < samples.size() || samples.size() > 0x7FFFFFFFU) {
        return Status(StatusCode::kInvalidArgument, "fitDisparityPlane: scratch smaller than the samples",
                      static_cast<std::int64_t>(scratch.size()));
    }
    const auto n = static_cast<std::int32_t>(samples.size());
    for (std::int32_t i = 0; i < n; ++i) {
        const Vec3& s = samples[static_cast<std::size_t>(i)];
        if (!math::isFinite(s.x()) || !math::isFinite(s.y()) || !math::isFinite(s.z()) ||
            std::fabs(s.x()) > kMaxPlaneSamplePx || std::fabs(s.y()) > kMaxPlaneSamplePx ||
            std::fabs(s.z()) > kMaxPlaneSamplePx) {
            return Status(StatusCode::kInvalidArgument, "fitDisparityPlane: samples: not finite or beyond 1e6 px", i);
        }
    }
    if (!solvePlane(samples, nullptr, 0.0, plane)) {
        return Status(StatusCode::kDegenerate, "fitDisparityPlane: the samples lie on a line");
    }
    double* r = scratch.data();
    const auto residuals = [&samples, r, n](const DisparityPlane& q) {
        for (std::int32_t i = 0; i < n; ++i) {
            const Vec3& s = samples[static_cast<std::size_t>(i)];
            r[i] = s.z() - (q.a * s.x() + q.b * s.y() + q.c);
        }
    };
    double keep = 0.0;
    std::int32_t used_before = -1;
    for (std::int32_t refit = 0; refit < kPlaneRefits && plane.used != used_before; ++refit) {
        residuals(plane);
        const double spread = 3.0 * medianAbs(r, n);  // sorts r: the residuals again below
        keep = spread > 2.0 ? spread : 2.0;
        residuals(plane);
        used_before = plane.used;
        if (!solvePlane(samples, r, keep, plane)) {
            return Status(StatusCode::kDegenerate, "fitDisparityPlane: the samples kept lie on a line");
        }
    }
    // The median residual of the samples the last fit kept (as it chose them).
    std::int32_t m = 0;
    for (std::int32_t i = 0; i < n; ++i) {
        const Vec3& s = samples[static_cast<std::size_t>(i)];
        if (std::fabs(r[i]) <= keep) {
            r[m] = s.z() - (plane.a * s.x() + plane.b * s.y() + plane.c);
            ++m;
        }
    }
    plane.residual_px = medianAbs(r, m);
    return Status::ok();
}

Status fillDisparityPlane(const DisparityPlane& plane, std::int32_t bound_min, std::int32_t bound_max,
                          const ImageView<std::int16_t>& out) noexcept {
    if (!out.valid()) {
        return Status(StatusCode::kInvalidArgument, "fillDisparityPlane: out is empty");
    }
    if (bound_min > bound_max || bound_min < -kMaxDisparityPx || bound_max > kMaxDisparityPx) {
        return Status(StatusCode::kInvalidArgument, "fillDisparityPlane: bounds must satisfy -2047 <= min <= max <= 2047",
                      bound_min);
    }
    for (std::int32_t y = 0; y < out.height(); ++y) {
        std::int16_t* row = out.row(y);
        for (std::int32_t x = 0; x < out.width(); ++x) {
            double d = std::floor(plane.a * x + plane.b * y + plane.c + 0.5);
            d = d < bound_min ? bound_min : (d > bound_max ? bound_max : d);
            row[x] = static_cast<std::int16_t>(d);
        }
    }
    return Status::ok();
}

}  // namespace vtm::stereo
