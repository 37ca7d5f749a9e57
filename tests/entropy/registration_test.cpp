// vtm_entropy_tests (registration): a known similarity recovered between two "sensors"
// whose intensities are related by a non-monotonic response (where intensity NCC, the
// peer in the same run, does worse); refusal of unrelated noise; errors; every bad config
// field named; two runs give the same bits; no heap on the run path.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "entropy_scene.hpp"
#include "no_heap_guard.hpp"
#include "vtm/entropy/registration.hpp"

namespace vtm::entropy {
namespace {

constexpr std::int32_t kSize = 96;
constexpr std::int32_t kOffset = 80;  // image 1 = the world's window at (80, 80)

RegistrationConfig testConfig(Representation representation = Representation::kEntropy) {
    RegistrationConfig c;
    c.max_width = 128;
    c.max_height = 128;
    c.levels = 3;
    c.entropy.window = 5;
    c.entropy.bins = 8;
    // The synthetic world is piecewise constant on a gentle gradient, without sensor noise:
    // equalisation would cut the gradient into bands of bin boundaries that the other
    // sensor's folded response puts elsewhere. Real images (docs/entropy.md) equalise.
    c.equalise = false;
    c.representation = representation;
    return c;
}

struct Registrar {
    std::vector<std::byte> pool;
    Arena arena;
    EntropyRegistration reg;
    explicit Registrar(const RegistrationConfig& c)
        : pool(EntropyRegistration::workspaceBytes(c)), arena(pool.data(), pool.size()) {
        EXPECT_TRUE(reg.init(c, arena).isOk());
        arena.freeze();
    }
};

Mat23 truthMatrix(const test::Similarity& g, std::int32_t size1, std::int32_t size2) {
    const double c1 = 0.5 * (size1 - 1);
    const double c2 = 0.5 * (size2 - 1);
    const double c = g.scale * std::cos(g.angle_rad);
    const double s = g.scale * std::sin(g.angle_rad);
    Mat23 m;
    m << c, -s, c2 + g.tx - (c * c1 - s * c1), s, c, c2 + g.ty - (s * c1 + c * c1);
    return m;
}

struct Scene {
    std::vector<std::uint8_t> image1;
    std::vector<std::uint8_t> image2;
    test::Similarity truth;
};

const Scene& scene() {
    static const Scene s = [] {
        Scene q;
        const std::vector<std::uint8_t> world = test::makeWorld(11U);
        q.truth.angle_rad = 0.21;  // 12 degrees
        q.truth.scale = 1.12;
        q.truth.tx = 4.3;
        q.truth.ty = -2.6;
        q.image1 = test::cameraImage(world, kSize, kOffset);
        q.image2 = test::secondSensorImage(world, kSize, kOffset, kSize, q.truth, 4);
        return q;
    }();
    return s;
}

RegistrationRequest request() {
    RegistrationRequest r;
    r.angle_min_rad = -0.5236;  // +-30 degrees
    r.angle_max_rad = 0.5236;
    r.scale_min = 0.8;
    r.scale_max = 1.25;
    r.shift_range_px = 8.0;
    return r;
}

ImageView<const std::uint8_t> view(const std::vector<std::uint8_t>& v, std::int32_t side) {
    return ImageView<const std::uint8_t>(v.data(), side, side);
}

TEST(EntropyRegistration, RecoversAKnownSimilarityAcrossSensorsWhereIntensityNccDoesWorse) {
    const Scene& s = scene();
    Registrar e(testConfig());
    Registration r;
    const Status st = e.reg.registerImages(view(s.image1, kSize), view(s.image2, kSize), request(), r);
    ASSERT_TRUE(st.isOk()) << st.reason() << " ncc " << r.ncc << " second " << r.second_ncc;
    const Mat23 truth = truthMatrix(s.truth, kSize, kSize);
    const double error = test::cornerError(r.image2_from_image1, truth, kSize, kSize);
    EXPECT_LT(error, 1.0) << "angle " << r.angle_rad << " scale " << r.scale << " t " << r.shift_x_px << ", "
                          << r.shift_y_px << " ncc " << r.ncc << " second " << r.second_ncc;
    EXPECT_GT(r.ncc, 0.5);
    EXPECT_GT(r.overlap, 0.5);

    // The same search on the intensities (the peer): refused, or farther from the truth.
    Registrar i(testConfig(Representation::kIntensity));
    Registration ri;
    const Status si = i.reg.registerImages(view(s.image1, kSize), view(s.image2, kSize), request(), ri);
    const double intensityError = test::cornerError(ri.image2_from_image1, truth, kSize, kSize);
    std::printf("entropy: corner error %.3f px, ncc %.3f (second %.3f); intensity: %s, %.3f px, ncc %.3f\n", error,
                r.ncc, r.second_ncc, statusCodeName(si.code()), intensityError, ri.ncc);
    EXPECT_TRUE(!si.isOk() || intensityError > 3.0 * std::max(error, 0.3));
}

TEST(EntropyRegistration, SameSensorIsRecoveredByBothRepresentations) {
    // Sanity of the peer itself: without the response change intensity NCC works too.
    const std::vector<std::uint8_t> world = test::makeWorld(5U);
    test::Similarity g;
    g.angle_rad = -0.35;
    g.scale = 0.9;
    g.tx = -3.0;
    g.ty = 5.5;
    const std::vector<std::uint8_t> a = test::cameraImage(world, kSize, kOffset);
    const std::vector<std::uint8_t> b = test::secondSensorImage(world, kSize, kOffset, kSize, g, 2, false);
    const Mat23 truth = truthMatrix(g, kSize, kSize);
    for (const Representation rep : {Representation::kEntropy, Representation::kIntensity}) {
        Registrar e(testConfig(rep));
        Registration r;
        ASSERT_TRUE(e.reg.registerImages(view(a, kSize), view(b, kSize), request(), r).isOk())
            << static_cast<int>(rep);
        EXPECT_LT(test::cornerError(r.image2_from_image1, truth, kSize, kSize), 1.0)
            << static_cast<int>(rep) << " angle " << r.angle_rad << " scale " << r.scale << " t " << r.shift_x_px
            << ", " << r.shift_y_px;
    }
}

TEST(EntropyRegistration, UnrelatedNoiseIsRefused) {
    std::vector<std::uint8_t> a(kSize * kSize);
    std::vector<std::uint8_t> b(kSize * kSize);
    for (std::size_t i = 0; i < a.size(); ++i) {
        a[i] = static_cast<std::uint8_t>(test::hashNoise(i) & 0xFFU);
        b[i] = static_cast<std::uint8_t>(test::hashNoise(i + 1000003U) & 0xFFU);
    }
    Registrar e(testConfig());
    Registration r;
    const Status st = e.reg.registerImages(view(a, kSize), view(b, kSize), request(), r);
    EXPECT_FALSE(st.isOk()) << "ncc " << r.ncc << " second " << r.second_ncc;
    EXPECT_TRUE(st.code() == StatusCode::kNoData || st.code() == StatusCode::kDegenerate) << st.reason();
    // A flat image has no entropy contrast at all.
    std::vector<std::uint8_t> flat(kSize * kSize, 77);
    EXPECT_EQ(e.reg.registerImages(view(flat, kSize), view(b, kSize), request(), r).code(), StatusCode::kDegenerate);
}

TEST(EntropyRegistration, TooLittleOverlapIsRefused) {
    const Scene& s = scene();
    RegistrationConfig c = testConfig();
    c.min_overlap = 1.0;  // image 1 must map entirely into image 2: impossible at scale >= 0.8 and 12 deg
    Registrar e(c);
    Registration r;
    RegistrationRequest q = request();
    q.scale_min = 1.0;
    EXPECT_EQ(e.reg.registerImages(view(s.image1, kSize), view(s.image2, kSize), q, r).code(), StatusCode::kNoData);
}

TEST(EntropyRegistration, TwoRunsGiveTheSameBitsAndTouchNoHeap) {
    const Scene& s = scene();
    Registrar e(testConfig());
    // A narrower search than request()'s (a third of the cost under qemu): the whole run
    // path still runs, coarse grid, shifts, refinement and subpixel fit.
    RegistrationRequest q = request();
    q.angle_min_rad = 0.0;
    q.angle_max_rad = 0.35;
    q.scale_min = 1.0;
    Registration first;
    Registration second;
    ASSERT_TRUE(e.reg.registerImages(view(s.image1, kSize), view(s.image2, kSize), q, first).isOk());
    vtm::test::NoHeapScope guard;
    const Status st = e.reg.registerImages(view(s.image1, kSize), view(s.image2, kSize), q, second);
    EXPECT_EQ(guard.heapCalls(), 0U);
    ASSERT_TRUE(st.isOk());
    for (std::int32_t i = 0; i < 6; ++i) {
        EXPECT_EQ(first.image2_from_image1(i / 3, i % 3), second.image2_from_image1(i / 3, i % 3));
    }
    EXPECT_EQ(first.ncc, second.ncc);
    EXPECT_EQ(first.fine_scored, second.fine_scored);
}

TEST(EntropyRegistration, ErrorsNameTheInput) {
    const Scene& s = scene();
    EntropyRegistration fresh;
    Registration r;
    EXPECT_EQ(fresh.registerImages(view(s.image1, kSize), view(s.image2, kSize), request(), r).code(),
              StatusCode::kNotInitialized);
    Registrar e(testConfig());
    auto reason = [&](const RegistrationRequest& q) {
        return std::string(e.reg.registerImages(view(s.image1, kSize), view(s.image2, kSize), q, r).reason());
    };
    RegistrationRequest q = request();
    q.angle_max_rad = q.angle_min_rad - 0.1;
    EXPECT_NE(reason(q).find("request.angle"), std::string::npos);
    q = request();
    q.scale_min = 0.01;
    EXPECT_NE(reason(q).find("request.scale"), std::string::npos);
    q = request();
    q.shift_x_px = std::nan("");
    EXPECT_NE(reason(q).find("request.shift_x_px"), std::string::npos);
    q = request();
    q.shift_range_px = -1.0;
    EXPECT_NE(reason(q).find("request.shift_range_px"), std::string::npos);
    EXPECT_EQ(e.reg.registerImages(ImageView<const std::uint8_t>(), view(s.image2, kSize), request(), r).code(),
              StatusCode::kInvalidArgument);
    std::vector<std::uint8_t> big(200 * 20, 5);
    EXPECT_EQ(e.reg.registerImages(ImageView<const std::uint8_t>(big.data(), 200, 20), view(s.image2, kSize),
                                   request(), r).code(),
              StatusCode::kSizeMismatch);
    std::vector<std::uint8_t> small(24 * 24, 5);  // 6 px at level 2
    EXPECT_EQ(e.reg.registerImages(view(s.image1, kSize), ImageView<const std::uint8_t>(small.data(), 24, 24),
                                   request(), r).code(),
              StatusCode::kSizeMismatch);
}

TEST(RegistrationConfig, EveryBadFieldIsNamedAndTheWorkspaceFits) {
    auto reason = [](const RegistrationConfig& c) { return std::string(c.validate().reason()); };
    struct Case {
        void (*mutate)(RegistrationConfig&);
        const char* field;
    };
    const Case cases[] = {
        {[](RegistrationConfig& c) { c.max_width = 15; }, "registration.max_width"},
        {[](RegistrationConfig& c) { c.max_height = 5000; }, "registration.max_height"},
        {[](RegistrationConfig& c) { c.entropy.window = 2; }, "entropy.window"},
        {[](RegistrationConfig& c) { c.entropy.bins = 3; }, "entropy.bins"},
        {[](RegistrationConfig& c) { c.entropy.input_bits = 7; }, "entropy.input_bits"},
        {[](RegistrationConfig& c) { c.representation = static_cast<Representation>(7); }, "registration.representation"},
        {[](RegistrationConfig& c) { c.fill_max_grey = 255; }, "registration.fill_max_grey"},
        {[](RegistrationConfig& c) { c.equalise_radius_px = -1; }, "registration.equalise_radius_px"},
        {[](RegistrationConfig& c) { c.equalise_radius_px = 64; }, "registration.equalise_radius_px"},
        {[](RegistrationConfig& c) { c.levels = 0; }, "registration.levels"},
        {[](RegistrationConfig& c) { c.levels = 6; }, "registration.levels"},  // 128 >> 5 = 4 px
        {[](RegistrationConfig& c) { c.max_angle_steps = 0; }, "registration.max_angle_steps"},
        {[](RegistrationConfig& c) { c.max_scale_steps = 300; }, "registration.max_scale_steps"},
        {[](RegistrationConfig& c) { c.max_shift_steps = 32; }, "registration.max_shift_steps"},
        {[](RegistrationConfig& c) { c.candidates = 17; }, "registration.candidates"},
        {[](RegistrationConfig& c) { c.refine_rounds = 0; }, "registration.refine_rounds"},
        {[](RegistrationConfig& c) { c.min_overlap = 0.0; }, "registration.min_overlap"},
        {[](RegistrationConfig& c) { c.min_ncc = 1.5; }, "registration.min_ncc"},
        {[](RegistrationConfig& c) { c.max_peak_ratio = std::nan(""); }, "registration.max_peak_ratio"},
    };
    for (const Case& k : cases) {
        RegistrationConfig c = testConfig();
        k.mutate(c);
        EXPECT_EQ(c.validate().code(), StatusCode::kInvalidConfig) << k.field;
        EXPECT_NE(reason(c).find(k.field), std::string::npos) << k.field << ": " << reason(c);
        EXPECT_EQ(EntropyRegistration::workspaceBytes(c), 0U) << k.field;
    }
    const RegistrationConfig c = testConfig();
    std::vector<std::byte> pool(EntropyRegistration::workspaceBytes(c));
    Arena exact(pool.data(), pool.size());
    EntropyRegistration reg;
    EXPECT_TRUE(reg.init(c, exact).isOk());
    Arena small(pool.data(), pool.size() / 2U);
    EXPECT_EQ(reg.init(c, small).code(), StatusCode::kOutOfMemory);
    // The default (512 x 512, three levels) stays under 2 MiB.
    EXPECT_LT(EntropyRegistration::workspaceBytes(RegistrationConfig{}), std::size_t{2} << 20U);
}

}  // namespace
}  // namespace vtm::entropy
