// vtm_entropy_srif_evaluation (host only, label "accuracy"): multi-modal registration on
// the real SRIF pairs (../shared/data/srif, README there), the module's entropy images
// against two peers on the same pairs and the same search:
//   - intensity NCC: the module itself with Representation::kIntensity;
//   - mutual information (Viola and Wells; Maes et al.): this file's own implementation of
//     the same coarse grid and pattern search, scoring MI of the grey levels (32 x 32 joint
//     histogram) instead of NCC.
// optical-infrared: 256 x 256 pairs with their ground-truth similarity (gt_N.txt).
// optical-map: 400 x 400 pairs in the same geometry; image 1 = the optical image's central
// 224 x 224, image 2 = 224 x 224 of the map under a known similarity drawn per pair
// (rotation +-30 deg, scale 0.8-1.25 log-uniform, shift +-8 px).
// A pair is correct when image 1's four corners land within 3 px of the truth's.
//
// CI runs a subset (every 10th optical-infrared pair from pair 2, every 80th optical-map
// pair: about 1.5 minutes of CPU); VTM_SRIF_FULL=1 runs all 200 + 200 (about 33 min),
// VTM_SRIF_STEP=n every n-th pair of both, VTM_SRIF_FIRST the first infrared pair
// (docs/entropy.md has the figures and the commands).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "entropy_scene.hpp"
#include "test_data.hpp"
#include "vtm/core/image_pyramid.hpp"
#include "vtm/core/random.hpp"
#include "vtm/entropy/registration.hpp"
#include "vtm/ground/image_io.hpp"

namespace vtm::entropy {
namespace {

constexpr double kCorrectPx = 3.0;
constexpr std::int32_t kMapCrop = 224;
constexpr std::int32_t kLevels = 3;

std::string dataRoot() { return vtm::test::testDataSet("srif"); }

bool fullRun() {
    const char* env = std::getenv("VTM_SRIF_FULL");
    return env != nullptr && std::string(env) == "1";
}

std::int32_t envInt(const char* name, std::int32_t fallback) {
    const char* env = std::getenv(name);
    return env != nullptr ? std::atoi(env) : fallback;
}

// radius: the module's equalisation (registration.equalise_radius_px).
RegistrationConfig moduleConfig(Representation rep, std::int32_t radius) {
    RegistrationConfig c;
    c.equalise_radius_px = envInt("VTM_ENTROPY_RADIUS", radius);
    c.max_width = 256;
    c.max_height = 256;
    c.levels = kLevels;
    // The module's defaults; the variables let a tuning run try others (docs/entropy.md).
    c.entropy.window = envInt("VTM_ENTROPY_WINDOW", c.entropy.window);
    c.entropy.bins = envInt("VTM_ENTROPY_BINS", c.entropy.bins);
    c.representation = rep;
    c.fill_max_grey = envInt("VTM_ENTROPY_FILL", c.fill_max_grey);
    c.candidates = envInt("VTM_ENTROPY_CANDIDATES", c.candidates);
    return c;
}

// ---- Mutual information, the peer: same grid, same pattern search, MI instead of NCC ----

struct MiParams {
    double angle = 0.0, logScale = 0.0, tx = 0.0, ty = 0.0, score = -1.0;
};

// Narrows [lo, hi] to the x where 0 <= slope x + offset <= limit may hold, widened by 2 px
// so that rounding cannot drop a column the exact test would keep. A slope of about zero
// leaves the range to the exact test.
void clipRow(double slope, double offset, double limit, std::int32_t& lo, std::int32_t& hi) {
    if (std::fabs(slope) < 1e-9) {
        return;
    }
    double a = -offset / slope, b = (limit - offset) / slope;
    if (a > b) {
        std::swap(a, b);
    }
    const auto column = [](double v) { return static_cast<std::int32_t>(std::clamp(v, -8.0, 1.0e6)); };
    lo = std::max(lo, column(std::floor(a)) - 2);
    hi = std::min(hi, column(std::ceil(b)) + 2);
}

class MutualInformation {
public:
    MutualInformation(const ImageView<const std::uint8_t>& a, const ImageView<const std::uint8_t>& b) {
        for (std::int32_t i = 0; i < 2; ++i) {
            const ImageView<const std::uint8_t>& src = i == 0 ? a : b;
            std::vector<std::vector<std::uint8_t>>& levels = i == 0 ? a_ : b_;
            std::vector<std::pair<std::int32_t, std::int32_t>>& sizes = i == 0 ? sizeA_ : sizeB_;
            levels.emplace_back(src.data(), src.data() + src.pixelCount());
            sizes.emplace_back(src.width(), src.height());
            for (std::int32_t l = 1; l < kLevels; ++l) {
                const auto [w, h] = sizes.back();
                std::vector<std::uint8_t> half(static_cast<std::size_t>(w / 2) * (h / 2));
                EXPECT_TRUE(halveImage(ImageView<const std::uint8_t>(levels.back().data(), w, h),
                                       ImageView<std::uint8_t>(half.data(), w / 2, h / 2)).isOk());
                levels.push_back(std::move(half));
                sizes.emplace_back(w / 2, h / 2);
            }
        }
    }

    // MI (bits) of the level's grey levels (32 bins) under p; -1 below 25 % overlap.
    double score(std::int32_t level, const MiParams& p) const {
        const auto [w1, h1] = sizeA_[static_cast<std::size_t>(level)];
        const auto [w2, h2] = sizeB_[static_cast<std::size_t>(level)];
        const std::vector<std::uint8_t>& e1 = a_[static_cast<std::size_t>(level)];
        const std::vector<std::uint8_t>& e2 = b_[static_cast<std::size_t>(level)];
        // The same level geometry as the module (full = k q + o).
        const double k = static_cast<double>(1 << level);
        const double o = 0.5 * (k - 1.0);
        const double s = std::exp(p.logScale);
        const double c = s * std::cos(p.angle);
        const double sn = s * std::sin(p.angle);
        const double c1x = 0.5 * (sizeA_[0].first - 1), c1y = 0.5 * (sizeA_[0].second - 1);
        const double c2x = 0.5 * (sizeB_[0].first - 1), c2y = 0.5 * (sizeB_[0].second - 1);
        const double gx = c2x + p.tx - (c * c1x - sn * c1y);
        const double gy = c2y + p.ty - (sn * c1x + c * c1y);
        const double vx = (c * o - sn * o + gx - o) / k;
        const double vy = (sn * o + c * o + gy - o) / k;
        std::vector<std::int32_t> joint(32 * 32, 0);
        std::int32_t n = 0;
        for (std::int32_t y = 0; y < h1; ++y) {
            // Only the columns whose sample can land in image 2 (the test below still decides).
            std::int32_t x_lo = 0, x_hi = w1 - 1;
            clipRow(c, vx - sn * y, w2 - 1, x_lo, x_hi);
            clipRow(sn, vy + c * y, h2 - 1, x_lo, x_hi);
            for (std::int32_t x = x_lo; x <= x_hi; ++x) {
                const double px = c * x - sn * y + vx;
                const double py = sn * x + c * y + vy;
                if (px < 0.0 || py < 0.0 || px > w2 - 1 || py > h2 - 1) {
                    continue;
                }
                const auto x0 = static_cast<std::int32_t>(px);
                const auto y0 = static_cast<std::int32_t>(py);
                const std::int32_t x1 = std::min(x0 + 1, w2 - 1);
                const std::int32_t y1 = std::min(y0 + 1, h2 - 1);
                const double ax = px - x0, ay = py - y0;
                auto at = [&](std::int32_t xx, std::int32_t yy) { return e2[static_cast<std::size_t>(yy * w2 + xx)]; };
                const double v = (1 - ay) * ((1 - ax) * at(x0, y0) + ax * at(x1, y0)) +
                                 ay * ((1 - ax) * at(x0, y1) + ax * at(x1, y1));
                const std::int32_t bin2 = std::min(31, static_cast<std::int32_t>(v + 0.5) >> 3);
                ++joint[static_cast<std::size_t>((e1[static_cast<std::size_t>(y * w1 + x)] >> 3) * 32 + bin2)];
                ++n;
            }
        }
        if (n < w1 * h1 / 4) {
            return -1.0;
        }
        double pa[32] = {}, pb[32] = {};
        for (std::int32_t i = 0; i < 32; ++i) {
            for (std::int32_t j = 0; j < 32; ++j) {
                pa[i] += joint[static_cast<std::size_t>(i * 32 + j)];
                pb[j] += joint[static_cast<std::size_t>(i * 32 + j)];
            }
        }
        double mi = 0.0;
        for (std::int32_t i = 0; i < 32; ++i) {
            for (std::int32_t j = 0; j < 32; ++j) {
                const double pij = joint[static_cast<std::size_t>(i * 32 + j)];
                if (pij > 0.0) {
                    mi += pij / n * std::log2(pij * n / (pa[i] * pb[j]));
                }
            }
        }
        return mi;
    }

    // The module's search with MI: the same grid (one coarse pixel of motion per step, the
    // same capacities), the 4 best separated coarse peaks, the same pattern search per level.
    MiParams search(const RegistrationRequest& r, const RegistrationConfig& cfg) const {
        const std::int32_t coarse = kLevels - 1;
        const auto [wc, hc] = sizeA_[static_cast<std::size_t>(coarse)];
        const double k = static_cast<double>(1 << coarse);
        const double step = 1.0 / (0.5 * std::max(wc, hc));
        auto count = [&](double lo, double hi, std::int32_t cap) {
            return hi > lo ? std::min(cap, static_cast<std::int32_t>(std::ceil((hi - lo) / step) + 1.0)) : 1;
        };
        auto value = [](double lo, double hi, std::int32_t i, std::int32_t n) {
            return n <= 1 ? 0.5 * (lo + hi) : lo + (hi - lo) * i / (n - 1);
        };
        const double lmin = std::log(r.scale_min), lmax = std::log(r.scale_max);
        const std::int32_t na = count(r.angle_min_rad, r.angle_max_rad, cfg.max_angle_steps);
        const std::int32_t ns = count(lmin, lmax, cfg.max_scale_steps);
        const std::int32_t margin = std::min((cfg.max_shift_steps - 1) / 2,
                                             static_cast<std::int32_t>(std::ceil(r.shift_range_px * std::sqrt(2.0) /
                                                                                 (r.scale_min * k))));
        std::vector<MiParams> best;
        for (std::int32_t si = 0; si < ns; ++si) {
            for (std::int32_t ai = 0; ai < na; ++ai) {
                MiParams p;
                p.angle = value(r.angle_min_rad, r.angle_max_rad, ai, na);
                p.logScale = value(lmin, lmax, si, ns);
                const double s = std::exp(p.logScale), c = s * std::cos(p.angle), sn = s * std::sin(p.angle);
                for (std::int32_t uy = -margin; uy <= margin; ++uy) {
                    for (std::int32_t ux = -margin; ux <= margin; ++ux) {
                        MiParams q = p;
                        q.tx = r.shift_x_px + k * (c * ux - sn * uy);
                        q.ty = r.shift_y_px + k * (sn * ux + c * uy);
                        q.score = score(coarse, q);
                        offer(best, q, 3.0 * k, cfg.candidates);
                    }
                }
            }
        }
        MiParams winner;
        for (MiParams& p : best) {
            double steps[4] = {};
            for (std::int32_t level = coarse; level >= 0; --level) {
                const auto [w, h] = sizeA_[static_cast<std::size_t>(level)];
                steps[0] = steps[1] = 1.0 / (0.5 * std::max(w, h));
                steps[2] = steps[3] = static_cast<double>(1 << level);
                p.score = score(level, p);
                for (std::int32_t round = 0; round < cfg.refine_rounds; ++round) {
                    MiParams top = p;
                    for (std::int32_t i = 0; i < 8; ++i) {
                        MiParams q = p;
                        double* f[4] = {&q.angle, &q.logScale, &q.tx, &q.ty};
                        *f[i / 2] += (i % 2 == 0 ? -1.0 : 1.0) * steps[i / 2];
                        q.score = score(level, q);
                        if (q.score > top.score) top = q;
                    }
                    if (top.score > p.score) {
                        p = top;
                    } else {
                        for (double& st : steps) st *= 0.5;
                    }
                }
            }
            if (p.score > winner.score) winner = p;
        }
        return winner;
    }

private:
    double corners(const MiParams& a, const MiParams& b) const {
        auto m = [&](const MiParams& p) {
            const double s = std::exp(p.logScale), c = s * std::cos(p.angle), sn = s * std::sin(p.angle);
            const double c1x = 0.5 * (sizeA_[0].first - 1), c1y = 0.5 * (sizeA_[0].second - 1);
            Mat23 g;
            g << c, -sn, p.tx - (c * c1x - sn * c1y), sn, c, p.ty - (sn * c1x + c * c1y);
            return g;
        };
        return test::cornerError(m(a), m(b), sizeA_[0].first, sizeA_[0].second);
    }
    void offer(std::vector<MiParams>& list, const MiParams& q, double separation, std::int32_t capacity) const {
        if (q.score <= -1.0) return;
        for (MiParams& p : list) {
            if (corners(p, q) <= separation) {
                if (q.score > p.score) p = q;
                return;
            }
        }
        if (static_cast<std::int32_t>(list.size()) < capacity) {
            list.push_back(q);
            return;
        }
        auto worst = std::min_element(list.begin(), list.end(),
                                      [](const MiParams& x, const MiParams& y) { return x.score < y.score; });
        if (q.score > worst->score) *worst = q;
    }

    std::vector<std::vector<std::uint8_t>> a_, b_;
    std::vector<std::pair<std::int32_t, std::int32_t>> sizeA_, sizeB_;
};

Mat23 matrixOf(double angle, double scale, double tx, double ty, std::int32_t w1, std::int32_t h1, std::int32_t w2,
               std::int32_t h2) {
    const double c = scale * std::cos(angle), s = scale * std::sin(angle);
    const double c1x = 0.5 * (w1 - 1), c1y = 0.5 * (h1 - 1), c2x = 0.5 * (w2 - 1), c2y = 0.5 * (h2 - 1);
    Mat23 g;
    g << c, -s, c2x + tx - (c * c1x - s * c1y), s, c, c2y + ty - (s * c1x + c * c1y);
    return g;
}

// ---- The pairs ------------------------------------------------------------------------

struct Pair {
    std::string name;
    std::vector<std::uint8_t> image1, image2;
    std::int32_t w1 = 0, h1 = 0, w2 = 0, h2 = 0;
    Mat23 truth;
    RegistrationRequest request;
};

bool readTruth(const std::string& path, Mat23& g) {
    std::ifstream f(path);
    for (std::int32_t i = 0; i < 6; ++i) {
        if (!(f >> g(i / 3, i % 3))) return false;
    }
    return true;
}

bool loadOpticalInfrared(std::int32_t n, Pair& p) {
    const std::string dir = dataRoot() + "optical-infrared/";
    const auto a = ground::loadGrey8(dir + "pair" + std::to_string(n) + "_1.jpg");
    const auto b = ground::loadGrey8(dir + "pair" + std::to_string(n) + "_2.jpg");
    if (!a.ok || !b.ok || !readTruth(dir + "gt_" + std::to_string(n) + ".txt", p.truth)) return false;
    p.name = "oi" + std::to_string(n);
    p.image1 = a.value.pixels;
    p.image2 = b.value.pixels;
    p.w1 = a.value.width;
    p.h1 = a.value.height;
    p.w2 = b.value.width;
    p.h2 = b.value.height;
    // The search: the data set's rotations lie in -90..0 deg about the centre at scale 1;
    // searched: -96..+6 deg, scale 0.9-1.1, shift +-8 px.
    p.request.angle_min_rad = -1.68;
    p.request.angle_max_rad = 0.1;
    p.request.scale_min = 0.9;
    p.request.scale_max = 1.1;
    p.request.shift_range_px = 8.0;
    return true;
}

bool loadOpticalMap(std::int32_t n, Pair& p) {
    const std::string dir = dataRoot() + "optical-map/";
    const auto a = ground::loadGrey8(dir + "pair" + std::to_string(n) + "_1.jpg");
    const auto b = ground::loadGrey8(dir + "pair" + std::to_string(n) + "_2.jpg");
    if (!a.ok || !b.ok || a.value.width != 400 || b.value.width != 400) return false;
    p.name = "om" + std::to_string(n);
    const std::int32_t offset = (400 - kMapCrop) / 2;
    p.image1.resize(static_cast<std::size_t>(kMapCrop) * kMapCrop);
    for (std::int32_t y = 0; y < kMapCrop; ++y) {
        for (std::int32_t x = 0; x < kMapCrop; ++x) {
            p.image1[static_cast<std::size_t>(y * kMapCrop + x)] =
                a.value.pixels[static_cast<std::size_t>((y + offset) * 400 + x + offset)];
        }
    }
    // The known similarity of this pair (seeded by its number).
    Random rng(1000U + static_cast<std::uint64_t>(n));
    auto uniform = [&rng](double lo, double hi) { return lo + (hi - lo) * rng.uniform01(); };
    const double angle = uniform(-0.5236, 0.5236);
    const double logScale = uniform(std::log(0.8), std::log(1.25));
    const double tx = uniform(-8.0, 8.0);
    const double ty = uniform(-8.0, 8.0);
    const double s = std::exp(logScale);
    // Image 2 (crop size): the map at G^-1(q), bilinear, borders clamped.
    p.image2.resize(p.image1.size());
    const double c1 = 0.5 * (kMapCrop - 1);
    const double cs = std::cos(angle) / s, sn = std::sin(angle) / s;
    for (std::int32_t y = 0; y < kMapCrop; ++y) {
        for (std::int32_t x = 0; x < kMapCrop; ++x) {
            const double dx = x - c1 - tx, dy = y - c1 - ty;
            const double px = std::clamp(cs * dx + sn * dy + c1 + offset, 0.0, 398.999);
            const double py = std::clamp(-sn * dx + cs * dy + c1 + offset, 0.0, 398.999);
            const auto x0 = static_cast<std::int32_t>(px), y0 = static_cast<std::int32_t>(py);
            const double ax = px - x0, ay = py - y0;
            auto at = [&](std::int32_t xx, std::int32_t yy) {
                return static_cast<double>(b.value.pixels[static_cast<std::size_t>(yy * 400 + xx)]);
            };
            const double v = (1 - ay) * ((1 - ax) * at(x0, y0) + ax * at(x0 + 1, y0)) +
                             ay * ((1 - ax) * at(x0, y0 + 1) + ax * at(x0 + 1, y0 + 1));
            p.image2[static_cast<std::size_t>(y * kMapCrop + x)] = static_cast<std::uint8_t>(std::lround(v));
        }
    }
    p.w1 = p.h1 = p.w2 = p.h2 = kMapCrop;
    p.truth = matrixOf(angle, s, tx, ty, kMapCrop, kMapCrop, kMapCrop, kMapCrop);
    p.request.angle_min_rad = -0.55;
    p.request.angle_max_rad = 0.55;
    p.request.scale_min = 0.78;
    p.request.scale_max = 1.28;
    p.request.shift_range_px = 10.0;
    return true;
}

// ---- The evaluation -------------------------------------------------------------------

struct Tally {
    std::int32_t pairs = 0, correct = 0, accepted = 0, acceptedCorrect = 0;
    double seconds = 0.0;
    std::vector<double> errors;  // of the correct pairs
};

struct Methods {
    Tally entropy, intensity, mi;
};

void runPair(const Pair& p, Methods& m, EntropyRegistration& ent, EntropyRegistration& inten) {
    const ImageView<const std::uint8_t> i1(p.image1.data(), p.w1, p.h1);
    const ImageView<const std::uint8_t> i2(p.image2.data(), p.w2, p.h2);
    auto tally = [&](Tally& t, const Mat23& g, bool accepted, double seconds) {
        const double e = test::cornerError(g, p.truth, p.w1, p.h1);
        ++t.pairs;
        t.seconds += seconds;
        t.accepted += accepted ? 1 : 0;
        if (e <= kCorrectPx) {
            ++t.correct;
            t.acceptedCorrect += accepted ? 1 : 0;
            t.errors.push_back(e);
        }
        return e;
    };
    using Clock = std::chrono::steady_clock;
    auto t0 = Clock::now();
    Registration re;
    const Status se = ent.registerImages(i1, i2, p.request, re);
    const double ee = tally(m.entropy, re.image2_from_image1, se.isOk(),
                            std::chrono::duration<double>(Clock::now() - t0).count());
    if (std::getenv("VTM_SRIF_ENTROPY_ONLY") != nullptr) {  // tuning runs: the module alone
        std::printf("%-6s entropy %7.2f px ncc %.3f 2nd %6.3f %s\n", p.name.c_str(), ee, re.ncc, re.second_ncc,
                    statusCodeName(se.code()));
        return;
    }
    t0 = Clock::now();
    Registration ri;
    const Status si = inten.registerImages(i1, i2, p.request, ri);
    const double ei = tally(m.intensity, ri.image2_from_image1, si.isOk(),
                            std::chrono::duration<double>(Clock::now() - t0).count());
    t0 = Clock::now();
    const MutualInformation mi(i1, i2);
    const MiParams best = mi.search(p.request, ent.config());
    const Mat23 gm = matrixOf(best.angle, std::exp(best.logScale), best.tx, best.ty, p.w1, p.h1, p.w2, p.h2);
    const double em = tally(m.mi, gm, true, std::chrono::duration<double>(Clock::now() - t0).count());
    std::printf("%-6s entropy %7.2f px ncc %.3f 2nd %6.3f %-11s | intensity %7.2f px ncc %.3f %-11s | MI %7.2f px %.3f bit\n",
                p.name.c_str(), ee, re.ncc, re.second_ncc, statusCodeName(se.code()), ei, ri.ncc,
                statusCodeName(si.code()), em, best.score);
}

void report(const char* set, const Methods& m) {
    auto line = [&](const char* name, const Tally& t) {
        std::vector<double> e = t.errors;
        std::sort(e.begin(), e.end());
        const double median = e.empty() ? 0.0 : e[e.size() / 2];
        std::printf("%s %-10s correct %3d/%3d (%5.1f %%), accepted %3d (of them correct %3d), median error of the "
                    "correct %.2f px, %.2f s per pair\n",
                    set, name, t.correct, t.pairs, 100.0 * t.correct / std::max(1, t.pairs), t.accepted,
                    t.acceptedCorrect, median, t.seconds / std::max(1, t.pairs));
    };
    line("entropy", m.entropy);
    line("intensity", m.intensity);
    line("MI", m.mi);
}

class SrifEvaluation : public ::testing::Test {
protected:
    void SetUp() override {
        VTM_REQUIRE_TEST_DATA(dataRoot() + "README.md");
        useEqualisation(RegistrationConfig{}.equalise_radius_px);
        const RegistrationConfig ci = moduleConfig(Representation::kIntensity, 0);
        poolI_.resize(EntropyRegistration::workspaceBytes(ci));
        arenaI_ = std::make_unique<Arena>(poolI_.data(), poolI_.size());
        ASSERT_TRUE(intensity_.init(ci, *arenaI_).isOk());
    }
    // The module's entropy images with equalise_radius_px = radius (0: whole image).
    void useEqualisation(std::int32_t radius) {
        const RegistrationConfig ce = moduleConfig(Representation::kEntropy, radius);
        poolE_.assign(EntropyRegistration::workspaceBytes(ce), std::byte{0});
        arenaE_ = std::make_unique<Arena>(poolE_.data(), poolE_.size());
        ASSERT_TRUE(entropy_.init(ce, *arenaE_).isOk());
    }
    std::vector<std::byte> poolE_, poolI_;
    std::unique_ptr<Arena> arenaE_, arenaI_;
    EntropyRegistration entropy_, intensity_;
};

// The target, on every pair of the full run and on the CI subset (docs/entropy.md
// has the measured levels).
constexpr double kTarget = 0.90;              // issue 24: optical-infrared pairs within 3 px
constexpr std::int32_t kInfraredFirstCi = 2;  // every 10th even pair: 20 pairs, none of them
constexpr std::int32_t kInfraredStepCi = 10;  // among the odd pairs the settings were chosen on
constexpr std::int32_t kMapStepCi = 80;       // 3 pairs

TEST_F(SrifEvaluation, OpticalInfrared) {
    const std::int32_t first = fullRun() ? 1 : envInt("VTM_SRIF_FIRST", kInfraredFirstCi);
    const std::int32_t step = fullRun() ? 1 : envInt("VTM_SRIF_STEP", kInfraredStepCi);
    Methods m;
    for (std::int32_t n = first; n <= 200; n += step) {
        Pair p;
        ASSERT_TRUE(loadOpticalInfrared(n, p)) << n;
        runPair(p, m, entropy_, intensity_);
    }
    report("optical-infrared", m);
    const double rate = static_cast<double>(m.entropy.correct) / m.entropy.pairs;
    EXPECT_GE(rate, kTarget) << "the issue's target: >= 90 % of the pairs within 3 px";
    // The point of the entropy images: across sensors they beat intensity correlation.
    EXPECT_GT(m.entropy.correct, m.intensity.correct);
    // Of the registrations the module accepts, nearly all are right.
    EXPECT_GE(m.entropy.acceptedCorrect, (m.entropy.accepted * 8 + 9) / 10);
}

TEST_F(SrifEvaluation, OpticalMap) {
    // The rendered maps are flat colour fields: a local rank turns their compression noise
    // into texture, so the maps are equalised over the whole image (docs/entropy.md).
    useEqualisation(0);
    const std::int32_t step = fullRun() ? 1 : envInt("VTM_SRIF_STEP", kMapStepCi);
    Methods m;
    for (std::int32_t n = 1; n <= 200; n += step) {
        Pair p;
        ASSERT_TRUE(loadOpticalMap(n, p)) << n;
        runPair(p, m, entropy_, intensity_);
    }
    report("optical-map", m);
    // Measured (docs/entropy.md, 2026-12-05): all 200 pairs 34 correct (17 %), MI 18, intensity
    // NCC 0. The issue sets no target here; the test holds the ranking against the peers.
    EXPECT_GT(m.entropy.correct, m.intensity.correct);
    EXPECT_GE(m.entropy.correct, m.mi.correct);
}

}  // namespace
}  // namespace vtm::entropy
