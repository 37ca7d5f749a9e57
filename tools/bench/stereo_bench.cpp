// vtm_bench_stereo: dense-stereo throughput, VTM against its OpenCV peers, in one binary
// on one pair (Middlebury teddy, 450x375, grey, numDisparities 64), one thread.
//
//   MlStereo/teddy/default    vtm::stereo::MlStereo::compute, default Config (d 0..63;
//                             disparity, sigma and reason outputs)
//   MlStereo/teddy/window7    the same with window = 7
//   MlStereo/teddy/conservative  Config::conservative() (left-right check, uniqueness on,
//                             as the OpenCV peers have)
//   OpenCvStereoBM/teddy      cv::StereoBM, the README's peer parameters (tests/peer)
//   OpenCvStereoSGBM3Way/teddy  cv::StereoSGBM MODE_SGBM_3WAY, README parameters
//
// Reports time per call (CPU time: one thread, and the rate is not skewed by other load
// on a shared machine) and the counter "Mpx*disp/s" = width * height * 64 / time
// / 1e6. It reports; it never fails on time (docs/benchmarks.md). Data directory:
// $VTM_MIDDLEBURY_DIR, else the build-time default.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "vtm/peer/peer_stereo.hpp"
#if VTM_BENCH_HAVE_ML_STEREO
#include "vtm/core/arena.hpp"
#include "vtm/core/image.hpp"
#include "vtm/stereo/ml_stereo.hpp"
#endif

namespace {

constexpr int kDisparities = 64;

struct Pair {
    cv::Mat left;
    cv::Mat right;
};

const Pair& teddy() {
    static const Pair pair = [] {
        const char* env = std::getenv("VTM_MIDDLEBURY_DIR");
        const std::string dir = std::string(env != nullptr ? env : VTM_MIDDLEBURY_DEFAULT_DIR) + "/teddy/";
        Pair p{cv::imread(dir + "im2.png", cv::IMREAD_GRAYSCALE), cv::imread(dir + "im6.png", cv::IMREAD_GRAYSCALE)};
        if (p.left.empty() || p.right.empty()) {
            throw std::runtime_error("vtm_bench_stereo: cannot read " + dir + "im2.png / im6.png");
        }
        return p;
    }();
    return pair;
}

void setRate(benchmark::State& state, const cv::Mat& image) {
    const double perCall = static_cast<double>(image.cols) * image.rows * kDisparities / 1e6;
    state.counters["Mpx*disp/s"] =
        benchmark::Counter(perCall * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
    state.SetLabel(std::to_string(image.cols) + "x" + std::to_string(image.rows) + " d0.." +
                   std::to_string(kDisparities - 1));
}

void validFraction(benchmark::State& state, const cv::Mat& disparity32f) {
    const cv::Mat finite = disparity32f < std::numeric_limits<float>::infinity();
    state.counters["valid_fraction"] =
        static_cast<double>(cv::countNonZero(finite)) / static_cast<double>(disparity32f.total());
}

// One OpenCV peer (StereoBM or StereoSGBM: both are cv::StereoMatcher), one thread.
void OpenCvPeer(benchmark::State& state, cv::Ptr<cv::StereoMatcher> (*make)(int)) {
    const Pair& p = teddy();
    cv::setNumThreads(1);
    const cv::Ptr<cv::StereoMatcher> matcher = make(kDisparities);
    cv::Mat d16;
    for (auto _ : state) {
        matcher->compute(p.left, p.right, d16);
        benchmark::DoNotOptimize(d16.data);
    }
    setRate(state, p.left);
    validFraction(state, vtm::peer::fixedPointToFloat(d16));
}

cv::Ptr<cv::StereoMatcher> makeBm(int nd) { return vtm::peer::makeStereoBm(nd); }
cv::Ptr<cv::StereoMatcher> makeSgbm(int nd) { return vtm::peer::makeStereoSgbm3Way(nd); }

#if VTM_BENCH_HAVE_ML_STEREO
void MlStereo(benchmark::State& state, const vtm::stereo::Config& config) {
    const Pair& p = teddy();
    if (config.d_max - config.d_min + 1 != kDisparities) {
        state.SkipWithError("default Config no longer searches 64 disparities");
        return;
    }
    std::vector<std::byte> pool(vtm::stereo::MlStereo::workspaceBytes(config));
    vtm::Arena arena(pool.data(), pool.size());
    static vtm::stereo::MlStereo stereo;  // large object: not on the stack
    if (!stereo.init(config, arena).isOk()) {
        state.SkipWithError("MlStereo::init failed");
        return;
    }
    arena.freeze();
    const int w = p.left.cols, h = p.left.rows;
    std::vector<std::int16_t> disparity(static_cast<std::size_t>(w) * h);
    std::vector<float> sigma(disparity.size());
    std::vector<std::uint8_t> reason(disparity.size());
    vtm::stereo::DisparityOutput out;
    out.disparity_px16 = vtm::ImageView<std::int16_t>(disparity.data(), w, h);
    out.sigma_px = vtm::ImageView<float>(sigma.data(), w, h);
    out.reason = vtm::ImageView<std::uint8_t>(reason.data(), w, h);
    const vtm::ImageView<const std::uint8_t> left(p.left.data, w, h, static_cast<std::int32_t>(p.left.step));
    const vtm::ImageView<const std::uint8_t> right(p.right.data, w, h, static_cast<std::int32_t>(p.right.step));
    vtm::stereo::StereoStats stats;
    for (auto _ : state) {
        if (!stereo.compute(left, right, out, &stats).isOk()) {
            state.SkipWithError("MlStereo::compute failed");
            return;
        }
        benchmark::DoNotOptimize(disparity.data());
    }
    setRate(state, p.left);
    state.counters["valid_fraction"] = static_cast<double>(stats.valid_pixels) / static_cast<double>(w * h);
}
vtm::stereo::Config window7() {
    vtm::stereo::Config c;
    c.window = 7;
    return c;
}
BENCHMARK_CAPTURE(MlStereo, default, vtm::stereo::Config{})->Name("MlStereo/teddy/default")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(MlStereo, window7, window7())->Name("MlStereo/teddy/window7")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(MlStereo, conservative, vtm::stereo::Config::conservative())
    ->Name("MlStereo/teddy/conservative")
    ->Unit(benchmark::kMillisecond);
#endif

BENCHMARK_CAPTURE(OpenCvPeer, bm, &makeBm)->Name("OpenCvStereoBM/teddy")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(OpenCvPeer, sgbm, &makeSgbm)->Name("OpenCvStereoSGBM3Way/teddy")->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
