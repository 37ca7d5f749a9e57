#include "serve_command.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <thread>

#include "hal/link/protocol.hpp"
#include "serve_writer.hpp"
#include "sim/render.hpp"
#include "sim/scenario.hpp"
#include "sim/terrain.hpp"

namespace vtm::simtool {
namespace {

namespace link = vtm::hal::link;

// What the server streams, independent of where it comes from.
class FrameSource {
public:
    virtual ~FrameSource() = default;
    virtual hal::CameraDescription camera() const = 0;
    virtual int frameCount() const = 0;
    virtual hal::PoseEstimate pose(int i) const = 0;  // odometry pose for frame i
    // Frame i's info and packed pixels (1 byte, or 2 bytes big-endian, per pixel).
    virtual Status frame(int i, hal::FrameInfo& info, std::vector<std::uint8_t>& packed) = 0;
};

// The scenario's frames (every camera of it whose frame size is the main camera's),
// rendered on demand exactly as an in-process renderFrame() call with the same request.
class ScenarioFrameSource final : public FrameSource {
public:
    // camera_id < 0: every camera whose frame size is the main camera's.
    Status load(const std::string& path, int camera_id) {
        std::ifstream in(path, std::ios::binary);
        if (!in) {
            return Status(StatusCode::kIoError, "serve: cannot read the scenario file");
        }
        std::stringstream text;
        text << in.rdbuf();
        const std::string s = text.str();
        VTM_RETURN_IF_ERROR(sim::parseScenario(s, scenario_));
        pool_.resize(sim::scenarioTerrainBytes(scenario_) + 64U);
        arena_ = std::make_unique<Arena>(pool_.data(), pool_.size());
        VTM_RETURN_IF_ERROR(sim::buildScenarioTerrain(scenario_, *arena_, terrain_));
        frames_ = std::make_unique<sim::ScenarioFrames>();
        VTM_RETURN_IF_ERROR(sim::buildScenarioFrames(scenario_, terrain_, *frames_));
        for (std::int32_t i = 0; i < frames_->count; ++i) {
            const sim::ScenarioFrame& f = frames_->frames[i];
            if (f.model.width_px == scenario_.camera.width_px && f.model.height_px == scenario_.camera.height_px &&
                (camera_id < 0 || f.camera_id == camera_id)) {
                selected_.push_back(i);
            }
        }
        return Status::ok();
    }
    hal::CameraDescription camera() const override {
        hal::CameraDescription d;
        d.camera_id = sim::kMainCameraId;
        d.bit_depth = static_cast<std::uint8_t>(scenario_.sensor.bit_depth);
        d.width_px = scenario_.camera.width_px;
        d.height_px = scenario_.camera.height_px;
        d.model = scenario_.camera;
        return d;
    }
    int frameCount() const override { return static_cast<int>(selected_.size()); }
    hal::PoseEstimate pose(int i) const override {
        const sim::VehiclePose& v = frames_->frames[selected_.at(static_cast<std::size_t>(i))].odometry_pose;
        hal::PoseEstimate p;
        p.timestamp_ns = v.timestamp_ns;
        std::copy(v.position_m, v.position_m + 3, p.position_m);
        std::copy(v.attitude_wxyz, v.attitude_wxyz + 4, p.attitude_wxyz);
        std::copy(v.covariance, v.covariance + 36, p.covariance);
        return p;
    }
    Status frame(int i, hal::FrameInfo& info, std::vector<std::uint8_t>& packed) override {
        // Rendered once per scenario frame (a repeated --frames lap streams the cache, so
        // the link, not the renderer, sets the pace).
        auto& cached = cache_[i];
        if (cached.first.width_px == 0) {
            VTM_RETURN_IF_ERROR(render(i, cached.first, cached.second));
        }
        info = cached.first;
        packed = cached.second;
        return Status::ok();
    }

private:
    Status render(int i, hal::FrameInfo& info, std::vector<std::uint8_t>& packed) {
        const sim::ScenarioFrame& f = frames_->frames[selected_.at(static_cast<std::size_t>(i))];
        const sim::FrameRequest request = sim::scenarioFrameRequest(scenario_, terrain_, f);
        const std::int32_t w = f.model.width_px;
        const std::int32_t h = f.model.height_px;
        const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
        sim::FrameOutput out;
        std::vector<std::uint16_t> px16;
        if (f.sensor.bit_depth > 8) {
            px16.resize(n);
            out.image16 = ImageView<std::uint16_t>(px16.data(), w, h);
        } else {
            packed.resize(n);
            out.image8 = ImageView<std::uint8_t>(packed.data(), w, h);
        }
        VTM_RETURN_IF_ERROR(sim::renderFrame(request, out, nullptr));
        if (!px16.empty()) {
            packed.resize(2U * n);
            for (std::size_t k = 0U; k < n; ++k) {
                packed[2U * k] = static_cast<std::uint8_t>(px16[k] >> 8U);
                packed[2U * k + 1U] = static_cast<std::uint8_t>(px16[k] & 0xFFU);
            }
        }
        info = hal::FrameInfo{};
        info.sequence = f.sequence + 1000U * f.camera_id;  // unique across the scenario's cameras
        info.timestamp_ns = f.timestamp_ns;
        info.exposure_us = static_cast<std::uint32_t>(f.sensor.exposure_s * 1e6 + 0.5);
        info.camera_id = f.camera_id;
        info.bit_depth = static_cast<std::uint8_t>(f.sensor.bit_depth);
        info.width_px = w;
        info.height_px = h;
        return Status::ok();
    }

    sim::Scenario scenario_{};
    std::map<int, std::pair<hal::FrameInfo, std::vector<std::uint8_t>>> cache_;
    std::vector<std::byte> pool_;
    std::unique_ptr<Arena> arena_;
    sim::Terrain terrain_{};
    std::unique_ptr<sim::ScenarioFrames> frames_;
    std::vector<std::int32_t> selected_;
};

int fail(int code, const std::string& what) {
    std::fprintf(stderr, "vtm-sim serve: %s\n", what.c_str());
    return code;
}

// Listening socket for "HOST:PORT" (IPv4 literal) or a Unix path; -1 with a message.
int listenOn(const ServeOptions& o, std::string& error) {
    if (!o.unix_path.empty()) {
        sockaddr_un addr{};
        addr.sun_family = AF_UNIX;
        if (o.unix_path.size() >= sizeof(addr.sun_path)) {
            error = "--unix path longer than 107 characters";
            return -1;
        }
        std::snprintf(addr.sun_path, sizeof(addr.sun_path), "%s", o.unix_path.c_str());
        ::unlink(o.unix_path.c_str());
        const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
        if (fd < 0 || ::bind(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof(addr)) != 0 || ::listen(fd, 1) != 0) {
            error = "cannot listen on " + o.unix_path;
            return -1;
        }
        return fd;
    }
    const std::size_t colon = o.tcp.rfind(':');
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    const int port = (colon == std::string::npos) ? 0 : std::atoi(o.tcp.c_str() + colon + 1);
    if (colon == std::string::npos || port < 1 || port > 65535 ||
        ::inet_pton(AF_INET, o.tcp.substr(0, colon).c_str(), &addr.sin_addr) != 1) {
        error = "--tcp must be IPV4:PORT, e.g. 127.0.0.1:5600";
        return -1;
    }
    addr.sin_port = htons(static_cast<std::uint16_t>(port));
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    const int one = 1;
    (void)::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
    if (fd < 0 || ::bind(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof(addr)) != 0 || ::listen(fd, 1) != 0) {
        error = "cannot listen on " + o.tcp;
        return -1;
    }
    return fd;
}

int acceptOne(int listen_fd, int timeout_s) {
    pollfd p{};
    p.fd = listen_fd;
    p.events = POLLIN;
    if (::poll(&p, 1, timeout_s * 1000) != 1) {
        return -1;
    }
    return ::accept(listen_fd, nullptr, nullptr);
}

// One connection's start: the camera description (its own fault draws apply).
LinkWriter::Sent sendDescription(FrameSource& source, LinkWriter& writer) {
    std::vector<std::uint8_t> payload(link::kCameraDescriptionBytes);
    link::encodeCameraDescription(source.camera(), payload.data());
    writer.setFrame(-1, false);
    return writer.send(link::MessageType::kCameraDescription, payload);
}

// Frame i of the stream: its pose (once per vehicle time), its begin and its chunks.
LinkWriter::Sent sendFrame(FrameSource& source, LinkWriter& writer, const ServeOptions& o, int i,
                           std::uint64_t& last_pose_ns, std::string& error) {
    hal::FrameInfo info;
    std::vector<std::uint8_t> packed;
    const Status s = source.frame(i % source.frameCount(), info, packed);
    if (!s.isOk()) {
        error = std::string("render failed: ") + s.reason();
        return LinkWriter::Sent::kPeerGone;
    }
    if (i >= source.frameCount()) {  // --frames beyond the scenario: repeat, with fresh sequence and time
        const auto lap = static_cast<std::uint32_t>(i / source.frameCount());
        info.sequence += 100000U * lap;
        info.timestamp_ns += 1000000000000ULL * lap;
    }
    hal::PoseEstimate pose = source.pose(i % source.frameCount());
    pose.timestamp_ns = info.timestamp_ns;
    using Sent = LinkWriter::Sent;
    Sent sent = Sent::kOk;
    std::vector<std::uint8_t> payload;
    // One pose per vehicle time: frames of several cameras taken together share it
    // (the ICD requires pose times to increase).
    if (last_pose_ns == 0U || pose.timestamp_ns > last_pose_ns) {
        payload.assign(link::kPoseBytes, 0U);
        link::encodePose(pose, payload.data());
        writer.setFrame(info.sequence, true);
        sent = writer.send(link::MessageType::kPose, payload);
        last_pose_ns = pose.timestamp_ns;
    }
    writer.setFrame(info.sequence, false);
    link::FrameBegin begin;
    begin.info = info;
    begin.bytes_per_pixel = info.bit_depth > 8U ? 2U : 1U;
    begin.pixel_bytes = static_cast<std::uint32_t>(packed.size());
    payload.assign(link::kFrameBeginBytes, 0U);
    link::encodeFrameBegin(begin, payload.data());
    if (sent == Sent::kOk) {
        sent = writer.send(link::MessageType::kFrameBegin, payload);
    }
    const std::size_t chunk = static_cast<std::size_t>(o.chunk_bytes) / begin.bytes_per_pixel * begin.bytes_per_pixel;
    for (std::size_t off = 0U; sent == Sent::kOk && off < packed.size(); off += chunk) {
        const std::size_t n = std::min(chunk, packed.size() - off);
        payload.resize(link::kFrameChunkPrefixBytes + n);
        link::encodeFrameChunkPrefix(info.sequence, static_cast<std::uint32_t>(off), payload.data());
        std::copy(packed.begin() + static_cast<std::ptrdiff_t>(off),
                  packed.begin() + static_cast<std::ptrdiff_t>(off + n), payload.begin() + link::kFrameChunkPrefixBytes);
        sent = writer.send(link::MessageType::kFrameChunk, payload);
    }
    if (sent == Sent::kPeerGone && error.empty()) {
        error = "receiver closed the connection";
    }
    return sent;
}

// Streams everything; false when the receiver went away. A disconnect fault closes the
// connection: the next one is accepted and the stream goes on with the next frame (the
// last frame and the end of stream are never damaged, so that the receiver sees the end).
bool streamFrames(FrameSource& source, LinkWriter& writer, const ServeOptions& o, int count, int listen_fd,
                  std::string& error) {
    using Sent = LinkWriter::Sent;
    const auto start = std::chrono::steady_clock::now();
    std::uint64_t last_pose_ns = 0U;
    Sent sent = sendDescription(source, writer);
    int i = 0;
    // bound: each pass sends frame i and moves on, or takes the next connection after a
    // disconnect fault (the frame it cut short is not sent again)
    for (;;) {
        if (sent == Sent::kDisconnected) {
            const int fd = acceptOne(listen_fd, o.accept_timeout_s);
            if (fd < 0) {
                error = "the receiver did not reconnect in time";
                return false;
            }
            writer.attach(fd);
            last_pose_ns = 0U;  // the new stream starts with a pose again
            sent = sendDescription(source, writer);
            continue;
        }
        if (sent == Sent::kPeerGone) {
            error = error.empty() ? "receiver closed the connection" : error;
            return false;
        }
        if (i >= count) {
            break;
        }
        if (o.rate_hz > 0.0) {
            std::this_thread::sleep_until(start + std::chrono::duration<double>(i / o.rate_hz));
        }
        if (i == count - 1) {
            writer.protect();
        }
        sent = sendFrame(source, writer, o, i, last_pose_ns, error);
        ++i;
    }
    writer.setFrame(-1, false);
    if (sent != Sent::kOk || writer.send(link::MessageType::kEndOfStream, {}) != Sent::kOk) {
        error = error.empty() ? "receiver closed the connection" : error;
        return false;
    }
    return true;
}

}  // namespace

int runServe(const ServeOptions& o) {
    FaultPlan plan;
    if (o.tcp.empty() == o.unix_path.empty()) {
        return fail(2, "give exactly one of --tcp HOST:PORT and --unix PATH");
    }
    if (!parseFaults(o.faults, plan) || o.chunk_bytes < 2 || o.chunk_bytes > static_cast<int>(link::kMaxChunkDataBytes)) {
        return fail(2, "--fault must be crc:N, truncate:N, replay:N or garbage:N (N >= 1); --chunk 2..65536");
    }
    if (o.soak_seed >= 0) {
        if (!o.faults.empty() || o.fault_rate_permille < 0 || o.fault_rate_permille > 1000 || o.stall_ms < 0 ||
            o.hang_ms < 0) {
            return fail(2, "--soak takes no --fault; --fault-rate 0..1000, --stall-ms and --hang-ms >= 0");
        }
        plan.soak = true;
        plan.seed = static_cast<std::uint64_t>(o.soak_seed);
        plan.rate_permille = o.fault_rate_permille;
        plan.stall_ms = o.stall_ms;
        plan.hang_ms = o.hang_ms;
    }
    ScenarioFrameSource source;
    const Status loaded = source.load(o.scenario, o.camera_id);
    if (!loaded.isOk() || source.frameCount() == 0) {
        return fail(1, o.scenario + ": " + (loaded.isOk() ? "no frames" : loaded.reason()) + " (detail " +
                           std::to_string(loaded.detail()) + ")");
    }
    std::string error;
    const int lfd = listenOn(o, error);
    if (lfd < 0) {
        return fail(2, error);
    }
    std::fprintf(stderr, "vtm-sim serve: listening on %s\n", o.unix_path.empty() ? o.tcp.c_str() : o.unix_path.c_str());
    const int fd = acceptOne(lfd, o.accept_timeout_s);
    if (fd < 0) {
        ::close(lfd);
        return fail(1, "no receiver connected in time");
    }
    LinkWriter writer(plan);
    writer.attach(fd);
    const int count = o.frames < 0 ? source.frameCount() : o.frames;
    const auto t0 = std::chrono::steady_clock::now();
    const bool ok = streamFrames(source, writer, o, count, lfd, error);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ::close(lfd);
    if (writer.fd() >= 0) {
        ::shutdown(writer.fd(), SHUT_WR);
        char drain[256];
        while (::recv(writer.fd(), drain, sizeof(drain), 0) > 0) {  // bound: the receiver closes its end
        }
        ::close(writer.fd());
    }
    if (!o.unix_path.empty()) {
        ::unlink(o.unix_path.c_str());
    }
    if (!o.fault_log.empty()) {
        std::ofstream log(o.fault_log);
        log << writer.log(static_cast<std::uint64_t>(count));
        if (!log) {
            return fail(1, "cannot write the fault log " + o.fault_log);
        }
    }
    std::fprintf(stderr, "vtm-sim serve: %d frames, %llu messages, %.1f MB in %.3f s (%.1f frames/s, %.1f MB/s)\n",
                 count, static_cast<unsigned long long>(writer.messages()), writer.bytesWritten() / 1e6, s, count / s,
                 writer.bytesWritten() / 1e6 / s);
    return ok ? 0 : fail(1, error);
}

CLI::App* addServeCommand(CLI::App& app) {
    static ServeOptions options;  // lives as long as the parsed command line
    CLI::App* cmd = app.add_subcommand("serve", "stream a scenario over the HIL link (docs/icd-hil-link.md)");
    cmd->add_option("scenario", options.scenario, "scenario file (sim/scenarios/*.scn)")->required();
    cmd->add_option("--tcp", options.tcp, "listen on IPV4:PORT (e.g. 127.0.0.1:5600)");
    cmd->add_option("--unix", options.unix_path, "listen on a Unix-domain socket path");
    cmd->add_option("--frames", options.frames, "frames to stream (default: every frame of the scenario; more repeat it)");
    cmd->add_option("--rate", options.rate_hz, "frames per second (default: as fast as the receiver reads)");
    cmd->add_option("--chunk", options.chunk_bytes, "pixel bytes per chunk message, 2..65536");
    cmd->add_option("--accept-timeout", options.accept_timeout_s, "seconds to wait for the receiver");
    cmd->add_option("--fault", options.faults, "crc:N | truncate:N | replay:N | garbage:N (repeatable)");
    cmd->add_option("--camera", options.camera_id, "stream only this camera's frames (default: every camera of the main size)");
    cmd->add_option("--soak", options.soak_seed, "random faults of every kind from this seed (docs/hal-link.md, Soak)");
    cmd->add_option("--fault-rate", options.fault_rate_permille, "--soak: messages hit per 1000 (default 20)");
    cmd->add_option("--stall-ms", options.stall_ms, "--soak: pause of a stall, ms (default 100)");
    cmd->add_option("--hang-ms", options.hang_ms, "--soak: pause of a hang, ms (default 0: no hangs)");
    cmd->add_option("--fault-log", options.fault_log, "write what was injected, per frame and in total");
    cmd->callback([]() {
        const int code = runServe(options);
        if (code != 0) {
            std::exit(code);
        }
    });
    return cmd;
}

}  // namespace vtm::simtool
