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
    Status load(const std::string& path) {
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
            if (f.model.width_px == scenario_.camera.width_px && f.model.height_px == scenario_.camera.height_px) {
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

struct FaultPlan {
    int crc_every = 0;
    int truncate_every = 0;
    int replay_every = 0;
    int garbage_every = 0;
};

bool parseFaults(const std::vector<std::string>& specs, FaultPlan& plan) {
    for (const std::string& spec : specs) {
        const std::size_t colon = spec.find(':');
        if (colon == std::string::npos) {
            return false;
        }
        const std::string kind = spec.substr(0, colon);
        const int n = std::atoi(spec.c_str() + colon + 1);
        if (n < 1) {
            return false;
        }
        int* slot = kind == "crc"        ? &plan.crc_every
                    : kind == "truncate" ? &plan.truncate_every
                    : kind == "replay"   ? &plan.replay_every
                    : kind == "garbage"  ? &plan.garbage_every
                                         : nullptr;
        if (slot == nullptr) {
            return false;
        }
        *slot = n;
    }
    return true;
}

// Encodes messages, applies the fault plan and writes them to the connected socket.
class LinkWriter {
public:
    LinkWriter(int fd, FaultPlan plan) : fd_(fd), plan_(plan) {}

    bool send(link::MessageType type, const std::vector<std::uint8_t>& payload) {
        std::vector<std::uint8_t> msg(link::kHeaderBytes + payload.size());
        const std::size_t n = link::encodeMessage(type, sequence_++, Span<const std::uint8_t>(payload.data(), payload.size()),
                                                  Span<std::uint8_t>(msg.data(), msg.size()));
        if (n == 0U) {
            return false;
        }
        ++count_;
        if (every(plan_.garbage_every)) {
            std::vector<std::uint8_t> noise(37U);
            for (std::size_t i = 0U; i < noise.size(); ++i) {
                noise[i] = static_cast<std::uint8_t>(count_ * 131U + i * 29U);
            }
            if (!writeAll(noise.data(), noise.size())) {
                return false;
            }
        }
        if (every(plan_.crc_every)) {
            msg[msg.size() > link::kHeaderBytes ? msg.size() - 1U : link::kHeaderBytes - 1U] ^= 0x01U;
        }
        const std::size_t size = every(plan_.truncate_every) ? msg.size() / 2U : msg.size();
        if (!writeAll(msg.data(), size)) {
            return false;
        }
        if (every(plan_.replay_every)) {
            return writeAll(msg.data(), msg.size());
        }
        return true;
    }
    std::uint64_t bytesWritten() const { return bytes_; }
    std::uint64_t messages() const { return count_; }

private:
    bool every(int n) const { return n > 0 && count_ % static_cast<std::uint64_t>(n) == 0U; }
    bool writeAll(const std::uint8_t* data, std::size_t size) {
        std::size_t pos = 0U;
        while (pos < size) {  // bound: each pass writes >= 1 byte or fails
            const ssize_t w = ::send(fd_, data + pos, size - pos, MSG_NOSIGNAL);
            if (w <= 0) {
                return false;
            }
            pos += static_cast<std::size_t>(w);
        }
        bytes_ += size;
        return true;
    }
    int fd_;
    FaultPlan plan_;
    std::uint32_t sequence_ = 1U;
    std::uint64_t count_ = 0U;
    std::uint64_t bytes_ = 0U;
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

// Streams everything; false when the receiver went away.
bool streamFrames(FrameSource& source, LinkWriter& writer, const ServeOptions& o, int count, std::string& error) {
    std::vector<std::uint8_t> payload(link::kCameraDescriptionBytes);
    link::encodeCameraDescription(source.camera(), payload.data());
    if (!writer.send(link::MessageType::kCameraDescription, payload)) {
        error = "receiver closed the connection";
        return false;
    }
    const auto start = std::chrono::steady_clock::now();
    std::vector<std::uint8_t> packed;
    std::uint64_t last_pose_ns = 0U;
    for (int i = 0; i < count; ++i) {
        if (o.rate_hz > 0.0) {
            std::this_thread::sleep_until(start + std::chrono::duration<double>(i / o.rate_hz));
        }
        hal::FrameInfo info;
        const Status s = source.frame(i % source.frameCount(), info, packed);
        if (!s.isOk()) {
            error = std::string("render failed: ") + s.reason();
            return false;
        }
        if (i >= source.frameCount()) {  // --frames beyond the scenario: repeat, with fresh sequence and time
            const auto lap = static_cast<std::uint32_t>(i / source.frameCount());
            info.sequence += 100000U * lap;
            info.timestamp_ns += 1000000000000ULL * lap;
        }
        hal::PoseEstimate pose = source.pose(i % source.frameCount());
        pose.timestamp_ns = info.timestamp_ns;
        bool ok = true;
        // One pose per vehicle time: frames of several cameras taken together share it
        // (the ICD requires pose times to increase).
        if (i == 0 || pose.timestamp_ns > last_pose_ns) {
            payload.assign(link::kPoseBytes, 0U);
            link::encodePose(pose, payload.data());
            ok = writer.send(link::MessageType::kPose, payload);
            last_pose_ns = pose.timestamp_ns;
        }
        link::FrameBegin begin;
        begin.info = info;
        begin.bytes_per_pixel = info.bit_depth > 8U ? 2U : 1U;
        begin.pixel_bytes = static_cast<std::uint32_t>(packed.size());
        payload.assign(link::kFrameBeginBytes, 0U);
        link::encodeFrameBegin(begin, payload.data());
        ok = ok && writer.send(link::MessageType::kFrameBegin, payload);
        const std::size_t chunk = static_cast<std::size_t>(o.chunk_bytes) / begin.bytes_per_pixel * begin.bytes_per_pixel;
        for (std::size_t off = 0U; ok && off < packed.size(); off += chunk) {
            const std::size_t n = std::min(chunk, packed.size() - off);
            payload.resize(link::kFrameChunkPrefixBytes + n);
            link::encodeFrameChunkPrefix(info.sequence, static_cast<std::uint32_t>(off), payload.data());
            std::copy(packed.begin() + static_cast<std::ptrdiff_t>(off),
                      packed.begin() + static_cast<std::ptrdiff_t>(off + n), payload.begin() + link::kFrameChunkPrefixBytes);
            ok = writer.send(link::MessageType::kFrameChunk, payload);
        }
        if (!ok) {
            error = "receiver closed the connection";
            return false;
        }
    }
    if (!writer.send(link::MessageType::kEndOfStream, {})) {
        error = "receiver closed the connection";
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
    ScenarioFrameSource source;
    const Status loaded = source.load(o.scenario);
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
    ::close(lfd);
    if (fd < 0) {
        return fail(1, "no receiver connected in time");
    }
    LinkWriter writer(fd, plan);
    const int count = o.frames < 0 ? source.frameCount() : o.frames;
    const auto t0 = std::chrono::steady_clock::now();
    const bool ok = streamFrames(source, writer, o, count, error);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ::shutdown(fd, SHUT_WR);
    char drain[256];
    while (::recv(fd, drain, sizeof(drain), 0) > 0) {  // bound: the receiver closes its end
    }
    ::close(fd);
    if (!o.unix_path.empty()) {
        ::unlink(o.unix_path.c_str());
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
    cmd->callback([]() {
        const int code = runServe(options);
        if (code != 0) {
            std::exit(code);
        }
    });
    return cmd;
}

}  // namespace vtm::simtool
