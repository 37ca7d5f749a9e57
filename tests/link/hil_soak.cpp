// The HIL soak (tools/scripts/hil_soak.sh, docs/hal-link.md "Soak"): the rover's
// WideBaselineMapper answers N consecutive requests whose frames and poses come over the
// HIL link from `vtm-sim serve --soak SEED` (random drops, truncations, corrupt bytes,
// replays, garbage, stalls, hangs and disconnects). Flight storage is static, as on board;
// the request loop runs on a thread whose stack is painted, under the no-heap guard.
// After the N requests the link is drained to the simulator's end of stream, so that every
// frame sent is accounted for. The report (--report) lists the frames delivered, every
// request's outcome and the link counters; hil_soak.sh checks them against the
// simulator's fault log.
//
//   vtm_hil_soak --unix PATH | --tcp IPV4:PORT --scenario FILE --requests N
//                [--timeout-ms MS] [--report FILE]
// Exit 0 when every request was answered with a product or a named Status, nothing
// touched the heap, and the stack and memory high-water marks did not grow in the second
// half of the run; 1 otherwise (each failure printed); 2 on a usage error.
#include <fcntl.h>
#include <pthread.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "hal/event_log.hpp"
#include "hal/link/link_session.hpp"
#include "hal/link/socket_stream.hpp"
#include "hal/posix/monotonic_clock.hpp"
#include "no_heap_guard.hpp"
#include "sim/scenario.hpp"
#include "sim/terrain.hpp"
#include "vtm/app/wide_baseline_mapper.hpp"

namespace {

using namespace vtm;
namespace link = vtm::hal::link;

struct Args {
    std::string unix_path, tcp, scenario, report;
    int requests = 0;
    std::uint32_t timeout_ms = 1000U;
};

bool parseArgs(int argc, char** argv, Args& a) {
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string k = argv[i];
        const char* v = argv[i + 1];
        if (k == "--unix") {
            a.unix_path = v;
        } else if (k == "--tcp") {
            a.tcp = v;
        } else if (k == "--scenario") {
            a.scenario = v;
        } else if (k == "--report") {
            a.report = v;
        } else if (k == "--requests") {
            a.requests = std::atoi(v);
        } else if (k == "--timeout-ms") {
            a.timeout_ms = static_cast<std::uint32_t>(std::atoi(v));
        } else {
            return false;
        }
    }
    return argc % 2 == 1 && (a.unix_path.empty() != a.tcp.empty()) && !a.scenario.empty() && a.requests > 0;
}

// hal::Camera that passes every call to the link camera and notes each frame delivered.
class RecordingCamera final : public hal::Camera {
public:
    static constexpr std::size_t kCapacity = 65536U;
    explicit RecordingCamera(hal::Camera& inner) noexcept : inner_(&inner) {}
    [[nodiscard]] Status describe(hal::CameraDescription& out) const noexcept override { return inner_->describe(out); }
    [[nodiscard]] Status capture(const ImageView<std::uint8_t>& out, hal::FrameInfo& info) noexcept override {
        return note(inner_->capture(out, info), info);
    }
    [[nodiscard]] Status capture16(const ImageView<std::uint16_t>& out, hal::FrameInfo& info) noexcept override {
        return note(inner_->capture16(out, info), info);
    }
    std::uint32_t delivered[kCapacity] = {};
    std::size_t count = 0U;

private:
    Status note(const Status& s, const hal::FrameInfo& info) noexcept {
        if (s.isOk() && count < kCapacity) {
            delivered[count++] = info.sequence;
        }
        return s;
    }
    hal::Camera* inner_;
};

// Flight-side storage: static, as on board.
link::SocketStream g_stream;
link::LinkSession g_session;
link::LinkCamera g_link_camera{g_session};
RecordingCamera g_camera{g_link_camera};
link::LinkOdometry g_odometry{g_session};
hal::MonotonicClock g_clock;
hal::EventLog g_events;
app::WideBaselineMapper g_mapper;

// The request loop's stack: painted before the thread starts; the unpainted depth is
// the high-water mark.
constexpr std::size_t kStackBytes = 4U << 20U;
constexpr unsigned char kPaint = 0xA5U;
alignas(64) unsigned char g_stack[kStackBytes];

std::size_t stackHighWater() {
    std::size_t untouched = 0U;
    while (untouched < kStackBytes && g_stack[untouched] == kPaint) {  // bound: kStackBytes
        ++untouched;
    }
    return kStackBytes - untouched;
}

// VmHWM of /proc/self/status in KiB (read without the heap), -1 where there is none.
long long memoryHighWaterKiB() {
    static char text[8192];
    const int fd = ::open("/proc/self/status", O_RDONLY);
    if (fd < 0) {
        return -1;
    }
    const ssize_t n = ::read(fd, text, sizeof(text) - 1U);
    ::close(fd);
    text[n > 0 ? n : 0] = '\0';
    const char* p = std::strstr(text, "VmHWM:");
    return p == nullptr ? -1 : std::strtoll(p + 6, nullptr, 10);
}

Status connectLink(const Args& a) {
    if (!a.unix_path.empty()) {
        return g_stream.connectUnix(a.unix_path.c_str(), 10000U);
    }
    const std::size_t colon = a.tcp.rfind(':');
    const std::string host = a.tcp.substr(0, colon);
    const int port = colon == std::string::npos ? 0 : std::atoi(a.tcp.c_str() + colon + 1);
    return g_stream.connectTcp(host.c_str(), static_cast<std::uint16_t>(port), 10000U);
}

// What the run found; filled by the loop thread, read by main after it ends.
struct Outcome {
    static constexpr int kStages = 16;
    static constexpr int kCodes = 16;
    long long table[kStages][kCodes] = {};  // refusals by the stage that ended the request and its code
    const char* first_reason[kStages][kCodes] = {};
    long long requests = 0, products = 0, refused = 0, unnamed = 0, reconnect_failures = 0;
    long long drained = 0;
    bool ended_early = false;
    std::uint64_t heap_calls = 0U;
    std::size_t stack_half = 0U, stack_end = 0U;
    long long hwm_half_kib = 0, hwm_end_kib = 0;
};

const Args* g_args = nullptr;
Outcome g_out;

// After a link failure (the connection closed or broke) the flight side connects again.
void reconnectIfLost(const Status& s) {
    if (s.code() != StatusCode::kIoError) {
        return;
    }
    if (!connectLink(*g_args).isOk() || !g_session.reconnect(g_stream).isOk()) {
        ++g_out.reconnect_failures;
    }
}

void noteRequest(const Status& s) {
    ++g_out.requests;
    if (s.isOk()) {
        g_out.products += g_mapper.products() != nullptr ? 1 : 0;
        g_out.unnamed += g_mapper.products() != nullptr ? 0 : 1;  // ok without a product
        return;
    }
    ++g_out.refused;
    const app::StageRecord* failed = g_mapper.stages().failed();
    const int stage = failed == nullptr ? 0 : static_cast<int>(failed->stage);
    const int code = static_cast<int>(s.code());
    const bool named = failed != nullptr && s.reason() != nullptr && s.reason()[0] != '\0' && stage < Outcome::kStages &&
                       code < Outcome::kCodes && g_mapper.products() == nullptr;
    if (!named) {
        ++g_out.unnamed;
        return;
    }
    if (g_out.table[stage][code]++ == 0) {
        g_out.first_reason[stage][code] = s.reason();
    }
}

void* requestLoop(void*) {
    const vtm::test::NoHeapScope guard;
    const int n = g_args->requests;
    for (int r = 0; r < n; ++r) {  // bound: --requests
        if (g_session.endOfStream()) {
            g_out.ended_early = true;
            break;
        }
        const Status s = g_mapper.map();
        noteRequest(s);
        reconnectIfLost(s);
        if (r + 1 == (n + 1) / 2) {
            // The /proc read first: its own stack is then inside both marks.
            g_out.hwm_half_kib = memoryHighWaterKiB();
            g_out.stack_half = stackHighWater();
        }
    }
    g_out.hwm_end_kib = memoryHighWaterKiB();
    g_out.stack_end = stackHighWater();
    g_out.heap_calls = guard.heapCalls();
    // Drain to the end of stream: every frame sent is delivered or counted as a fault.
    static std::uint8_t px[2048U * 2048U];
    hal::CameraDescription d;
    if (g_camera.describe(d).isOk() && static_cast<long long>(d.width_px) * d.height_px <= 2048LL * 2048LL) {
        const ImageView<std::uint8_t> out(px, d.width_px, d.height_px);
        for (int k = 0; k < 8 * n + 64 && !g_session.endOfStream(); ++k) {  // bound: 8 captures per request
            hal::FrameInfo info;
            const Status s = g_camera.capture(out, info);
            g_out.drained += s.isOk() ? 1 : 0;
            reconnectIfLost(s);
        }
    }
    return nullptr;
}

app::WideBaselineMapperConfig configFor(const sim::ScenarioFrame& f) {
    app::WideBaselineMapperConfig c;
    c.frame_width = f.model.width_px;
    c.frame_height = f.model.height_px;
    c.refine.match_margin_px = 75.0 * static_cast<double>(std::max(c.frame_width, c.frame_height)) / 1024.0;
    c.speckle.max_region_px = static_cast<std::int32_t>(100LL * c.frame_width * c.frame_height / (1024LL * 1024LL));
    const RigidPose vehicle_from_camera = sim::vehicleFromCamera(f);
    c.mount.R_vehicle_from_camera = vehicle_from_camera.R;
    c.mount.position_vehicle_m = vehicle_from_camera.t_m;
    return c;
}

bool loadConfig(const std::string& path, app::WideBaselineMapperConfig& config) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    sim::Scenario scenario;
    Status s = sim::parseScenario(text.str(), scenario);
    std::vector<std::byte> pool;
    std::unique_ptr<Arena> arena;
    sim::Terrain terrain{};
    auto frames = std::make_unique<sim::ScenarioFrames>();
    if (s.isOk()) {
        pool.resize(sim::scenarioTerrainBytes(scenario) + 64U);
        arena = std::make_unique<Arena>(pool.data(), pool.size());
        s = sim::buildScenarioTerrain(scenario, *arena, terrain);
    }
    s = s.isOk() ? sim::buildScenarioFrames(scenario, terrain, *frames) : s;
    if (!s.isOk()) {
        std::fprintf(stderr, "hil_soak: %s: %s (detail %lld)\n", path.c_str(), s.reason(), static_cast<long long>(s.detail()));
        return false;
    }
    config = configFor(frames->frames[0]);
    return true;
}

void writeReport(std::FILE* f) {
    const link::LinkCounters& c = g_session.counters();
    std::fprintf(f, "vtm-hil-soak 1\n");
    for (std::size_t i = 0U; i < g_camera.count; ++i) {
        std::fprintf(f, "delivered %u\n", g_camera.delivered[i]);
    }
    std::fprintf(f, "requests %lld products %lld refused %lld unnamed %lld drained %lld ended_early %d reconnect_failures %lld\n",
                 g_out.requests, g_out.products, g_out.refused, g_out.unnamed, g_out.drained, g_out.ended_early ? 1 : 0,
                 g_out.reconnect_failures);
    for (int st = 0; st < Outcome::kStages; ++st) {
        for (int code = 0; code < Outcome::kCodes; ++code) {
            if (g_out.table[st][code] > 0) {
                std::fprintf(f, "refusal %s %s %lld %s\n", app::stageName(static_cast<app::Stage>(st)),
                             statusCodeName(static_cast<StatusCode>(code)), g_out.table[st][code], g_out.first_reason[st][code]);
            }
        }
    }
    std::fprintf(f, "link messages_ok %llu messages_lost %llu bytes_skipped %llu frames_ok %llu poses_ok %llu orphan_chunks %llu reconnects %llu\n",
                 static_cast<unsigned long long>(c.messages_ok), static_cast<unsigned long long>(c.messages_lost),
                 static_cast<unsigned long long>(c.bytes_skipped), static_cast<unsigned long long>(c.frames_ok),
                 static_cast<unsigned long long>(c.poses_ok), static_cast<unsigned long long>(c.orphan_chunks),
                 static_cast<unsigned long long>(c.reconnects));
    for (std::size_t k = 0U; k < link::kLinkFaultCount; ++k) {
        const auto fault = static_cast<link::LinkFault>(k);
        std::fprintf(f, "fault %s %llu\n", link::linkFaultName(fault), static_cast<unsigned long long>(c.count(fault)));
    }
    std::fprintf(f, "resources heap_calls %llu stack_half %zu stack_end %zu hwm_half_kib %lld hwm_end_kib %lld\n",
                 static_cast<unsigned long long>(g_out.heap_calls), g_out.stack_half, g_out.stack_end, g_out.hwm_half_kib,
                 g_out.hwm_end_kib);
}

}  // namespace

int main(int argc, char** argv) {
    Args a;
    if (!parseArgs(argc, argv, a)) {
        std::fprintf(stderr, "usage: %s --unix PATH | --tcp IPV4:PORT --scenario FILE --requests N [--timeout-ms MS] [--report FILE]\n",
                     argv[0]);
        return 2;
    }
    g_args = &a;
    app::WideBaselineMapperConfig config;
    if (!loadConfig(a.scenario, config)) {
        return 1;
    }
    link::LinkSession::Config link_config;
    link_config.timeout_ms = a.timeout_ms;
    link_config.max_interpolation_gap_ns = 1U;  // a lost pose is lost, never interpolated across laps
    std::vector<std::byte> pool(app::WideBaselineMapper::workspaceBytes(config) + 64U);
    Arena arena(pool.data(), pool.size());
    Status s = connectLink(a);
    s = s.isOk() ? g_session.init(link_config, g_stream, g_clock) : s;
    s = s.isOk() ? g_mapper.init(config, arena, g_camera, g_odometry, g_clock, g_events) : s;
    if (!s.isOk()) {
        std::fprintf(stderr, "hil_soak: start: %s (%s, detail %lld)\n", s.reason(), statusCodeName(s.code()),
                     static_cast<long long>(s.detail()));
        return 1;
    }
    std::memset(g_stack, kPaint, sizeof(g_stack));
    for (std::size_t i = 0U; i < RecordingCamera::kCapacity; i += 1024U) {  // resident before the loop
        static_cast<volatile std::uint32_t*>(g_camera.delivered)[i] = 0U;
    }
    pthread_attr_t attr;
    pthread_t thread;
    if (pthread_attr_init(&attr) != 0 || pthread_attr_setstack(&attr, g_stack, sizeof(g_stack)) != 0 ||
        pthread_create(&thread, &attr, requestLoop, nullptr) != 0 || pthread_join(thread, nullptr) != 0) {
        std::fprintf(stderr, "hil_soak: cannot run the request thread\n");
        return 1;
    }
    writeReport(stdout);
    if (!a.report.empty()) {
        std::FILE* f = std::fopen(a.report.c_str(), "w");
        if (f == nullptr) {
            std::fprintf(stderr, "hil_soak: cannot write %s\n", a.report.c_str());
            return 1;
        }
        writeReport(f);
        std::fclose(f);
    }
    bool ok = true;
    const auto check = [&ok](bool good, const char* what) {
        if (!good) {
            std::fprintf(stderr, "hil_soak: FAILED: %s\n", what);
            ok = false;
        }
    };
    check(g_out.requests == a.requests && !g_out.ended_early, "every request answered before the end of stream");
    check(g_out.unnamed == 0, "every request a product or a named Status");
    check(g_out.requests == g_out.products + g_out.refused, "requests = products + refusals");
    check(g_out.heap_calls == 0U, "no heap in the request loop");
    check(g_out.reconnect_failures == 0, "every reconnect succeeded");
    check(g_out.stack_end == g_out.stack_half, "stack high-water unchanged in the second half");
    check(g_out.hwm_end_kib == g_out.hwm_half_kib, "memory high-water unchanged in the second half");
    return ok ? 0 : 1;
}
