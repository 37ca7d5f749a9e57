// Cost probe of the two mapping executives in their default flight configuration, built
// for every target. tools/budget/timing_budget.sh runs it on the host (stage times) and
// under qemu-user with the instruction-counting plugin (instructions per stage, from the
// plugin's per-symbol profile).
//
//   vtm_mapper_probe rover|descent MANIFEST POSE_LOG R00 R01 R02 R10 R11 R12 R20 R21 R22 PX PY PZ [RUNS [CONTENT]]
//
// CONTENT (probe_content.hpp; default texture: the frames as rendered) replaces the frames'
// pixels with an adversarial content of the same size and bit depth, the poses unchanged
// (issue 22 item 5: each stage's count against the scenario frames').
// Frames from hal::FileCamera (MANIFEST: a `vtm-sim render` folder's <camera>.frames),
// poses from hal::FileOdometry (POSE_LOG: its odometry.poses), the camera mount on the
// vehicle as R_vehicle_from_camera (row-major) and the camera centre in the vehicle frame.
// The mapper (WideBaselineMapper{} / DescentMapper{} defaults: 1024 x 1024, 128
// disparities / 64 planes) flies one request RUNS times (default 1), the camera rewound
// before each. Prints per run "run K status S" and per stage "stage NAME ms T quality Q"
// (hal::MonotonicClock), then a hash of the products' bits (the same on every target).
// Under qemu, tools/qemu/insn_count.c's marker=vtm_probe_mark brackets every stage.
// Test code: the arena comes from the heap at start-up.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "hal/event_log.hpp"
#include "hal/file/file_camera.hpp"
#include "hal/file/file_odometry.hpp"
#include "hal/posix/monotonic_clock.hpp"
#include "probe_content.hpp"
#include "vtm/app/descent_mapper.hpp"
#include "vtm/app/wide_baseline_mapper.hpp"

// The stage marker: every stage reads the clock once when it starts and once when it ends
// (app::detail::recordStage), so the qemu plugin's marker=vtm_probe_mark records the
// instruction total at both ends of every stage. One block (a return), never inlined.
extern "C" __attribute__((noinline)) void vtm_probe_mark() { __asm__ volatile("" ::: "memory"); }

namespace {

// hal::MonotonicClock with the marker call in front of every reading.
class MarkedClock final : public vtm::hal::Clock {
public:
    [[nodiscard]] std::uint64_t monotonicNs() const override {
        vtm_probe_mark();
        return clock_.monotonicNs();
    }

private:
    vtm::hal::MonotonicClock clock_;
};

// hal::FileCamera with the frames' content replaced (issue 22 item 5, probe_content.hpp):
// "texture" leaves the scenario's frames as they are; "saturated" is their levels times 4
// clipped; the other kinds ignore them. The noise differs from frame to frame (a
// 32-bit LCG seeded by the frame's index), so the two frames of a pair do not match.
class ContentCamera final : public vtm::hal::Camera {
public:
    ContentCamera(vtm::hal::FileCamera& inner, std::string kind) : inner_(inner), kind_(std::move(kind)) {}
    [[nodiscard]] vtm::Status describe(vtm::hal::CameraDescription& out) const override {
        return inner_.describe(out);
    }
    [[nodiscard]] vtm::Status capture(const vtm::ImageView<std::uint8_t>& out, vtm::hal::FrameInfo& info) override {
        VTM_RETURN_IF_ERROR(inner_.capture(out, info));
        replace(out);
        return vtm::Status::ok();
    }
    [[nodiscard]] vtm::Status capture16(const vtm::ImageView<std::uint16_t>& out, vtm::hal::FrameInfo& info) override {
        VTM_RETURN_IF_ERROR(inner_.capture16(out, info));
        replace(out);
        return vtm::Status::ok();
    }
    void rewind() noexcept {
        inner_.rewind();
        frame_ = 0U;
    }

private:
    template <typename T>
    void replace(const vtm::ImageView<T>& img) {
        vtm::hal::CameraDescription d;
        if (kind_ == "texture" || !inner_.describe(d).isOk()) {  // texture: the frames as they are
            return;
        }
        const int max = (1 << d.bit_depth) - 1;
        const vtm::bench::ContentLevels levels{max, max / 2, max / 4, 3 * max / 4};
        std::uint32_t state = 2463534242U + 7919U * ++frame_;
        for (std::int32_t y = 0; y < img.height(); ++y) {
            T* row = img.row(y);
            for (std::int32_t x = 0; x < img.width(); ++x) {
                state = state * 1664525U + 1013904223U;
                const int r = static_cast<int>((state >> 8) % static_cast<std::uint32_t>(max + 1));
                row[x] = static_cast<T>(vtm::bench::contentValue(kind_, levels, x, y, img.width(), row[x], r));
            }
        }
    }
    vtm::hal::FileCamera& inner_;
    std::string kind_;
    std::uint32_t frame_ = 0U;
};

double parseDouble(const char* s, const char* what) {
    char* end = nullptr;
    const double v = std::strtod(s, &end);
    if (end == s || *end != '\0') {
        std::fprintf(stderr, "mapper_probe: %s: '%s' is not a number\n", what, s);
        std::exit(2);
    }
    return v;
}

// FNV-1a over values, each in little-endian byte order (the same bits hash the same on
// big-endian targets).
std::uint64_t fnvByte(std::uint64_t h, unsigned b) { return (h ^ (b & 0xFFU)) * 1099511628211ULL; }

std::uint64_t fnvValue(std::uint64_t h, std::uint32_t bits, int bytes) {
    for (int i = 0; i < bytes; ++i) {
        h = fnvByte(h, bits >> (8 * i));
    }
    return h;
}

std::uint64_t hashValue(std::uint64_t h, float v) {
    std::uint32_t bits = 0;
    std::memcpy(&bits, &v, sizeof bits);
    return fnvValue(h, bits, 4);
}

std::uint64_t hashValue(std::uint64_t h, std::int16_t v) {
    return fnvValue(h, static_cast<std::uint16_t>(v), 2);
}

template <typename T>
std::uint64_t hashView(std::uint64_t h, const vtm::ImageView<const T>& v) {
    for (std::int32_t y = 0; y < v.height(); ++y) {
        for (std::int32_t x = 0; x < v.width(); ++x) {
            h = hashValue(h, v.row(y)[x]);
        }
    }
    return h;
}

void printStages(const vtm::app::StageLog& log) {
    for (std::size_t i = 0; i < log.size(); ++i) {
        const vtm::app::StageRecord& r = log.at(i);
        std::printf("stage %s ms %.3f quality %lld\n", vtm::app::stageName(r.stage),
                    1e-6 * static_cast<double>(r.duration_ns), static_cast<long long>(r.quality));
    }
}

template <typename Mapper, typename Config>
int fly(Config config, ContentCamera& camera, vtm::hal::FileOdometry& odometry, int runs) {
    std::vector<std::byte> pool(Mapper::workspaceBytes(config) + 64U);
    vtm::Arena arena(pool.data(), pool.size());
    static MarkedClock clock;
    static vtm::hal::EventLog events;
    auto mapper = std::make_unique<Mapper>();
    vtm::Status st = mapper->init(config, arena, camera, odometry, clock, events);
    if (!st.isOk()) {
        std::fprintf(stderr, "mapper_probe: init: %s (%lld)\n", st.reason(), static_cast<long long>(st.detail()));
        return 1;
    }
    arena.freeze();
    std::printf("memory object %zu workspace %zu\n", sizeof(Mapper), Mapper::workspaceBytes(config));
    int failed = 0;
    for (int k = 0; k < runs; ++k) {
        camera.rewind();
        st = mapper->map();
        std::printf("run %d status %s %s\n", k, vtm::statusCodeName(st.code()), st.isOk() ? "" : st.reason());
        printStages(mapper->stages());
        failed += st.isOk() ? 0 : 1;
        while (events.size() > 0U) {
            vtm::hal::Event e;
            (void)events.pop(e);
        }
    }
    std::uint64_t h = 1469598103934665603ULL;
    if constexpr (std::is_same_v<Mapper, vtm::app::WideBaselineMapper>) {
        const vtm::app::WideBaselineProducts* p = mapper->products();
        if (p != nullptr) {
            h = hashView(h, p->disparity_px16);
            for (const vtm::terrain::TerrainPoint& q : p->points) {
                h = hashValue(hashValue(hashValue(hashValue(h, q.x_m), q.y_m), q.z_m), q.sigma_range_m);
            }
            std::printf("points %zu\n", p->points.size());
            std::printf("features %d attempted %d matched %d\n", p->refine.detection.kept, p->refine.matching.attempted,
                        p->refine.matching.matched);
        }
    } else {
        const vtm::app::DescentProducts* p = mapper->products();
        if (p != nullptr) {
            h = hashView(h, p->depth_m);
            const vtm::terrain::HeightMap& map = *p->height_map;  // row by row, row 0 north: the old image order
            for (std::int32_t row = 0; row < map.grid().rows; ++row) {
                for (std::int32_t col = 0; col < map.grid().cols; ++col) h = hashValue(h, map.elevation(col, row));
            }
            std::printf("valid %lld\n", static_cast<long long>(p->sweep.valid_pixels));
        }
    }
    std::printf("hash %016llx\n", static_cast<unsigned long long>(h));
    return failed == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 16 || argc > 18) {
        std::fprintf(stderr,
                     "usage: vtm_mapper_probe rover|descent MANIFEST POSE_LOG R00 R01 R02 R10 R11 R12 R20 R21 R22 PX "
                     "PY PZ [RUNS [CONTENT]]\n");
        return 2;
    }
    const std::string content = argc == 18 ? argv[17] : "texture";
    if (!vtm::bench::knownContent(content, "mapper_probe")) {
        return 2;
    }
    const bool rover = std::strcmp(argv[1], "rover") == 0;
    if (!rover && std::strcmp(argv[1], "descent") != 0) {
        std::fprintf(stderr, "mapper_probe: '%s': expected rover or descent\n", argv[1]);
        return 2;
    }
    vtm::app::CameraMount mount;
    for (int i = 0; i < 9; ++i) {
        mount.R_vehicle_from_camera(i / 3, i % 3) = parseDouble(argv[4 + i], "mount rotation");
    }
    for (int i = 0; i < 3; ++i) {
        mount.position_vehicle_m[i] = parseDouble(argv[13 + i], "mount position");
    }
    const int runs = argc >= 17 ? static_cast<int>(parseDouble(argv[16], "RUNS")) : 1;
    if (runs < 1 || runs > 100) {
        std::fprintf(stderr, "mapper_probe: RUNS must be 1..100\n");
        return 2;
    }
    static vtm::hal::FileCamera files;
    static vtm::hal::FileOdometry odometry;
    vtm::hal::FileCamera::Config cc;
    cc.manifest_path = argv[2];
    vtm::Status st = files.init(cc);
    if (!st.isOk()) {
        std::fprintf(stderr, "mapper_probe: %s: %s (%lld)\n", argv[2], st.reason(), static_cast<long long>(st.detail()));
        return 1;
    }
    static ContentCamera camera(files, content);
    vtm::hal::FileOdometry::Config oc;
    oc.pose_log_path = argv[3];
    st = odometry.init(oc);
    if (!st.isOk()) {
        std::fprintf(stderr, "mapper_probe: %s: %s (%lld)\n", argv[3], st.reason(), static_cast<long long>(st.detail()));
        return 1;
    }
    if (rover) {
        vtm::app::WideBaselineMapperConfig c;
        c.mount = mount;
        return fly<vtm::app::WideBaselineMapper>(c, camera, odometry, runs);
    }
    vtm::app::DescentMapperConfig c;
    c.mount = mount;
    return fly<vtm::app::DescentMapper>(c, camera, odometry, runs);
}
