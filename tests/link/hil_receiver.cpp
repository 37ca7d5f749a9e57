// The flight-side end of a HIL run (tools/scripts/hil_run.sh): connects to `vtm-sim serve`,
// receives frames through LinkCamera/LinkOdometry (static storage, as on board) and
// checks each one against an in-process render of the same scenario frame: pixels and
// pose must be bit-identical. Built for every target; under qemu-user it talks to the
// native simulator over loopback.
//
//   vtm_hil_receiver --unix PATH | --tcp IPV4:PORT  --scenario FILE  [--frames N]
//                    [--timeout-ms MS] [--no-check] [--warmup N] [--expect-faults]
// Exit 0 when N frames arrived (N = --frames, else every frame until end of stream) and
// every check passed; 1 otherwise. --expect-faults (the simulator runs with --fault):
// refused frames are skipped, faults must be counted, delivered frames must be exact. --no-check only receives (throughput measurement);
// the rate printed counts the frames after the first --warmup N (default 1).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "hal/link/link_session.hpp"
#include "hal/link/socket_stream.hpp"
#include "hal/posix/monotonic_clock.hpp"
#include "sim/render.hpp"
#include "sim/scenario.hpp"
#include "sim/terrain.hpp"

namespace {

using namespace vtm;
namespace link = vtm::hal::link;

struct Args {
    std::string unix_path, tcp, scenario;
    int frames = -1;
    std::uint32_t timeout_ms = 20000U;
    bool check = true;
    int warmup = 1;  // frames received before the rate is timed
    bool expect_faults = false;  // the simulator injects faults: carry on after a refused frame
};

bool parseArgs(int argc, char** argv, Args& a) {
    for (int i = 1; i < argc; ++i) {
        const std::string k = argv[i];
        const bool has_value = i + 1 < argc;
        if (k == "--no-check") {
            a.check = false;
        } else if (k == "--expect-faults") {
            a.expect_faults = true;
        } else if (k == "--unix" && has_value) {
            a.unix_path = argv[++i];
        } else if (k == "--tcp" && has_value) {
            a.tcp = argv[++i];
        } else if (k == "--scenario" && has_value) {
            a.scenario = argv[++i];
        } else if (k == "--frames" && has_value) {
            a.frames = std::atoi(argv[++i]);
        } else if (k == "--warmup" && has_value) {
            a.warmup = std::max(1, std::atoi(argv[++i]));
        } else if (k == "--timeout-ms" && has_value) {
            a.timeout_ms = static_cast<std::uint32_t>(std::atoi(argv[++i]));
        } else {
            return false;
        }
    }
    return (a.unix_path.empty() != a.tcp.empty()) && (!a.check || !a.scenario.empty());
}

// The in-process reference: the scenario rendered here, the way the simulator does.
struct Reference {
    sim::Scenario scenario{};
    std::vector<std::byte> pool;
    std::unique_ptr<Arena> arena;
    sim::Terrain terrain{};
    std::unique_ptr<sim::ScenarioFrames> frames = std::make_unique<sim::ScenarioFrames>();

    bool load(const std::string& path) {
        std::ifstream in(path, std::ios::binary);
        std::stringstream text;
        text << in.rdbuf();
        const std::string s = text.str();
        Status st = sim::parseScenario(s, scenario);
        if (st.isOk()) {
            pool.resize(sim::scenarioTerrainBytes(scenario) + 64U);
            arena = std::make_unique<Arena>(pool.data(), pool.size());
            st = sim::buildScenarioTerrain(scenario, *arena, terrain);
        }
        if (st.isOk()) {
            st = sim::buildScenarioFrames(scenario, terrain, *frames);
        }
        if (!st.isOk()) {
            std::fprintf(stderr, "hil_receiver: %s: %s (detail %lld)\n", path.c_str(), st.reason(),
                         static_cast<long long>(st.detail()));
        }
        return st.isOk();
    }
    // The scenario frame the simulator sent as `info`. vtm-sim serve numbers frames
    // sequence + 1000 * camera_id, plus 100000 per repetition when --frames exceeds the
    // scenario (its timestamps then move on too).
    const sim::ScenarioFrame* find(const hal::FrameInfo& info) const {
        for (std::int32_t i = 0; i < frames->count; ++i) {
            const sim::ScenarioFrame& f = frames->frames[i];
            if (f.camera_id == info.camera_id && f.sequence + 1000U * f.camera_id == info.sequence % 100000U) {
                return &f;
            }
        }
        return nullptr;
    }
    bool render(const sim::ScenarioFrame& f, std::vector<std::uint8_t>& px) const {
        const sim::FrameRequest request = sim::scenarioFrameRequest(scenario, terrain, f);
        px.assign(static_cast<std::size_t>(f.model.width_px) * f.model.height_px, 0U);
        sim::FrameOutput out;
        out.image8 = ImageView<std::uint8_t>(px.data(), f.model.width_px, f.model.height_px);
        return sim::renderFrame(request, out, nullptr).isOk();
    }
};

// Flight-side storage: static, as on board.
link::SocketStream g_stream;
link::LinkSession g_session;
link::LinkCamera g_camera{g_session};
link::LinkOdometry g_odometry{g_session};
hal::MonotonicClock g_clock;

bool connect(const Args& a) {
    Status s;
    if (!a.unix_path.empty()) {
        s = g_stream.connectUnix(a.unix_path.c_str(), a.timeout_ms);
    } else {
        const std::size_t colon = a.tcp.rfind(':');
        const std::string host = a.tcp.substr(0, colon);
        const int port = colon == std::string::npos ? 0 : std::atoi(a.tcp.c_str() + colon + 1);
        s = g_stream.connectTcp(host.c_str(), static_cast<std::uint16_t>(port), a.timeout_ms);
    }
    if (!s.isOk()) {
        std::fprintf(stderr, "hil_receiver: connect: %s (%lld)\n", s.reason(), static_cast<long long>(s.detail()));
    }
    return s.isOk();
}

// Checks one received frame and pose against the reference; prints what differs.
bool checkFrame(const Reference& ref, const hal::FrameInfo& info, const std::vector<std::uint8_t>& px,
                bool expect_faults) {
    const sim::ScenarioFrame* f = ref.find(info);
    std::vector<std::uint8_t> want;
    if (f == nullptr || !ref.render(*f, want)) {
        std::fprintf(stderr, "hil_receiver: frame %u: no such scenario frame\n", info.sequence);
        return false;
    }
    std::size_t differ = 0U;
    for (std::size_t i = 0U; i < px.size(); ++i) {
        differ += (px[i] != want[i]) ? 1U : 0U;
    }
    hal::PoseEstimate pose;
    const Status ps = g_odometry.poseAt(info.timestamp_ns, pose);
    // Under injected faults the frame's pose message may be the one lost, or poseAt()
    // may meet a damaged message while reading ahead for it; a pose delivered must be exact.
    const bool pose_lost = expect_faults && !ps.isOk();
    const bool pose_same = ps.isOk() &&
                           std::memcmp(pose.position_m, f->odometry_pose.position_m, sizeof(pose.position_m)) == 0 &&
                           std::memcmp(pose.attitude_wxyz, f->odometry_pose.attitude_wxyz, sizeof(pose.attitude_wxyz)) == 0 &&
                           std::memcmp(pose.covariance, f->odometry_pose.covariance, sizeof(pose.covariance)) == 0;
    int max_dn = 0;
    for (std::size_t i = 0U; i < px.size(); ++i) {
        max_dn = std::max(max_dn, std::abs(static_cast<int>(px[i]) - static_cast<int>(want[i])));
    }
    double max_dx_m = 0.0;
    for (int k = 0; k < 3; ++k) {
        max_dx_m = std::max(max_dx_m, std::fabs(pose.position_m[k] - f->odometry_pose.position_m[k]));
    }
    std::printf("frame camera %u seq %u: %zu of %zu pixels differ (max %d DN), pose %s (max %.3g m, %s)\n", info.camera_id,
                info.sequence, differ, px.size(), max_dn, pose_same ? "identical" : (pose_lost ? "lost" : "DIFFERS"), max_dx_m, statusCodeName(ps.code()));
    return differ == 0U && (pose_same || pose_lost);
}

}  // namespace

int main(int argc, char** argv) {
    Args a;
    if (!parseArgs(argc, argv, a)) {
        std::fprintf(stderr, "usage: %s --unix PATH | --tcp IPV4:PORT --scenario FILE [--frames N] [--timeout-ms MS] [--no-check]\n", argv[0]);
        return 2;
    }
    Reference ref;
    if (a.check && !ref.load(a.scenario)) {
        return 1;
    }
    link::LinkSession::Config config;
    config.timeout_ms = a.timeout_ms;
    config.max_interpolation_gap_ns = 1U;  // the check wants the sent pose itself, never an interpolation
    if (!connect(a) || !g_session.init(config, g_stream, g_clock).isOk()) {
        return 1;
    }
    hal::CameraDescription d;
    const Status ds = g_camera.describe(d);
    if (!ds.isOk() || d.bit_depth > 8U) {
        std::fprintf(stderr, "hil_receiver: describe: %s (8-bit cameras only here)\n", ds.reason());
        return 1;
    }
    std::vector<std::uint8_t> px(static_cast<std::size_t>(d.width_px) * static_cast<std::size_t>(d.height_px));
    const ImageView<std::uint8_t> out(px.data(), d.width_px, d.height_px);
    int received = 0;
    bool all_ok = true;
    // Timed from the first frame on, so that the simulator's start-up (terrain build,
    // first render) does not count: the rate is the link's (when frames come from cache).
    auto t0 = std::chrono::steady_clock::now();
    while (a.frames < 0 || received < a.frames) {  // bound: --frames, or end of stream
        hal::FrameInfo info;
        const Status s = g_camera.capture(out, info);
        if (s.code() == StatusCode::kNoData && a.frames < 0) {
            break;
        }
        if (!s.isOk()) {
            std::fprintf(stderr, "hil_receiver: capture %d: %s (%s, %lld)\n", received, s.reason(),
                         statusCodeName(s.code()), static_cast<long long>(s.detail()));
            const bool link_fault = s.code() == StatusCode::kCorruptData || s.code() == StatusCode::kOutOfOrder ||
                                    s.code() == StatusCode::kUnsupported || s.code() == StatusCode::kSizeMismatch;
            if (a.expect_faults && link_fault) {
                continue;  // bound: every fault consumed input; the stream ends
            }
            // The end-of-stream message itself may be the one damaged.
            if (a.expect_faults && (s.code() == StatusCode::kNoData || s.code() == StatusCode::kIoError)) {
                break;
            }
            return 1;
        }
        ++received;
        if (received == a.warmup) {
            t0 = std::chrono::steady_clock::now();
        }
        all_ok = (!a.check || checkFrame(ref, info, px, a.expect_faults)) && all_ok;
    }
    const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const link::LinkCounters& c = g_session.counters();
    std::printf("hil_receiver: %d frames of %dx%d, frames %d..%d in %.3f s (%.1f frames/s), %llu messages, %llu faults\n",
                received, d.width_px, d.height_px, a.warmup + 1, received, sec, (received - a.warmup) / sec, static_cast<unsigned long long>(c.messages_ok),
                static_cast<unsigned long long>(c.totalFaults()));
    for (std::size_t f = 0U; f < link::kLinkFaultCount; ++f) {
        const auto fault = static_cast<link::LinkFault>(f);
        if (c.count(fault) > 0U) {
            std::printf("  fault %-16s %llu\n", link::linkFaultName(fault), static_cast<unsigned long long>(c.count(fault)));
        }
    }
    // --expect-faults: the faults must have been seen, and every frame that was
    // delivered must still be exact.
    const bool faults_as_expected = a.expect_faults ? c.totalFaults() > 0U : c.totalFaults() == 0U;
    return (all_ok && received > 0 && faults_as_expected) ? 0 : 1;
}
