#include "vtm/core/config_check.hpp"
#include "vtm/app/orbital_fix.hpp"

#include "vtm/core/image_pyramid.hpp"
#include "vtm/core/math.hpp"
#include "request_support.hpp"

namespace vtm::app {
namespace {

constexpr std::int32_t kMaxHalvings = 8;  // a 4096-px frame down to 16 px
constexpr std::int32_t kMinRegistrationPx = 16;
constexpr std::size_t kHistogramBins = 1024U;  // a frame's top 10 bits

Status badMap(const char* reason) noexcept { return Status(StatusCode::kInvalidArgument, reason); }

std::size_t halvingBytes(std::int32_t w, std::int32_t h) noexcept {
    // Halvings stored one after another: (w/2)(h/2) + (w/4)(h/4) + ... < w h / 3.
    return static_cast<std::size_t>(w) * static_cast<std::size_t>(h) / 3U + 16U;
}

// Orbital pixel (col, row) of a site north/east, and back.
Vec2 orbitalPx(const OrbitalMapGeoreference& g, double north_m, double east_m) noexcept {
    return Vec2((east_m - g.east0_m) / g.cell_m, (g.north0_m - north_m) / g.cell_m);
}

Vec2 siteNe(const OrbitalMapGeoreference& g, const Vec2& px) noexcept {
    return Vec2(g.north0_m - px.y() * g.cell_m, g.east0_m + px.x() * g.cell_m);
}

// Full-resolution pixel of pixel q of a frame halved n times (halveImage's centres).
Vec2 fullPixel(const Vec2& q, std::int32_t n) noexcept {
    const double f = static_cast<double>(1 << n);
    return Vec2(f * q.x() + 0.5 * (f - 1.0), f * q.y() + 0.5 * (f - 1.0));
}

Vec2 reducedPixel(const Vec2& p, std::int32_t n) noexcept {
    const double f = static_cast<double>(1 << n);
    return Vec2((p.x() - 0.5 * (f - 1.0)) / f, (p.y() - 0.5 * (f - 1.0)) / f);
}

// Site point of a frame pixel on the level plane z = ground_z (site z down); false when the
// ray does not go down to it.
bool groundPoint(const CameraModel& model, const RigidPose& pose, const Vec2& pixel, double ground_z, Vec3& out) noexcept {
    CameraRay ray;
    if (!backProjectPixel(model, pixel, ray).isOk()) {
        return false;
    }
    const Vec3 o = pose.R * ray.origin_m + pose.t_m;
    const Vec3 d = pose.R * ray.direction;
    if (!(d.z() > 1e-6)) {
        return false;
    }
    out = o + ((ground_z - o.z()) / d.z()) * d;
    return true;
}

// Least-squares similarity b = a * z + c on complex numbers (x + i y): a = s e^{i theta}.
struct Similarity {
    double ar = 0.0;  // Re a
    double ai = 0.0;  // Im a
    Vec2 from_mean = Vec2::Zero();
    Vec2 to_mean = Vec2::Zero();
    [[nodiscard]] Vec2 apply(const Vec2& z) const noexcept {
        const Vec2 d = z - from_mean;
        return to_mean + Vec2(ar * d.x() - ai * d.y(), ai * d.x() + ar * d.y());
    }
};

Similarity fitSimilarity(const Vec2* from, const Vec2* to, std::int32_t n) noexcept {
    Similarity s;
    for (std::int32_t i = 0; i < n; ++i) {
        s.from_mean += from[i] / n;
        s.to_mean += to[i] / n;
    }
    double re = 0.0;
    double im = 0.0;
    double norm = 0.0;
    for (std::int32_t i = 0; i < n; ++i) {
        const Vec2 z = from[i] - s.from_mean;
        const Vec2 w = to[i] - s.to_mean;
        re += w.x() * z.x() + w.y() * z.y();  // w conj(z)
        im += w.y() * z.x() - w.x() * z.y();
        norm += z.squaredNorm();
    }
    s.ar = norm > 0.0 ? re / norm : 0.0;
    s.ai = norm > 0.0 ? im / norm : 0.0;
    return s;
}

// One-pass least squares of g = c + k o over pairs of 2-vectors (o: a feature's
// navigation-scale offset from a camera, g: where the orbital map puts it), c a 2-vector,
// k a scalar; the residual RMS from the same sums.
struct ScaleShiftFit {
    double n = 0.0;
    Vec2 so = Vec2::Zero();
    Vec2 sg = Vec2::Zero();
    double soo = 0.0;
    double sog = 0.0;
    double sgg = 0.0;
    void add(const Vec2& o, const Vec2& g) noexcept {
        n += 1.0;
        so += o;
        sg += g;
        soo += o.squaredNorm();
        sog += o.dot(g);
        sgg += g.squaredNorm();
    }
    // false when fewer than 3 pairs or the offsets do not spread.
    bool solve(double& k, Vec2& c, double& rms) const noexcept {
        const double den = soo - so.squaredNorm() / (n > 0.0 ? n : 1.0);
        if (n < 3.0 || !(den > 1e-9)) {
            return false;
        }
        k = (sog - so.dot(sg) / n) / den;
        c = (sg - k * so) / n;
        const double ss = sgg - 2.0 * c.dot(sg) - 2.0 * k * sog + n * c.squaredNorm() + 2.0 * k * c.dot(so) + k * k * soo;
        rms = math::sqrt((ss > 0.0 ? ss : 0.0) / n);
        return true;
    }
};

}  // namespace

Status validateOrbitalMap(const OrbitalMap& map) noexcept {
    const bool has8 = map.image8.valid() && map.image8.data() != nullptr;
    const bool has16 = map.image16.valid() && map.image16.data() != nullptr;
    if (has8 == has16) {
        return badMap("orbital map: give image8 or image16 (exactly one)");
    }
    const std::int32_t w = has8 ? map.image8.width() : map.image16.width();
    const std::int32_t h = has8 ? map.image8.height() : map.image16.height();
    if (w < kMinRegistrationPx || h < kMinRegistrationPx) {
        return Status(StatusCode::kInvalidArgument, "orbital map: image smaller than 16 x 16", w < h ? w : h);
    }
    if (has8 ? map.bit_depth != 8U : (map.bit_depth < 9U || map.bit_depth > 16U)) {
        return Status(StatusCode::kInvalidArgument, "orbital map: bit_depth must be 8 for image8, 9..16 for image16",
                      map.bit_depth);
    }
    if (!isInRange(map.geo.cell_m, 1e-3, 1e3)) {
        return badMap("orbital map: geo.cell_m must be 1e-3..1e3 m");
    }
    if (!isInRange(map.geo.north0_m, -1e7, 1e7) || !isInRange(map.geo.east0_m, -1e7, 1e7)) {
        return badMap("orbital map: geo.north0_m/east0_m must be finite, within 1e7 m");
    }
    return Status::ok();
}

Status OrbitalFixConfig::validate() const noexcept {
    VTM_RETURN_IF_ERROR(registration.validate());
    if (!isInRange(min_pixel_cells, 0.1, 4.0)) return invalidConfig("orbital.min_pixel_cells: must be 0.1..4");
    if (!isInRange(angle_range_rad, 0.0, math::kPi)) return invalidConfig("orbital.angle_range_rad: must be 0..pi");
    if (!isInRange(scale_range, 0.01, 0.9)) return invalidConfig("orbital.scale_range: must be 0.01..0.9");
    if (!isInRange(shift_sigmas, 0.0, 10.0)) return invalidConfig("orbital.shift_sigmas: must be 0..10");
    if (!isInRange(shift_margin_px, 0.0, 1000.0)) return invalidConfig("orbital.shift_margin_px: must be 0..1000");
    if (!isInRange(min_ncc, 0.0, 1.0)) return invalidConfig("orbital.min_ncc: must be 0..1");
    if (!isInRange(max_peak_ratio, 1e-6, 1.0)) return invalidConfig("orbital.max_peak_ratio: must be in (0, 1]");
    if (!isInRange(max_residual_px, 1e-6, 1e6)) return invalidConfig("orbital.max_residual_px: must be > 0");
    if (!isInRange(max_position_disagreement_px, 1e-6, 1e6)) {
        return invalidConfig("orbital.max_position_disagreement_px: must be > 0");
    }
    if (!isInRange(max_scale_change, 1e-6, 1.0)) return invalidConfig("orbital.max_scale_change: must be in (0, 1]");
    if (!isInRange(max_scale_disagreement, 1e-6, 1.0)) {
        return invalidConfig("orbital.max_scale_disagreement: must be in (0, 1]");
    }
    return Status::ok();
}

std::size_t OrbitalLocator::workspaceBytes(const OrbitalFixConfig& config, std::int32_t frame_width,
                                           std::int32_t frame_height) noexcept {
    if (!config.validate().isOk() || frame_width < 1 || frame_height < 1) {
        return 0U;
    }
    const entropy::RegistrationConfig& r = config.registration;
    return entropy::EntropyRegistration::workspaceBytes(r)                     // its own plan
           + Arena::arrayBytes<std::uint8_t>(static_cast<std::size_t>(frame_width) *
                                             static_cast<std::size_t>(frame_height))  // the frame at 8 bits
           + Arena::arrayBytes<std::uint32_t>(kHistogramBins)                  // its histogram
           + Arena::arrayBytes<std::uint8_t>(halvingBytes(frame_width, frame_height))  // the frame's halvings
           + Arena::arrayBytes<std::uint8_t>(static_cast<std::size_t>(r.max_width) *
                                             static_cast<std::size_t>(r.max_height));  // orbital cut-out
}

Status OrbitalLocator::init(const OrbitalFixConfig& config, std::int32_t frame_width, std::int32_t frame_height,
                            Arena& arena) noexcept {
    initialized_ = false;
    has_map_ = false;
    VTM_RETURN_IF_ERROR(config.validate());
    VTM_RETURN_IF_ERROR(registration_.init(config.registration, arena));
    stretched_ = detail::carve<std::uint8_t>(arena, frame_width, frame_height);
    histogram_ = arena.allocateArray<std::uint32_t>(kHistogramBins);
    reduce_ = arena.allocateArray<std::uint8_t>(halvingBytes(frame_width, frame_height));
    cut_ = detail::carve<std::uint8_t>(arena, config.registration.max_width, config.registration.max_height);
    if (reduce_.empty() || cut_.data() == nullptr || stretched_.data() == nullptr || histogram_.empty()) {
        return Status(StatusCode::kOutOfMemory, "OrbitalLocator::init: arena smaller than workspaceBytes(config)",
                      static_cast<std::int64_t>(workspaceBytes(config, frame_width, frame_height)));
    }
    config_ = config;
    initialized_ = true;
    return Status::ok();
}

Status OrbitalLocator::setMap(const OrbitalMap& map) noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "setOrbitalMap: the orbital fix is not initialised (orbital.enabled)");
    }
    VTM_RETURN_IF_ERROR(validateOrbitalMap(map));
    map_ = map;
    has_map_ = true;
    return Status::ok();
}

// The frame at 8 bits: its 1st .. 99th percentile (from a histogram of its top 10 bits)
// stretched linearly over 0..255, integer arithmetic. Same size as the frame.
void OrbitalLocator::stretchFrame(const ImageView<const std::uint16_t>& frame, std::uint8_t bit_depth) noexcept {
    const std::uint32_t bits = bit_depth < 8U ? 8U : (bit_depth > 16U ? 16U : bit_depth);
    const std::uint32_t shift = bits > 10U ? bits - 10U : 0U;
    const std::uint32_t bins = 1U << (bits - shift);
    for (std::uint32_t b = 0U; b < bins; ++b) histogram_[b] = 0U;
    for (std::int32_t y = 0; y < frame.height(); ++y) {
        const std::uint16_t* row = frame.row(y);
        for (std::int32_t x = 0; x < frame.width(); ++x) {
            const std::uint32_t b = static_cast<std::uint32_t>(row[x]) >> shift;
            ++histogram_[b < bins ? b : bins - 1U];
        }
    }
    const std::uint64_t total = static_cast<std::uint64_t>(frame.width()) * static_cast<std::uint64_t>(frame.height());
    std::uint64_t seen = 0U;
    std::uint32_t lo_bin = 0U;
    std::uint32_t hi_bin = bins - 1U;
    bool lo_found = false;
    for (std::uint32_t b = 0U; b < bins; ++b) {
        seen += histogram_[b];
        if (!lo_found && 100U * seen > total) { lo_bin = b; lo_found = true; }
        if (100U * seen >= 99U * total) { hi_bin = b; break; }
    }
    const std::uint32_t lo = lo_bin << shift;
    const std::uint32_t hi = ((hi_bin + 1U) << shift) - 1U;
    const std::uint32_t span = hi > lo ? hi - lo : 1U;
    const ImageView<std::uint8_t> out(stretched_.data(), frame.width(), frame.height());
    for (std::int32_t y = 0; y < frame.height(); ++y) {
        const std::uint16_t* src = frame.row(y);
        std::uint8_t* dst = out.row(y);
        for (std::int32_t x = 0; x < frame.width(); ++x) {
            const std::uint32_t v = src[x] > lo ? src[x] - lo : 0U;
            const std::uint32_t g = (v * 255U + span / 2U) / span;
            dst[x] = static_cast<std::uint8_t>(g > 255U ? 255U : g);
        }
    }
}

// Halves the frame until its pixel covers at least min_pixel_cells of an orbital cell and it fits the
// registration's capacity (never below 16 px).
Status OrbitalLocator::reduceFrame(const ImageView<const std::uint8_t>& frame, double ground_px_m, LocatedFrame& out,
                                   ImageView<const std::uint8_t>& reduced) noexcept {
    reduced = frame;
    std::size_t used = 0U;
    const double cell = map_.geo.cell_m;
    std::int32_t n = 0;
    for (; n < kMaxHalvings; ++n) {
        const bool too_fine = ground_px_m * static_cast<double>(1 << n) < config_.min_pixel_cells * cell;
        const bool too_big = reduced.width() > config_.registration.max_width ||
                             reduced.height() > config_.registration.max_height;
        if ((!too_fine && !too_big) || reduced.width() / 2 < kMinRegistrationPx ||
            reduced.height() / 2 < kMinRegistrationPx) {
            break;
        }
        const std::size_t pixels = static_cast<std::size_t>(reduced.width() / 2) *
                                   static_cast<std::size_t>(reduced.height() / 2);
        if (used + pixels > reduce_.size()) {
            break;
        }
        const ImageView<std::uint8_t> next(reduce_.data() + used, reduced.width() / 2, reduced.height() / 2);
        VTM_RETURN_IF_ERROR(halveImage(reduced, next));
        used += pixels;
        reduced = next;
    }
    out.reduction = n;
    if (reduced.width() > config_.registration.max_width || reduced.height() > config_.registration.max_height) {
        return Status(StatusCode::kSizeMismatch, "locate: the reduced frame exceeds orbital.registration.max_width/max_height",
                      reduced.width());
    }
    return Status::ok();
}

// The orbital pixels [lo, hi] (clamped to the capacity about their centre and to the map)
// as an 8-bit cut-out.
Status OrbitalLocator::cutOrbital(const Vec2& lo, const Vec2& hi, LocatedFrame& out,
                                  ImageView<const std::uint8_t>& cut) noexcept {
    const bool is8 = map_.image8.data() != nullptr;
    const std::int32_t mw = is8 ? map_.image8.width() : map_.image16.width();
    const std::int32_t mh = is8 ? map_.image8.height() : map_.image16.height();
    double x0 = lo.x();
    double y0 = lo.y();
    double x1 = hi.x();
    double y1 = hi.y();
    const double cap_w = static_cast<double>(cut_.width() - 1);
    const double cap_h = static_cast<double>(cut_.height() - 1);
    if (x1 - x0 > cap_w) { x0 = 0.5 * (x0 + x1 - cap_w); x1 = x0 + cap_w; }
    if (y1 - y0 > cap_h) { y0 = 0.5 * (y0 + y1 - cap_h); y1 = y0 + cap_h; }
    const double fx0 = x0 > 0.0 ? x0 : 0.0;
    const double fy0 = y0 > 0.0 ? y0 : 0.0;
    const double fx1 = x1 < mw - 1.0 ? x1 : mw - 1.0;
    const double fy1 = y1 < mh - 1.0 ? y1 : mh - 1.0;
    if (!(fx1 - fx0 >= kMinRegistrationPx) || !(fy1 - fy0 >= kMinRegistrationPx)) {
        return Status(StatusCode::kNoData, "locate: the predicted footprint lies outside the orbital map");
    }
    const std::int32_t cx = static_cast<std::int32_t>(fx0);  // non-negative: truncation is floor
    const std::int32_t cy = static_cast<std::int32_t>(fy0);
    const std::int32_t cw = static_cast<std::int32_t>(fx1) - cx + 1;
    const std::int32_t ch = static_cast<std::int32_t>(fy1) - cy + 1;
    const std::uint32_t shift = is8 ? 0U : static_cast<std::uint32_t>(map_.bit_depth) - 8U;
    const ImageView<std::uint8_t> dst(cut_.data(), cw, ch);
    for (std::int32_t y = 0; y < ch; ++y) {
        std::uint8_t* d = dst.row(y);
        for (std::int32_t x = 0; x < cw; ++x) {
            const std::uint32_t v = is8 ? map_.image8.row(cy + y)[cx + x]
                                        : (static_cast<std::uint32_t>(map_.image16.row(cy + y)[cx + x]) >> shift);
            d[x] = static_cast<std::uint8_t>(v > 255U ? 255U : v);
        }
    }
    out.cut_origin_px = Vec2(cx, cy);
    cut = dst;
    return Status::ok();
}

Vec2 OrbitalLocator::groundOf(const LocatedFrame& f, const Vec2& pixel) const noexcept {
    const Vec2 q = reducedPixel(pixel, f.reduction);
    const entropy::Mat23& g = f.registration.image2_from_image1;
    const Vec2 c(g(0, 0) * q.x() + g(0, 1) * q.y() + g(0, 2), g(1, 0) * q.x() + g(1, 1) * q.y() + g(1, 2));
    return siteNe(map_.geo, c + f.cut_origin_px);
}

namespace {

// Site point of refined inlier j at the navigation's scale (camera 1's ray, its range).
bool inlierPoint(const LocateInput& in, std::size_t j, Vec3& out) noexcept {
    const refine::Result& r = *in.refine;
    if (r.inliers[j] == 0U || !math::isFinite(r.ranges_m[j])) {
        return false;
    }
    CameraRay ray;
    if (!backProjectPixel(in.model, r.pixels_a[j], ray).isOk()) {
        return false;
    }
    out = in.site_from_cam1.R * (ray.origin_m + r.ranges_m[j] * ray.direction) + in.site_from_cam1.t_m;
    return true;
}

}  // namespace

// Navigation-scale site offset (north, east), from camera `from`, of inlier j as frame
// `index` sees it: its pixel's ray through that frame's pose meets the features' mean
// ground plane. The plane, not the feature's own depth: the registration's similarity
// maps the frame as one plane too, and a regression on the features' own depths is biased
// low by their relief's variance (about (relief / altitude)^2; 0.1-0.6 % measured).
bool OrbitalLocator::planeOffset(const LocateInput& in, std::int32_t index, std::size_t j, const Vec3& from,
                                 Vec2& out) const noexcept {
    const refine::Result& r = *in.refine;
    if (r.inliers[j] == 0U || !math::isFinite(r.ranges_m[j])) {
        return false;
    }
    Vec3 x;
    if (!groundPoint(in.model, index == 0 ? in.site_from_cam1 : in.site_from_cam2,
                     index == 0 ? r.pixels_a[j] : r.pixels_b[j], ground_z_m_, x)) {
        return false;
    }
    out = Vec2(x.x() - from.x(), x.y() - from.y());
    return true;
}

// The frame's features placed by its registration, fitted to their navigation-scale
// offsets from the frame's camera: its horizontal position, the scale, the misfit.
void OrbitalLocator::fitFrame(const LocateInput& in, std::int32_t index, LocatedFrame& out) const noexcept {
    const refine::Result& r = *in.refine;
    const Vec3& camera = (index == 0 ? in.site_from_cam1 : in.site_from_cam2).t_m;
    ScaleShiftFit fit;
    for (std::size_t j = 0U; j < r.pixels_a.size(); ++j) {
        Vec2 offset;
        if (planeOffset(in, index, j, camera, offset)) {
            fit.add(offset, groundOf(out, index == 0 ? r.pixels_a[j] : r.pixels_b[j]));
        }
    }
    out.features = static_cast<std::int32_t>(fit.n);
    double rms = 0.0;
    if (fit.solve(out.scale, out.position_ne_m, rms)) {
        out.residual_px = rms / map_.geo.cell_m;
    }
}

// Registers one frame around the navigation's prediction and applies the confidence rules.
Status OrbitalLocator::locateFrame(const LocateInput& in, std::int32_t index, LocatedFrame& out) noexcept {
    const RigidPose& pose = index == 0 ? in.site_from_cam1 : in.site_from_cam2;
    const ImageView<const std::uint16_t>& frame16 = index == 0 ? in.frame1 : in.frame2;
    if (frame16.width() > stretched_.width() || frame16.height() > stretched_.height()) {
        return Status(StatusCode::kSizeMismatch, "locate: frame larger than the planned frame size", frame16.width());
    }
    const double height = ground_z_m_ - pose.t_m.z();  // site z down
    if (!(height > 0.0)) {
        return Status(StatusCode::kDegenerate, "locate: the camera is not above the features' ground");
    }
    stretchFrame(frame16, index == 0 ? in.bit_depth1 : in.bit_depth2);
    const ImageView<const std::uint8_t> frame(stretched_.data(), frame16.width(), frame16.height());
    ImageView<const std::uint8_t> reduced;
    VTM_RETURN_IF_ERROR(reduceFrame(frame, height / in.model.fx_px, out, reduced));
    entropy::RegistrationRequest rq;
    ImageView<const std::uint8_t> cut;
    VTM_RETURN_IF_ERROR(predict(in, index, reduced, out, rq, cut));
    VTM_RETURN_IF_ERROR(registration_.registerImages(reduced, cut, rq, out.registration));
    return acceptFrame(in, index, out);
}

// The navigation's prediction of the reduced frame in the orbital map: a 3 x 3 grid of it
// on the ground, in orbital pixels, and the least-squares similarity through them; the
// orbital cut-out around it and the registration's search.
Status OrbitalLocator::predict(const LocateInput& in, std::int32_t index, const ImageView<const std::uint8_t>& reduced,
                               LocatedFrame& out, entropy::RegistrationRequest& rq,
                               ImageView<const std::uint8_t>& cut) noexcept {
    const RigidPose& pose = index == 0 ? in.site_from_cam1 : in.site_from_cam2;
    Vec2 from[9];
    Vec2 to[9];
    std::int32_t n = 0;
    for (std::int32_t k = 0; k < 9; ++k) {
        const std::int32_t col = k % 3;
        const std::int32_t row = k / 3;
        const Vec2 q(0.5 * static_cast<double>(col) * (reduced.width() - 1),
                     0.5 * static_cast<double>(row) * (reduced.height() - 1));
        Vec3 ground;
        if (groundPoint(in.model, pose, fullPixel(q, out.reduction), ground_z_m_, ground)) {
            from[n] = q;
            to[n] = orbitalPx(map_.geo, ground.x(), ground.y());
            ++n;
        }
    }
    if (n < 3) {
        return Status(StatusCode::kDegenerate, "locate: the frame's corners do not reach the ground");
    }
    const Similarity predicted = fitSimilarity(from, to, n);
    out.predicted_px = orbitalPx(map_.geo, pose.t_m.x(), pose.t_m.y());
    const double shift_range =
        config_.shift_sigmas * in.position_sigma_m[index == 0 ? 0 : 1] / map_.geo.cell_m + config_.shift_margin_px;
    Vec2 lo = to[0];
    Vec2 hi = to[0];
    for (std::int32_t k = 1; k < n; ++k) {
        lo = lo.cwiseMin(to[k]);
        hi = hi.cwiseMax(to[k]);
    }
    const Vec2 pad(shift_range + 2.0, shift_range + 2.0);
    VTM_RETURN_IF_ERROR(cutOrbital(lo - pad, hi + pad, out, cut));
    const double scale = math::sqrt(predicted.ar * predicted.ar + predicted.ai * predicted.ai);
    const double angle = math::atan2(predicted.ai, predicted.ar);
    rq.angle_min_rad = angle - config_.angle_range_rad;
    rq.angle_max_rad = angle + config_.angle_range_rad;
    rq.scale_min = scale * (1.0 - config_.scale_range);
    rq.scale_max = scale * (1.0 + config_.scale_range);
    if (!(rq.scale_min >= 0.125) || !(rq.scale_max <= 8.0)) {
        return Status(StatusCode::kDegenerate, "locate: the frame's scale in the orbital map is outside 1/8..8");
    }
    const Vec2 c1(0.5 * (reduced.width() - 1), 0.5 * (reduced.height() - 1));
    const Vec2 c2(0.5 * (cut.width() - 1), 0.5 * (cut.height() - 1));
    const Vec2 t = predicted.apply(c1) - out.cut_origin_px - c2;
    rq.shift_x_px = t.x();
    rq.shift_y_px = t.y();
    rq.shift_range_px = shift_range;
    return Status::ok();
}

// The confidence rules on a registered frame, and its features placed and fitted.
Status OrbitalLocator::acceptFrame(const LocateInput& in, std::int32_t index, LocatedFrame& out) const noexcept {
    if (out.registration.ncc < config_.min_ncc) {
        return Status(StatusCode::kNoData, "locate: peak NCC below orbital.min_ncc");
    }
    if (out.registration.second_ncc >= config_.max_peak_ratio * out.registration.ncc) {
        return Status(StatusCode::kDegenerate, "locate: second peak within orbital.max_peak_ratio of the best (ambiguous)");
    }
    fitFrame(in, index, out);
    if (out.features < 3) {
        return Status(StatusCode::kDegenerate, "locate: fewer than 3 refined inliers to place", out.features);
    }
    if (!(out.residual_px <= config_.max_residual_px)) {
        return Status(StatusCode::kDegenerate, "locate: the features do not fit the located ground (orbital.max_residual_px)");
    }
    if (!(out.scale > 1.0 - config_.scale_range && out.scale < 1.0 + config_.scale_range)) {
        return Status(StatusCode::kDegenerate, "locate: the located scale differs from the navigation's by more than orbital.scale_range");
    }
    return Status::ok();
}

// Both frames' placed features against their offsets from camera 1: camera 1's position
// and the pair's scale. Both frames must be used and agree on camera 1's position.
Status OrbitalLocator::fitPair(const LocateInput& in, OrbitalFix& fix) const noexcept {
    const LocatedFrame& a = fix.frames[0];
    const LocatedFrame& b = fix.frames[1];
    if (!a.used || !b.used) {
        return !a.used ? a.status : b.status;
    }
    const Vec3 baseline = in.site_from_cam2.t_m - in.site_from_cam1.t_m;
    const Vec2 camera1_from_b = b.position_ne_m - Vec2(baseline.x(), baseline.y());
    if (!((a.position_ne_m - camera1_from_b).norm() <= config_.max_position_disagreement_px * map_.geo.cell_m)) {
        return Status(StatusCode::kDegenerate,
                      "locate: the two frames disagree on the position (orbital.max_position_disagreement_px)");
    }
    const refine::Result& r = *in.refine;
    const Vec3& c1 = in.site_from_cam1.t_m;
    ScaleShiftFit fit;
    for (std::size_t j = 0U; j < r.pixels_a.size(); ++j) {
        for (std::int32_t i = 0; i < 2; ++i) {
            Vec2 offset;
            const LocatedFrame& f = i == 0 ? a : b;
            if (f.used && planeOffset(in, i, j, c1, offset)) {
                fit.add(offset, groundOf(f, i == 0 ? r.pixels_a[j] : r.pixels_b[j]));
            }
        }
    }
    double rms = 0.0;
    if (!fit.solve(fix.scale, fix.camera1_ne_m, rms)) {
        return Status(StatusCode::kDegenerate, "locate: the placed features do not spread");
    }
    fix.residual_px = rms / map_.geo.cell_m;
    const double d = a.scale > b.scale ? a.scale - b.scale : b.scale - a.scale;
    const double change = fix.scale > 1.0 ? fix.scale - 1.0 : 1.0 - fix.scale;
    fix.scale_applied = d <= config_.max_scale_disagreement * 0.5 * (a.scale + b.scale) &&
                        change <= config_.max_scale_change;
    fix.correction_ne_m = fix.camera1_ne_m - Vec2(c1.x(), c1.y());
    return Status::ok();
}

Status OrbitalLocator::locate(const LocateInput& in, OrbitalFix& fix) noexcept {
    fix = OrbitalFix{};
    if (!initialized_ || !has_map_) {
        return Status(StatusCode::kNotInitialized, "locate: no orbital map (setOrbitalMap)");
    }
    if (in.refine == nullptr || in.frame1.data() == nullptr || in.frame2.data() == nullptr) {
        return Status(StatusCode::kInvalidArgument, "locate: the frames and the refined inliers are needed");
    }
    fix.attempted = true;
    double z = 0.0;
    std::int32_t n = 0;
    for (std::size_t j = 0U; j < in.refine->pixels_a.size(); ++j) {
        Vec3 x;
        if (inlierPoint(in, j, x)) {
            z += x.z();
            ++n;
        }
    }
    if (n == 0) {
        return Status(StatusCode::kDegenerate, "locate: no refined inlier to place");
    }
    ground_z_m_ = z / n;
    for (std::size_t i = 0U; i < fix.frames.size(); ++i) {
        LocatedFrame& f = fix.frames[i];
        f.status = locateFrame(in, static_cast<std::int32_t>(i), f);
        f.used = f.status.isOk();
    }
    return fitPair(in, fix);
}

}  // namespace vtm::app
