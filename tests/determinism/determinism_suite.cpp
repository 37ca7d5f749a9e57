#include "determinism_suite.hpp"
#include "vtm/core/hasher.hpp"

#include <cstring>

#include "vtm/core/eigen.hpp"
#include "vtm/core/image.hpp"
#include "vtm/core/math.hpp"
#include "vtm/core/random.hpp"
#include "sim/orbital.hpp"
#include "sim/render.hpp"
#include "sim/terrain.hpp"
#include "vtm/app/orbital_fix.hpp"
#include "vtm/core/camera_model.hpp"
#include "vtm/descent/plane_sweep.hpp"
#include "vtm/entropy/local_entropy.hpp"
#include "vtm/entropy/registration.hpp"
#include "vtm/features/features.hpp"
#include "vtm/icp/icp.hpp"
#include "vtm/motion/motion_refiner.hpp"
#include "vtm/octree/height_products.hpp"
#include "vtm/octree/octree.hpp"
#include "vtm/rectify/rectifier.hpp"
#include "vtm/refine/pair_refiner.hpp"
#include "vtm/stereo/disparity_plane.hpp"
#include "vtm/stereo/ml_stereo.hpp"
#include "vtm/stereo/pyramid_stereo.hpp"
#include "vtm/terrain/ground_bound.hpp"
#include "vtm/terrain/height_map.hpp"
#include "vtm/terrain/triangulation.hpp"

namespace vtm::determinism {
namespace {

std::uint64_t eigenSection() noexcept {
    Hasher h;
    Random rng(42U);
    for (int trial = 0; trial < 2000; ++trial) {
        Mat3 a;
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c) {
                a(r, c) = rng.uniform01() * 2.0 - 1.0;
            }
        }
        a += Mat3::Identity() * 0.5;
        // One draw per statement: the evaluation order of function arguments is
        // unspecified, and GCC orders them differently on x86-64 and PowerPC.
        const double b0 = rng.uniform01();
        const double b1 = rng.uniform01() - 0.5;
        const double b2 = rng.uniform01() * 3.0;
        const Vec3 b(b0, b1, b2);
        const Vec3 xLu = a.partialPivLu().solve(b);
        const Mat3 spd = a * a.transpose() + Mat3::Identity() * 1e-3;
        const Vec3 xLlt = spd.llt().solve(b);
        const Mat3 inv = a.inverse();
        const double qw = rng.uniform01() - 0.5;
        const double qx = rng.uniform01() - 0.5;
        const double qy = rng.uniform01();
        const Quat q = Quat(qw, qx, qy, 0.3).normalized();
        const Vec3 rotated = q * b;
        const Vec3 cross = xLu.cross(xLlt);
        for (int i = 0; i < 3; ++i) {
            h.addDouble(xLu(i));
            h.addDouble(xLlt(i));
            h.addDouble(rotated(i));
            h.addDouble(cross(i));
            h.addDouble(inv(i, (i + trial) % 3));
        }
        h.addDouble(a.determinant());
        h.addDouble(q.toRotationMatrix().trace());
    }
    return h.value();
}

std::uint64_t mathSection() noexcept {
    Hasher h;
    for (int i = -3000; i <= 3000; ++i) {
        const double x = static_cast<double>(i) * 0.0123456789;
        h.addDouble(math::exp(x * 0.2));
        h.addDouble(math::log(math::exp(x * 0.01) + static_cast<double>(i + 3001)));
        h.addDouble(math::sin(x));
        h.addDouble(math::cos(x * 3.7));
        h.addDouble(math::atan2(x, 1.0 - x * 0.5));
        h.addDouble(math::sqrt(static_cast<double>(i + 3000) * 1.7));
    }
    return h.value();
}

std::uint64_t randomSection() noexcept {
    Hasher h;
    Random rng(20261122U);
    for (int i = 0; i < 5000; ++i) {
        h.addU64(rng.nextU64());
        h.addDouble(rng.uniform01());
        h.addDouble(rng.normal());
        h.addI64(rng.uniformInt(-1000, 1000));
    }
    return h.value();
}

constexpr std::int32_t kW = 97;
constexpr std::int32_t kH = 61;

std::uint64_t imageSection() noexcept {
    static std::uint8_t pixels[kW * kH];
    static std::int32_t sums[kW * kH];
    Random rng(7U);
    const ImageView<std::uint8_t> img(pixels, kW, kH);
    for (std::int32_t y = 0; y < kH; ++y) {
        for (std::int32_t x = 0; x < kW; ++x) {
            img.at(x, y) = static_cast<std::uint8_t>((x * 7 + y * 13 + rng.uniformInt(0, 40)) & 0xFF);
        }
    }
    // 5x5 box sums (clamped borders), Sobel-like gradients and a threshold count.
    const ImageView<std::int32_t> box(sums, kW, kH);
    Hasher h;
    std::int64_t above = 0;
    for (std::int32_t y = 0; y < kH; ++y) {
        for (std::int32_t x = 0; x < kW; ++x) {
            std::int32_t s = 0;
            for (std::int32_t dy = -2; dy <= 2; ++dy) {
                for (std::int32_t dx = -2; dx <= 2; ++dx) {
                    const std::int32_t xx = x + dx < 0 ? 0 : (x + dx >= kW ? kW - 1 : x + dx);
                    const std::int32_t yy = y + dy < 0 ? 0 : (y + dy >= kH ? kH - 1 : y + dy);
                    s += img.at(xx, yy);
                }
            }
            box.at(x, y) = s;
            const std::int32_t gx = (x > 0 && x < kW - 1) ? img.at(x + 1, y) - img.at(x - 1, y) : 0;
            const std::int32_t gy = (y > 0 && y < kH - 1) ? img.at(x, y + 1) - img.at(x, y - 1) : 0;
            above += (gx * gx + gy * gy > 400) ? 1 : 0;
            h.addI64(s);
            h.addI64(gx * 3 - gy);
        }
    }
    h.addI64(above);
    return h.value();
}

// Expressions of the form a*b + c where the product is nearly cancelled by c: rounding
// the product before the addition (separate multiply and add, as written) and not
// rounding it (a fused multiply-add) give different bits for most inputs.
std::uint64_t fmaSensitiveSection() noexcept {
    Hasher h;
    Random rng(99U);
    double acc = 0.0;
    for (int i = 0; i < 4000; ++i) {
        const double a = 1.0 + rng.uniform01() * 1e-3;
        const double b = 1.0 / a + rng.uniform01() * 1e-12;
        const double c = -1.0;
        const double r = a * b + c;
        acc = acc * 0.5 + r;
        const double u2 = rng.uniform01();
        const double v2 = rng.uniform01();
        const Vec3 u(a, b, u2);
        const Vec3 v(b, -a, v2);
        h.addDouble(r);
        h.addDouble(u.dot(v));
    }
    h.addDouble(acc);
    return h.value();
}

// The dense stereo module on a 96 x 64 pair: textured noise shifted by 5 px on the left
// half and 9 px on the right half.
std::uint64_t stereoSection() noexcept {
    constexpr std::int32_t kSw = 96;
    constexpr std::int32_t kSh = 64;
    static std::uint8_t left[kSw * kSh];
    static std::uint8_t right[kSw * kSh];
    static std::uint8_t texture[(kSw + 16) * kSh];
    Random rng(5U);
    for (std::uint8_t& t : texture) {
        t = static_cast<std::uint8_t>(rng.uniformInt(20, 235));
    }
    for (std::int32_t y = 0; y < kSh; ++y) {
        for (std::int32_t x = 0; x < kSw; ++x) {
            const std::int32_t d = x < kSw / 2 ? 5 : 9;
            left[y * kSw + x] = texture[y * (kSw + 16) + x + 12];
            right[y * kSw + x] = texture[y * (kSw + 16) + x + 12 + (x + d < kSw + 4 ? d : 0)];
        }
    }
    stereo::Config c = stereo::Config::conservative();
    c.max_width = kSw;
    c.max_height = kSh;
    c.d_min = -2;
    c.d_max = 13;
    static std::byte pool[1U << 20U];
    Arena arena(pool, sizeof pool);
    static stereo::MlStereo matcher;
    static std::int16_t disparity[kSw * kSh];
    static float sigma[kSw * kSh];
    static std::uint8_t reason[kSw * kSh];
    Hasher h;
    const Status s = matcher.init(c, arena);
    h.addI64(static_cast<std::int64_t>(s.code()));
    const stereo::DisparityOutput out{ImageView<std::int16_t>(disparity, kSw, kSh), ImageView<float>(sigma, kSw, kSh),
                                      ImageView<std::uint8_t>(reason, kSw, kSh)};
    const Status r = matcher.compute(ImageView<const std::uint8_t>(left, kSw, kSh),
                                     ImageView<const std::uint8_t>(right, kSw, kSh), out);
    h.addI64(static_cast<std::int64_t>(r.code()));
    for (std::int32_t i = 0; i < kSw * kSh; ++i) {
        h.addI64(disparity[i]);
        h.addDouble(static_cast<double>(sigma[i]));
        h.addI64(reason[i]);
    }
    const auto hashDisparities = [&h]() {
        for (std::int32_t i = 0; i < kSw * kSh; ++i) {
            h.addI64(disparity[i]);
            h.addI64(reason[i]);
        }
    };
    // The same pair with the window moved (setDisparityWindow: the right image moved
    // inside the workspace, black where it has no pixel).
    h.addI64(static_cast<std::int64_t>(matcher.setDisparityWindow(3).code()));
    h.addI64(static_cast<std::int64_t>(matcher
                                           .compute(ImageView<const std::uint8_t>(left, kSw, kSh),
                                                    ImageView<const std::uint8_t>(right, kSw, kSh), out)
                                           .code()));
    hashDisparities();
    // A disparity prior (a plane fitted to three samples, filled per pixel) and the
    // coarse-to-fine search around it.
    static Vec3 samples[4] = {Vec3(10.0, 5.0, 4.6), Vec3(80.0, 10.0, 9.3), Vec3(40.0, 60.0, 5.1),
                              Vec3(20.0, 30.0, 30.0)};
    static double scratch[4];
    stereo::DisparityPlane plane;
    h.addI64(static_cast<std::int64_t>(
        stereo::fitDisparityPlane(Span<const Vec3>(samples, 4U), Span<double>(scratch, 4U), plane).code()));
    h.addDouble(plane.a);
    h.addDouble(plane.b);
    h.addDouble(plane.c);
    static std::int16_t prior[kSw * kSh];
    h.addI64(static_cast<std::int64_t>(
        stereo::fillDisparityPlane(plane, -20, 20, ImageView<std::int16_t>(prior, kSw, kSh)).code()));
    h.addI64(static_cast<std::int64_t>(matcher.setDisparityPrior(ImageView<const std::int16_t>(prior, kSw, kSh)).code()));
    h.addI64(static_cast<std::int64_t>(matcher
                                           .compute(ImageView<const std::uint8_t>(left, kSw, kSh),
                                                    ImageView<const std::uint8_t>(right, kSw, kSh), out)
                                           .code()));
    hashDisparities();
    stereo::PyramidConfig pc;
    pc.max_width = kSw;
    pc.max_height = kSh;
    pc.levels = 1;
    pc.coarse_disparities = 16;
    pc.coarse_window = 5;
    pc.fine_radius_px = 3;
    static std::byte pyramidPool[1U << 20U];
    Arena pyramidArena(pyramidPool, sizeof pyramidPool);
    static stereo::PyramidStereo pyramid;
    h.addI64(static_cast<std::int64_t>(pyramid.init(pc, pyramidArena).code()));
    for (const bool withSurface : {false, true}) {
        const ImageView<const std::int16_t> surface =
            withSurface ? ImageView<const std::int16_t>(prior, kSw, kSh) : ImageView<const std::int16_t>();
        h.addI64(static_cast<std::int64_t>(pyramid
                                               .compute(ImageView<const std::uint8_t>(left, kSw, kSh),
                                                        ImageView<const std::uint8_t>(right, kSw, kSh), surface, -2,
                                                        13, out)
                                               .code()));
        hashDisparities();
    }
    return h.value();
}

// The orbital view of the same terrain (sim/orbital.hpp): thermal 8-bit and visible 16-bit,
// 2 x 2 sub-samples, cast shadows from a low sun, noise on, with the elevation truth.
void hashOrbitalViews(const sim::Terrain& terrain, Hasher& h) noexcept {
    constexpr std::int32_t kOw = 40;
    constexpr std::int32_t kOh = 32;
    static std::uint8_t image8[kOw * kOh];
    static std::uint16_t image16[kOw * kOh];
    static float elevation[kOw * kOh];
    sim::OrbitalParams p;
    p.cell_m = 0.1;
    p.width_px = kOw;
    p.height_px = kOh;
    p.to_sun_site = Vec3(-0.3, 0.8, -0.52).normalized();
    p.noise_fs = 0.01;
    p.noise_seed = 5U;
    sim::OrbitalOutput out;
    out.image8 = ImageView<std::uint8_t>(image8, kOw, kOh);
    out.image16 = ImageView<std::uint16_t>(image16, kOw, kOh);
    out.elevation_m = ImageView<float>(elevation, kOw, kOh);
    const sim::OrbitalModality modalities[2] = {sim::OrbitalModality::kThermal, sim::OrbitalModality::kVisible};
    for (int m = 0; m < 2; ++m) {
        p.modality = modalities[m];
        p.bit_depth = m == 0 ? 8 : 16;
        h.addI64(static_cast<std::int64_t>(sim::renderOrbital(terrain, p, out, nullptr).code()));
        for (std::int32_t i = 0; i < kOw * kOh; ++i) {
            h.addI64(m == 0 ? image8[i] : image16[i]);
            h.addFloat(elevation[i]);
        }
    }
}

// The simulated world (sim/): a small Mars terrain (its content hash), a 64 x 48 frame
// through a pinhole and a CAHVOR camera with shot/read noise and cast shadows (image and
// range truth), and the true disparity of a rectified pair.
std::uint64_t simSection() noexcept {
    constexpr std::int32_t kRw = 64;
    constexpr std::int32_t kRh = 48;
    sim::TerrainParams params = sim::defaultMarsTerrainParams();
    params.seed = 3U;
    params.finest_cell_m = 0.02;
    params.samples_log2 = 6;
    params.levels = 7;
    params.rock_region_radius_m = 10.0;
    static std::byte pool[4U << 20U];
    Arena arena(pool, sizeof pool);
    static sim::Terrain terrain;
    Hasher h;
    const Status built = terrain.build(params, arena);
    h.addI64(static_cast<std::int64_t>(built.code()));
    if (!built.isOk()) {
        return h.value();
    }
    h.addU64(terrain.contentHash());
    static std::uint8_t image[kRw * kRh];
    static float range[kRw * kRh];
    sim::FrameRequest r;
    r.terrain = &terrain;
    const double ground = terrain.elevationAt(0.0, 0.0);
    r.pose = sim::poseLookingAt(Vec3(0.0, 0.0, -(ground + 1.6)), Vec3(4.0, 0.5, -ground));
    r.frame_index = 2U;
    sim::FrameOutput out;
    out.image8 = ImageView<std::uint8_t>(image, kRw, kRh);
    out.truth.range_m = ImageView<float>(range, kRw, kRh);
    CameraModel cahvor = cahvFromPinhole(makePinhole(kRw, kRh, 50.0));
    cahvor.kind = CameraModelKind::kCahvor;
    cahvor.o[2] = 1.0;
    cahvor.r[1] = -0.06;
    const CameraModel models[2] = {makePinhole(kRw, kRh, 50.0), cahvor};
    for (const CameraModel& m : models) {
        r.model = m;
        h.addI64(static_cast<std::int64_t>(sim::renderFrame(r, out, nullptr).code()));
        for (std::int32_t i = 0; i < kRw * kRh; ++i) {
            h.addI64(image[i]);
            h.addFloat(range[i]);
        }
    }
    sim::StereoTruthRequest sr;
    sr.terrain = &terrain;
    sr.left_model = models[0];
    sr.left_pose = r.pose;
    sr.baseline_m = 0.3;
    static std::uint8_t code[kRw * kRh];
    const sim::StereoTruthOutput so{ImageView<float>(range, kRw, kRh), ImageView<std::uint8_t>(code, kRw, kRh),
                                    ImageView<float>()};
    h.addI64(static_cast<std::int64_t>(sim::rectifiedDisparity(sr, so).code()));
    for (std::int32_t i = 0; i < kRw * kRh; ++i) {
        h.addFloat(range[i]);
        h.addI64(code[i]);
    }
    hashOrbitalViews(terrain, h);
    return h.value();
}

// The wide-baseline front end and the terrain products on a small rendered rover pair
// (160 x 120, 1 m apart, toed in): Förstner features, guided matching with the true pose,
// motion refinement from a spoiled pose, rectification (tables and remapped images), and
// triangulation of a synthetic disparity ramp into a height map.
struct WidePair {
    static constexpr std::int32_t kW = 160;
    static constexpr std::int32_t kH = 120;
    std::uint8_t a[kW * kH];
    std::uint8_t b[kW * kH];
    CameraModel model;
    RigidPose pose_a;
    RigidPose pose_b;
};

Status renderWidePair(WidePair& pair, Hasher& h) noexcept {
    sim::TerrainParams params = sim::defaultMarsTerrainParams();
    params.seed = 8U;
    params.finest_cell_m = 0.02;
    params.samples_log2 = 6;
    params.levels = 7;
    params.rock_region_radius_m = 10.0;
    static std::byte pool[4U << 20U];
    Arena arena(pool, sizeof pool);
    static sim::Terrain terrain;
    const Status built = terrain.build(params, arena);
    if (!built.isOk()) {
        return built;
    }
    const double ground = terrain.elevationAt(0.0, 0.0);
    const Vec3 target(6.0, 0.0, -terrain.elevationAt(6.0, 0.0));
    pair.pose_a = sim::poseLookingAt(Vec3(0.0, -0.5, -(ground + 1.9)), target);
    pair.pose_b = sim::poseLookingAt(Vec3(0.0, 0.5, -(ground + 1.9)), target);
    pair.model = makePinhole(WidePair::kW, WidePair::kH, 50.0);
    sim::FrameRequest r;
    r.terrain = &terrain;
    r.model = pair.model;
    sim::FrameOutput out;
    for (std::int32_t k = 0; k < 2; ++k) {
        r.pose = (k == 0) ? pair.pose_a : pair.pose_b;
        r.frame_index = static_cast<std::uint32_t>(k);
        out.image8 = ImageView<std::uint8_t>((k == 0) ? pair.a : pair.b, WidePair::kW, WidePair::kH);
        h.addI64(static_cast<std::int64_t>(sim::renderFrame(r, out, nullptr).code()));
    }
    return Status::ok();
}

void hashMatches(const WidePair& pair, const Mat3& R_ba, const Vec3& t_ba, features::MatchSet& matches,
                 Hasher& h) noexcept {
    features::DetectorConfig dc;
    dc.max_width = WidePair::kW;
    dc.max_height = WidePair::kH;
    dc.grid_cols = 8;
    dc.grid_rows = 6;
    features::MatcherConfig mc;
    mc.max_width = WidePair::kW;
    mc.max_height = WidePair::kH;
    mc.pyramid_levels = 1;
    static std::byte pool[2U << 20U];
    Arena arena(pool, sizeof pool);
    static features::ForstnerDetector detector;
    static features::TemplateMatcher matcher;
    static features::FeatureSet fs;
    h.addI64(static_cast<std::int64_t>(detector.init(dc, arena).code()));
    h.addI64(static_cast<std::int64_t>(matcher.init(mc, arena).code()));
    const ImageView<const std::uint8_t> a(pair.a, WidePair::kW, WidePair::kH);
    const ImageView<const std::uint8_t> b(pair.b, WidePair::kW, WidePair::kH);
    h.addI64(static_cast<std::int64_t>(detector.detect(a, fs).code()));
    for (std::int32_t i = 0; i < fs.count; ++i) {
        h.addDouble(fs.items[i].pixel.x());
        h.addDouble(fs.items[i].pixel.y());
        h.addFloat(fs.items[i].strength);
    }
    features::MatchPrediction p;
    p.pair.model_a = pair.model;
    p.pair.model_b = pair.model;
    p.pair.b_from_a.R = R_ba;
    p.pair.b_from_a.t_m = t_ba;
    p.range_min_m = 1.0;
    p.range_max_m = 200.0;
    p.margin_px = 8.0;
    h.addI64(static_cast<std::int64_t>(matcher.match(a, b, fs, p, matches).code()));
    for (std::int32_t i = 0; i < matches.count; ++i) {
        h.addDouble(matches.items[i].pixel_b.x());
        h.addDouble(matches.items[i].pixel_b.y());
        h.addFloat(matches.items[i].score);
    }
}

void hashMotion(const WidePair& pair, const Mat3& R_ba, const Vec3& t_ba, const features::MatchSet& matches,
                Hasher& h) noexcept {
    static Vec2 pa[features::kMaxFeatures];
    static Vec2 pb[features::kMaxFeatures];
    const auto n = static_cast<std::size_t>(matches.count);
    for (std::size_t i = 0; i < n; ++i) {
        pa[i] = matches.items[i].pixel_a;
        pb[i] = matches.items[i].pixel_b;
    }
    // Odometry-like error: 1.5 deg about the camera's y axis, 5 % of the baseline sideways.
    const Mat3 spoil = Quat(math::cos(0.0131), 0.0, math::sin(0.0131), 0.0).toRotationMatrix();
    motion::MotionInput in;
    in.pair.model_a = pair.model;
    in.pair.model_b = pair.model;
    in.pair.b_from_a.R = spoil * R_ba;
    in.pair.b_from_a.t_m = t_ba + Vec3(0.0, 0.05 * t_ba.norm(), 0.0);
    in.pixels_a = Span<const Vec2>(pa, n);
    in.pixels_b = Span<const Vec2>(pb, n);
    static motion::MotionRefiner refiner;
    motion::MotionResult result;
    h.addI64(static_cast<std::int64_t>(refiner.refine(in, motion::Config{}, result).code()));
    for (std::int32_t i = 0; i < 9; ++i) {
        h.addDouble(result.R_b_from_a(i / 3, i % 3));
    }
    for (std::int32_t i = 0; i < 3; ++i) {
        h.addDouble(result.t_b_from_a_m[i]);
    }
    for (const double c : result.covariance) {
        h.addDouble(c);
    }
    h.addDouble(result.epipolar_sigma_px);
    h.addI64(result.inliers);
}

void hashRectification(const WidePair& pair, const Mat3& R_ba, const Vec3& t_ba, Hasher& h) noexcept {
    rectify::Config c;
    c.max_width = WidePair::kW;
    c.max_height = WidePair::kH;
    static std::byte pool[1U << 20U];
    Arena arena(pool, sizeof pool);
    static rectify::Rectifier rectifier;
    h.addI64(static_cast<std::int64_t>(rectifier.init(c, arena).code()));
    rectify::RectifyInput in;
    in.pair.model_a = pair.model;
    in.pair.model_b = pair.model;
    in.pair.b_from_a.R = R_ba;
    in.pair.b_from_a.t_m = t_ba;
    static rectify::RectifiedPair rp;
    h.addI64(static_cast<std::int64_t>(rectifier.compute(in, rp).code()));
    h.addDouble(rp.model_a.fx_px);
    h.addDouble(rp.model_a.cx_px);
    h.addDouble(rp.model_b.cx_px);
    h.addI64(rp.d_min);
    h.addI64(rp.d_max);
    static std::uint8_t out[WidePair::kW * WidePair::kH];
    const ImageView<std::uint8_t> view(out, rp.model_a.width_px, rp.model_a.height_px);
    for (const rectify::Rectifier::Side side : {rectify::Rectifier::Side::kA, rectify::Rectifier::Side::kB}) {
        const std::uint8_t* src = (side == rectify::Rectifier::Side::kA) ? pair.a : pair.b;
        h.addI64(static_cast<std::int64_t>(
            rectifier.remap(side, ImageView<const std::uint8_t>(src, WidePair::kW, WidePair::kH), view).code()));
        for (std::int32_t i = 0; i < WidePair::kW * WidePair::kH; ++i) {
            h.addI64(out[i]);
        }
    }
}

// The assembled refinement (refine::PairRefiner) from the spoiled prior of hashMotion, on
// the ground scene and on the general scene: refined pose, counts, every inlier's range.
void hashRefine(const WidePair& pair, const Mat3& R_ba, const Vec3& t_ba, Hasher& h) noexcept {
    refine::Config c;
    c.max_width = WidePair::kW;
    c.max_height = WidePair::kH;
    c.detector.grid_cols = 8;
    c.detector.grid_rows = 6;
    c.matcher.pyramid_levels = 1;
    c.match_margin_px = 8.0;
    static std::byte pool[2U << 20U];
    Arena arena(pool, sizeof pool);
    static refine::PairRefiner refiner;
    h.addI64(static_cast<std::int64_t>(refiner.init(c, arena).code()));
    const Mat3 spoil = Quat(math::cos(0.0131), 0.0, math::sin(0.0131), 0.0).toRotationMatrix();
    refine::Request rq;
    rq.prior.model_a = pair.model;
    rq.prior.model_b = pair.model;
    rq.prior.b_from_a.R = spoil * R_ba;
    rq.prior.b_from_a.t_m = t_ba + Vec3(0.0, 0.05 * t_ba.norm(), 0.0);
    rq.image_a = ImageView<const std::uint8_t>(pair.a, WidePair::kW, WidePair::kH);
    rq.image_b = ImageView<const std::uint8_t>(pair.b, WidePair::kW, WidePair::kH);
    rq.range_min_m = 1.0;
    rq.range_max_m = 200.0;
    rq.up_a = pair.pose_a.R.transpose() * Vec3(0.0, 0.0, -1.0);
    rq.camera_height_m = 1.9;
    static refine::Result result;
    for (const refine::Scene scene : {refine::Scene::kGround, refine::Scene::kGeneral}) {
        rq.scene = scene;
        h.addI64(static_cast<std::int64_t>(refiner.refine(rq, result).code()));
        h.addI64(result.visible_px);
        h.addI64(static_cast<std::int64_t>(result.features.size()));
        h.addI64(result.matching.matched);
        h.addI64(result.motion.inliers);
        for (std::int32_t i = 0; i < 9; ++i) {
            h.addDouble(result.refined.b_from_a.R(i / 3, i % 3));
        }
        for (std::int32_t i = 0; i < 3; ++i) {
            h.addDouble(result.refined.b_from_a.t_m[i]);
        }
        for (std::size_t i = 0U; i < result.ranges_m.size(); ++i) {
            h.addDouble(result.inliers[i] != 0U ? result.ranges_m[i] : 0.0);
        }
        h.addDouble(result.rotation_change_deg);
    }
}

void hashTerrain(Hasher& h) noexcept {
    terrain::RectifiedGeometry g;
    g.fx_px = 150.0;
    g.fy_px = 150.0;
    g.cx_left_px = 80.0;
    g.cx_right_px = 70.5;
    g.cy_px = 60.0;
    g.baseline_m = 2.0;
    g.R_site_from_rect = Quat(0.70710678118654752, 0.0, 0.0, 0.70710678118654752).toRotationMatrix();
    static std::int16_t disparity[64 * 48];
    for (std::int32_t y = 0; y < 48; ++y) {
        for (std::int32_t x = 0; x < 64; ++x) {
            disparity[y * 64 + x] = static_cast<std::int16_t>(16 * 12 + 7 * y + (x % 5));
        }
    }
    // The ground bound.
    terrain::RectifiedGeometry tilted = g;  // looking north, 20 deg down, 1.9 m up
    const double tilt = 20.0 * math::kPi / 180.0;
    tilted.R_site_from_rect.col(0) = Vec3(0.0, 1.0, 0.0);
    tilted.R_site_from_rect.col(2) = Vec3(math::cos(tilt), 0.0, math::sin(tilt));
    tilted.R_site_from_rect.col(1) = tilted.R_site_from_rect.col(2).cross(tilted.R_site_from_rect.col(0));
    tilted.left_centre_site_m = Vec3(0.3, -0.2, -1.9);
    static std::int16_t bounded[64 * 48];
    std::memcpy(bounded, disparity, sizeof bounded);
    std::int32_t dropped = 0;
    h.addI64(static_cast<std::int64_t>(terrain::boundByGround(tilted, 1.0, 14, 21,
                                                              ImageView<std::int16_t>(bounded, 64, 48), dropped)
                                           .code()));
    h.addI64(dropped);
    for (const std::int16_t d : bounded) {
        h.addI64(d);
    }
    static terrain::TerrainPoint points[64 * 48];
    terrain::TriangulationStats stats;
    h.addI64(static_cast<std::int64_t>(terrain::triangulate(g, terrain::TriangulationLimits{},
                                                            ImageView<const std::int16_t>(disparity, 64, 48), {},
                                                            Span<terrain::TerrainPoint>(points, 64 * 48), stats)
                                           .code()));
    terrain::HeightMapConfig mc;
    mc.grid.north_edge_m = 20.0;
    mc.grid.west_edge_m = -20.0;
    mc.grid.cell_m = 0.5;
    mc.grid.cols = 80;
    mc.grid.rows = 80;
    mc.reducer = terrain::Reducer::kMean;  // highest and lowest are kept too
    static std::byte pool[80U * 80U * 14U + 256U];
    Arena arena(pool, sizeof pool);
    static terrain::HeightMap map;
    h.addI64(static_cast<std::int64_t>(map.init(mc, arena).code()));
    h.addI64(static_cast<std::int64_t>(
        map.add(Span<const terrain::TerrainPoint>(points, static_cast<std::size_t>(stats.points))).code()));
    for (std::int32_t r = 0; r < mc.grid.rows; ++r) {
        for (std::int32_t c = 0; c < mc.grid.cols; ++c) {
            h.addFloat(map.highest(c, r));
            h.addFloat(map.lowest(c, r));
            h.addFloat(map.elevation(c, r));
            h.addI64(map.count(c, r));
        }
    }
}

std::uint64_t wideBaselineSection() noexcept {
    Hasher h;
    static WidePair pair;
    const Status rendered = renderWidePair(pair, h);
    h.addI64(static_cast<std::int64_t>(rendered.code()));
    if (rendered.isOk()) {
        // Relative pose X_b = R X_a + t of the two camera frames.
        const Mat3 R_ba = pair.pose_b.R.transpose() * pair.pose_a.R;
        const Vec3 t_ba = pair.pose_b.R.transpose() * (pair.pose_a.t_m - pair.pose_b.t_m);
        static features::MatchSet matches;
        hashMatches(pair, R_ba, t_ba, matches, h);
        hashMotion(pair, R_ba, t_ba, matches, h);
        hashRectification(pair, R_ba, t_ba, h);
        hashRefine(pair, R_ba, t_ba, h);
    }
    hashTerrain(h);
    return h.value();
}

// The descent plane sweep on a rendered 12-bit nadir pair (96 x 96, 60 m and 48 m above a
// small terrain, drifting sideways): depth, score and reason of every pixel.
std::uint64_t descentSection() noexcept {
    constexpr std::int32_t kD = 96;
    sim::TerrainParams params = sim::defaultMarsTerrainParams();
    params.seed = 12U;
    params.finest_cell_m = 0.05;
    params.samples_log2 = 6;
    params.levels = 7;
    params.rock_region_radius_m = 10.0;
    static std::byte pool[4U << 20U];
    Arena arena(pool, sizeof pool);
    static sim::Terrain terrain;
    Hasher h;
    const Status built = terrain.build(params, arena);
    h.addI64(static_cast<std::int64_t>(built.code()));
    if (!built.isOk()) {
        return h.value();
    }
    static std::uint16_t images[2][kD * kD];
    descent::PairGeometry g;
    g.camera = makePinhole(kD, kD, 40.0);
    const double ground = terrain.elevationAt(0.0, 0.0);
    const double altitude[2] = {60.0, 48.0};
    for (std::int32_t k = 0; k < 2; ++k) {
        sim::FrameRequest r;
        r.terrain = &terrain;
        r.model = g.camera;
        r.sensor.bit_depth = 12;
        const Vec3 eye(0.5 * k, 0.3 * k, -(ground + altitude[k]));
        r.pose = sim::poseLookingAt(eye, eye + Vec3(0.0, 0.0, 100.0));
        r.frame_index = static_cast<std::uint32_t>(k);
        sim::FrameOutput out;
        out.image16 = ImageView<std::uint16_t>(images[k], kD, kD);
        h.addI64(static_cast<std::int64_t>(sim::renderFrame(r, out, nullptr).code()));
        RigidPose& p = (k == 0) ? g.site_from_cam1 : g.site_from_cam2;
        p.R = r.pose.R;
        p.t_m = r.pose.t_m;
    }
    descent::Config c;
    c.max_width = kD;
    c.max_height = kD;
    c.planes = 24;
    c.depth_min_m = 50.0;
    c.depth_max_m = 70.0;
    c.min_parallax_px = 1.0;
    c.band_rows = 20;
    static std::byte sweep_pool[1U << 20U];
    Arena sweep_arena(sweep_pool, sizeof sweep_pool);
    static descent::PlaneSweep sweep;
    h.addI64(static_cast<std::int64_t>(sweep.init(c, sweep_arena).code()));
    static float depth[kD * kD];
    static float score[kD * kD];
    static std::uint8_t reason[kD * kD];
    const descent::SweepOutput out{ImageView<float>(depth, kD, kD), ImageView<float>(score, kD, kD),
                                   ImageView<std::uint8_t>(reason, kD, kD)};
    h.addI64(static_cast<std::int64_t>(sweep.compute(ImageView<const std::uint16_t>(images[0], kD, kD),
                                                     ImageView<const std::uint16_t>(images[1], kD, kD), g, out)
                                           .code()));
    for (std::int32_t i = 0; i < kD * kD; ++i) {
        h.addFloat(depth[i]);
        h.addFloat(score[i]);
        h.addI64(reason[i]);
    }
    // The depth through the height map, as the descent mapper does: mean per cell.
    terrain::HeightMapConfig mc;
    mc.grid.north_edge_m = g.site_from_cam1.t_m.x() + 80.0;  // the whole footprint (~144 m)
    mc.grid.west_edge_m = g.site_from_cam1.t_m.y() - 80.0;
    mc.grid.cell_m = 5.0;
    mc.grid.cols = 32;
    mc.grid.rows = 32;
    mc.reducer = terrain::Reducer::kMean;
    static std::byte map_pool[32U * 32U * 14U + 256U];
    Arena map_arena(map_pool, sizeof map_pool);
    static terrain::HeightMap map;
    h.addI64(static_cast<std::int64_t>(map.init(mc, map_arena).code()));
    h.addI64(static_cast<std::int64_t>(
        descent::addDepthToHeightMap(ImageView<const float>(depth, kD, kD), g.camera, g.site_from_cam1, map).code()));
    for (std::int32_t row = 0; row < mc.grid.rows; ++row) {
        for (std::int32_t col = 0; col < mc.grid.cols; ++col) {
            h.addFloat(map.elevation(col, row));
            h.addI64(map.count(col, row));
        }
    }
    return h.value();
}

// Local entropy and multi-modal registration (issue 24) on an integer-generated 96 x 96
// scene: flat and noisy boxes; image 2 is image 1 shifted by (5, -3) px seen through a
// folding (non-monotonic) response. The entropy images (plain and equalised through the
// registration) and the registration's transform, scores and counts.
std::uint64_t entropySection() noexcept {
    constexpr std::int32_t kD = 96;
    constexpr std::int32_t kWorldSide = 128;
    static std::uint8_t world[kWorldSide * kWorldSide];
    for (std::int32_t y = 0; y < kWorldSide; ++y) {
        for (std::int32_t x = 0; x < kWorldSide; ++x) {
            world[y * kWorldSide + x] = static_cast<std::uint8_t>(80 + (x + 2 * y) / 8);
        }
    }
    for (std::uint64_t k = 0; k < 24U; ++k) {
        const std::uint64_t h = mixBits64(k + 99U);
        const auto cx = static_cast<std::int32_t>(h % kWorldSide);
        const auto cy = static_cast<std::int32_t>((h >> 8U) % kWorldSide);
        const auto r = static_cast<std::int32_t>(5U + (h >> 16U) % 12U);
        const auto level = static_cast<std::int32_t>(30U + (h >> 24U) % 190U);
        const auto amplitude = static_cast<std::int32_t>((h >> 32U) % 4U) * 20;
        for (std::int32_t y = cy - r; y <= cy + r; ++y) {
            for (std::int32_t x = cx - r; x <= cx + r; ++x) {
                if (x >= 0 && y >= 0 && x < kWorldSide && y < kWorldSide) {
                    const auto n = static_cast<std::int32_t>(mixBits64(static_cast<std::uint64_t>(y * kWorldSide + x) + k * 7919U) % 256U);
                    const std::int32_t v = level + (n - 128) * amplitude / 128;
                    world[y * kWorldSide + x] = static_cast<std::uint8_t>(v < 0 ? 0 : (v > 255 ? 255 : v));
                }
            }
        }
    }
    static std::uint8_t image1[kD * kD];
    static std::uint8_t image2[kD * kD];
    for (std::int32_t y = 0; y < kD; ++y) {
        for (std::int32_t x = 0; x < kD; ++x) {
            image1[y * kD + x] = world[(y + 16) * kWorldSide + x + 16];
            const std::int32_t t = (world[(y + 16 + 3) * kWorldSide + x + 16 - 5] * 3) % 510;
            image2[y * kD + x] = static_cast<std::uint8_t>(t < 255 ? t : 509 - t);
        }
    }
    Hasher h;
    entropy::RegistrationConfig c;
    c.max_width = kD;
    c.max_height = kD;
    c.levels = 3;
    c.entropy.window = 7;
    c.entropy.bins = 16;
    static std::byte pool[256U << 10U];
    Arena arena(pool, sizeof pool);
    static entropy::LocalEntropy plain;
    h.addI64(static_cast<std::int64_t>(plain.init(c.entropy, arena).code()));
    static std::uint8_t e[kD * kD];
    h.addI64(static_cast<std::int64_t>(
        plain.compute(ImageView<const std::uint8_t>(image2, kD, kD), ImageView<std::uint8_t>(e, kD, kD)).code()));
    for (const std::uint8_t v : e) {
        h.addI64(v);
    }
    static entropy::EntropyRegistration reg;
    h.addI64(static_cast<std::int64_t>(reg.init(c, arena).code()));
    entropy::RegistrationRequest q;
    q.angle_min_rad = -0.3;
    q.angle_max_rad = 0.3;
    q.scale_min = 0.9;
    q.scale_max = 1.1;
    q.shift_range_px = 8.0;
    entropy::Registration r;
    h.addI64(static_cast<std::int64_t>(reg.registerImages(ImageView<const std::uint8_t>(image1, kD, kD),
                                                          ImageView<const std::uint8_t>(image2, kD, kD), q, r)
                                           .code()));
    const ImageView<const std::uint8_t> m1 = reg.matchedImage1();
    for (std::int32_t y = 0; y < m1.height(); ++y) {
        for (std::int32_t x = 0; x < m1.width(); ++x) {
            h.addI64(m1.at(x, y));
        }
    }
    for (std::int32_t i = 0; i < 6; ++i) {
        h.addDouble(r.image2_from_image1(i / 3, i % 3));
    }
    h.addDouble(r.ncc);
    h.addDouble(r.second_ncc);
    h.addDouble(r.overlap);
    h.addI64(r.coarse_scored);
    h.addI64(r.fine_scored);
    return h.value();
}

// The terrain octree and its height products (issue 25): 4,000 integer-generated samples
// of a 32 m cube (footprints 2 cm..40 m, four sources, a few refused), every node and
// counter, then products at three levels (mean reducer): every bin's highest, lowest,
// mean, count, data level and sources.
std::uint64_t octreeSection() noexcept {
    Hasher h;
    octree::OctreeConfig c;
    c.north_edge_m = 16.0;
    c.west_edge_m = -16.0;
    c.top_z_m = -8.0;
    c.side_m = 32.0;
    c.max_depth = 9;
    c.max_nodes = 9000;
    static std::byte pool[9000U * sizeof(octree::OctreeNode) + 64U];
    Arena arena(pool, sizeof pool);
    static octree::Octree tree;
    h.addI64(static_cast<std::int64_t>(tree.init(c, arena).code()));
    for (std::uint64_t k = 0; k < 4000U; ++k) {
        const std::uint64_t r = mixBits64(k + 2525U);
        octree::Sample s;
        const double x = -16.5 + 33.0 * static_cast<double>(r & 0xFFFFU) / 65536.0;  // a few outside
        const double y = -16.0 + 32.0 * static_cast<double>((r >> 16U) & 0xFFFFU) / 65536.0;
        const double bump = 1.0 - (x * x + y * y) / 300.0;
        s.site_m = Vec3(x, y, -(bump * bump * 2.0 + 0.03 * x - 0.02 * y));
        s.footprint_m = 0.02 * static_cast<double>(1U + ((r >> 32U) & 0x7FFU));  // 0.02 .. 40.96 m
        s.source = static_cast<std::uint8_t>((r >> 48U) & 3U);
        h.addI64(static_cast<std::int64_t>(tree.insert(s).code()));
    }
    for (std::uint32_t i = 0; i < tree.nodeCount(); ++i) {
        const octree::OctreeNode& n = tree.node(i);
        h.addI64(n.level);
        h.addI64(n.key_x);
        h.addI64(n.key_y);
        h.addI64(n.key_z);
        h.addI64(n.count);
        h.addI64(n.sources);
        h.addDouble(n.sum_m);
        h.addFloat(n.count > 0U ? n.highest_m : 0.0F);
        h.addFloat(n.count > 0U ? n.lowest_m : 0.0F);
        for (const std::uint32_t child : n.child) {
            h.addI64(child);
        }
    }
    h.addI64(tree.stats().inserted);
    h.addI64(tree.stats().refused_outside);
    octree::ProductConfig pc;
    pc.levels = {{2, 5, 7, 0, 0, 0}};
    pc.count = 3;
    pc.reducer = terrain::Reducer::kMean;
    static std::byte product_pool[400U << 10U];
    Arena product_arena(product_pool, sizeof product_pool);
    static octree::HeightProducts products;
    h.addI64(static_cast<std::int64_t>(products.init(pc, c, product_arena).code()));
    h.addI64(static_cast<std::int64_t>(products.extract(tree).code()));
    for (std::int32_t p = 0; p < products.count(); ++p) {
        const terrain::HeightMap& m = products.map(p);
        for (std::int32_t row = 0; row < m.grid().rows; ++row) {
            for (std::int32_t col = 0; col < m.grid().cols; ++col) {
                h.addFloat(m.highest(col, row));
                h.addFloat(m.lowest(col, row));
                h.addFloat(m.elevation(col, row));
                h.addI64(m.count(col, row));
                h.addI64(products.dataLevel(p, col, row));
                h.addI64(products.sources(p, col, row));
            }
        }
    }
    return h.value();
}

// Point-to-plane ICP (issue 25 item 2): a 16 m model of rolling hills and rocks (height
// field from vtm::math sin/cos and integer hashing, jittered grid, noise from vtm::Random)
// and a 12 m data cloud moved by a known rotation and translation. The refined pose, its
// covariance and the fit's figures; then a flat model's refusal.
double icpTerrainZ(double x, double y) noexcept {
    double z = -(0.8 * math::sin(0.31 * x + 0.5) * math::cos(0.23 * y - 0.3) + 0.35 * math::sin(0.67 * x + 0.52 * y));
    for (std::uint64_t k = 0; k < 12U; ++k) {
        const std::uint64_t h = mixBits64(k + 7U);
        const double cx = -8.0 + static_cast<double>(h % 1600U) * 0.01;
        const double cy = -8.0 + static_cast<double>((h >> 16U) % 1600U) * 0.01;
        const double r = 0.3 + static_cast<double>((h >> 32U) % 40U) * 0.01;
        const double d2 = (x - cx) * (x - cx) + (y - cy) * (y - cy);
        z -= d2 < r * r ? 0.7 * math::sqrt(r * r - d2) : 0.0;
    }
    return z;
}

std::size_t icpCloud(double x0, double y0, double side, std::int32_t n, std::uint64_t seed, const RigidPose& model_from_data,
                     bool flat, Vec3* out) noexcept {
    Random rng(seed);
    const double step = side / static_cast<double>(n);
    std::size_t count = 0U;
    for (std::int32_t j = 0; j < n; ++j) {
        for (std::int32_t i = 0; i < n; ++i) {
            const double x = x0 + (i + 0.5 + 0.8 * (rng.uniform01() - 0.5)) * step;
            const double y = y0 + (j + 0.5 + 0.8 * (rng.uniform01() - 0.5)) * step;
            const double z = (flat ? 0.0 : icpTerrainZ(x, y)) + rng.normal(0.0, 0.01);
            out[count++] = model_from_data.R.transpose() * (Vec3(x, y, z) - model_from_data.t_m);
        }
    }
    return count;
}

void hashIcpResult(const Status& s, const icp::IcpResult& r, Hasher& h) noexcept {
    h.addI64(static_cast<std::int64_t>(s.code()));
    h.addI64(s.detail());
    for (std::int32_t i = 0; i < 9; ++i) {
        h.addDouble(r.model_from_data.R(i / 3, i % 3));
    }
    for (std::int32_t i = 0; i < 3; ++i) {
        h.addDouble(r.model_from_data.t_m(i));
    }
    for (std::int32_t i = 0; i < 36; ++i) {
        h.addDouble(r.covariance(i / 6, i % 6));
    }
    h.addDouble(r.rms_residual_m);
    h.addDouble(r.sigma_m);
    h.addDouble(r.overlap);
    h.addDouble(r.eigen_ratio);
    h.addI64(r.correspondences);
    h.addI64(r.inliers);
    h.addI64(r.iterations);
    h.addI64(static_cast<std::int64_t>(r.stop));
}

std::uint64_t icpSection() noexcept {
    static Vec3 model[1600];
    static Vec3 data[900];
    RigidPose truth;
    truth.R = Quat(1.0, 0.01, -0.007, 0.02).normalized().toRotationMatrix();
    truth.t_m = Vec3(0.3, -0.2, 0.08);
    Hasher h;
    icp::IcpConfig c;
    c.max_model_points = 1600;
    c.max_data_points = 900;
    static std::byte pool[256U << 10U];
    Arena arena(pool, sizeof pool);
    static icp::PointToPlaneIcp reg;
    h.addI64(static_cast<std::int64_t>(reg.init(c, arena).code()));
    for (const bool flat : {false, true}) {
        const std::size_t nm = icpCloud(-8.0, -8.0, 16.0, 40, 21U, RigidPose{}, flat, model);
        const std::size_t nd = icpCloud(-4.0, -6.0, 12.0, 30, 22U, truth, flat, data);
        h.addI64(static_cast<std::int64_t>(reg.setModel(Span<const Vec3>(model, nm)).code()));
        h.addI64(reg.modelNormalCount());
        icp::IcpResult r;
        const Status s = reg.registerData(Span<const Vec3>(data, nd), RigidPose{}, r);
        hashIcpResult(s, r, h);
    }
    return h.value();
}

// The descent's orbital fix (issue 24 item 4, fsw/app OrbitalLocator): a generated 128 x 128
// orbital map at 1 m per pixel, two nadir 96 x 96 frames of it (100 m and 90 m up, through
// a folding response), 36 ground features in both, navigation poses 2.5 m off with a 1 %
// long baseline. Every figure of the located frames and of the fix.
std::uint64_t orbitalFixSection() noexcept {
    constexpr std::int32_t kMap = 128;
    constexpr std::int32_t kD = 96;
    static std::uint8_t map[kMap * kMap];
    for (std::int32_t y = 0; y < kMap; ++y) {
        for (std::int32_t x = 0; x < kMap; ++x) {
            map[y * kMap + x] = static_cast<std::uint8_t>(60 + (3 * x + y) / 4);
        }
    }
    for (std::uint64_t k = 0; k < 40U; ++k) {
        const std::uint64_t r = mixBits64(k + 424U);
        const auto cx = static_cast<std::int32_t>(r % kMap);
        const auto cy = static_cast<std::int32_t>((r >> 8U) % kMap);
        const auto rad = static_cast<std::int32_t>(2U + (r >> 16U) % 7U);
        const auto level = static_cast<std::uint8_t>(20U + (r >> 24U) % 200U);
        for (std::int32_t y = cy - rad; y <= cy + rad; ++y) {
            for (std::int32_t x = cx - rad; x <= cx + rad; ++x) {
                if (x >= 0 && y >= 0 && x < kMap && y < kMap) map[y * kMap + x] = level;
            }
        }
    }
    app::OrbitalMap orbital;
    orbital.image8 = ImageView<const std::uint8_t>(map, kMap, kMap);
    orbital.geo.north0_m = 63.5;  // centred on the site origin
    orbital.geo.east0_m = -63.5;
    orbital.geo.cell_m = 1.0;
    const CameraModel model = makePinhole(kD, kD, 42.0);
    Mat3 nadir;  // image right = east, image down = south, axis down
    nadir << 0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0;
    const Vec3 truth[2] = {Vec3(0.0, 0.0, -100.0), Vec3(1.0, 0.5, -90.0)};
    static std::uint16_t frames[2][kD * kD];
    for (std::int32_t i = 0; i < 2; ++i) {
        for (std::int32_t y = 0; y < kD; ++y) {
            for (std::int32_t x = 0; x < kD; ++x) {
                const Vec3 d = nadir * Vec3((x - model.cx_px) / model.fx_px, (y - model.cy_px) / model.fy_px, 1.0);
                const Vec3 g = truth[i] + (-truth[i].z() / d.z()) * d;
                auto col = static_cast<std::int32_t>(g.y() + 63.5 + 0.5);
                auto row = static_cast<std::int32_t>(63.5 - g.x() + 0.5);
                col = col < 0 ? 0 : (col >= kMap ? kMap - 1 : col);
                row = row < 0 ? 0 : (row >= kMap ? kMap - 1 : row);
                const std::int32_t t = (map[row * kMap + col] * 3) % 510;
                frames[i][y * kD + x] = static_cast<std::uint16_t>(16 * (t < 255 ? t : 509 - t) + 3);  // 12 bits
            }
        }
    }
    static Vec2 pixels[2][36];
    static std::uint8_t inliers[36];
    static double ranges[36];
    const double nav_scale = 1.01;
    for (std::int32_t j = 0; j < 36; ++j) {
        const Vec3 ground(-20.0 + 8.0 * (j / 6), -20.0 + 8.0 * (j % 6), 0.0);
        for (std::int32_t i = 0; i < 2; ++i) {
            const Vec3 c = nadir.transpose() * (ground - truth[i]);
            pixels[i][j] = Vec2(model.fx_px * c.x() / c.z() + model.cx_px, model.fy_px * c.y() / c.z() + model.cy_px);
        }
        inliers[j] = j == 7 ? 0U : 1U;
        ranges[j] = nav_scale * (ground - truth[0]).norm();
    }
    refine::Result result;
    result.pixels_a = Span<const Vec2>(pixels[0], 36);
    result.pixels_b = Span<const Vec2>(pixels[1], 36);
    result.inliers = Span<const std::uint8_t>(inliers, 36);
    result.ranges_m = Span<const double>(ranges, 36);
    app::LocateInput in;
    in.model = model;
    in.frame1 = ImageView<const std::uint16_t>(frames[0], kD, kD);
    in.frame2 = ImageView<const std::uint16_t>(frames[1], kD, kD);
    in.site_from_cam1 = RigidPose{nadir, truth[0] + Vec3(2.0, -1.5, 0.0)};
    in.site_from_cam2 = RigidPose{nadir, in.site_from_cam1.t_m + nav_scale * (truth[1] - truth[0])};
    in.refine = &result;
    in.position_sigma_m[0] = 2.0;
    in.position_sigma_m[1] = 2.0;
    app::OrbitalFixConfig c;
    c.enabled = true;
    c.registration.max_width = kMap;
    c.registration.max_height = kMap;
    static std::byte pool[1U << 20U];
    Arena arena(pool, sizeof pool);
    static app::OrbitalLocator locator;
    Hasher h;
    h.addI64(static_cast<std::int64_t>(locator.init(c, kD, kD, arena).code()));
    h.addI64(static_cast<std::int64_t>(locator.setMap(orbital).code()));
    app::OrbitalFix fix;
    h.addI64(static_cast<std::int64_t>(locator.locate(in, fix).code()));
    h.addDouble(fix.scale);
    h.addI64(fix.scale_applied ? 1 : 0);
    h.addDouble(fix.camera1_ne_m.x());
    h.addDouble(fix.camera1_ne_m.y());
    h.addDouble(fix.residual_px);
    for (const app::LocatedFrame& f : fix.frames) {
        h.addI64(static_cast<std::int64_t>(f.status.code()));
        h.addI64(f.reduction);
        h.addI64(f.features);
        for (std::int32_t i = 0; i < 6; ++i) h.addDouble(f.registration.image2_from_image1(i / 3, i % 3));
        h.addDouble(f.registration.ncc);
        h.addDouble(f.registration.second_ncc);
        h.addDouble(f.position_ne_m.x());
        h.addDouble(f.position_ne_m.y());
        h.addDouble(f.scale);
        h.addDouble(f.residual_px);
        h.addDouble(f.cut_origin_px.x());
        h.addDouble(f.cut_origin_px.y());
    }
    return h.value();
}

}  // namespace

const char* sectionName(Section s) noexcept {
    switch (s) {
        case Section::kEigen: return "eigen";
        case Section::kMath: return "math";
        case Section::kRandom: return "random";
        case Section::kImage: return "image";
        case Section::kFmaSensitive: return "fma_sensitive";
        case Section::kStereo: return "stereo";
        case Section::kSim: return "sim";
        case Section::kWideBaseline: return "wide_baseline";
        case Section::kDescent: return "descent";
        case Section::kEntropy: return "entropy";
        case Section::kOctree: return "octree";
        case Section::kIcp: return "icp";
        case Section::kOrbitalFix: return "orbital_fix";
        case Section::kPanorama: return "panorama";
        case Section::kTiepoints: return "tiepoints";
        case Section::kBundle: return "bundle";
        case Section::kKriging: return "kriging";
    }
    return "unknown";
}

std::uint64_t sectionHash(Section s) noexcept {
    switch (s) {
        case Section::kEigen: return eigenSection();
        case Section::kMath: return mathSection();
        case Section::kRandom: return randomSection();
        case Section::kImage: return imageSection();
        case Section::kFmaSensitive: return fmaSensitiveSection();
        case Section::kStereo: return stereoSection();
        case Section::kSim: return simSection();
        case Section::kWideBaseline: return wideBaselineSection();
        case Section::kDescent: return descentSection();
        case Section::kEntropy: return entropySection();
        case Section::kOctree: return octreeSection();
        case Section::kIcp: return icpSection();
        case Section::kOrbitalFix: return orbitalFixSection();
        case Section::kPanorama: return panoramaSection();
        case Section::kTiepoints: return tiepointsSection();
        case Section::kBundle: return bundleSection();
        case Section::kKriging: return krigingSection();
    }
    return 0U;
}

}  // namespace vtm::determinism
