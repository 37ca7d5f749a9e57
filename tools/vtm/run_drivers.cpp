#include "run_drivers.hpp"

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

extern char** environ;

namespace vtm::tools {

RunDrivers::~RunDrivers() {
    if (child_ > 0) {  // an early return: do not leave the simulator behind
        ::kill(child_, SIGTERM);
        int status = 0;
        ::waitpid(child_, &status, 0);
    }
    if (!socket_path_.empty()) ::unlink(socket_path_.c_str());
}

std::string RunDrivers::startInProcess(const ground::SimWorld& world) {
    sim_camera_ = std::make_unique<hal::SimCamera>();
    sim_odometry_ = std::make_unique<hal::SimOdometry>();
    hal::SimCamera::Config cc;
    cc.scenario = &world.scenario;
    cc.terrain = &world.terrain;
    cc.frames = world.frames.get();
    cc.camera_id = sim::kMainCameraId;
    Status st = sim_camera_->init(cc);
    if (st.isOk()) st = sim_odometry_->init({world.frames.get(), nullptr});
    if (!st.isOk()) return std::string("simulated drivers: ") + st.reason();
    camera_ = sim_camera_.get();
    odometry_ = sim_odometry_.get();
    return "";
}

std::string RunDrivers::startLink(const std::string& sim_executable, const std::string& scenario_text,
                                  const std::string& scenario_path, const std::string& frames) {
    if (sim_executable.empty() || ::access(sim_executable.c_str(), X_OK) != 0) {
        return "--sim '" + sim_executable + "': no vtm-sim executable there (build it: cmake --build --preset "
               "host-release --target vtm-sim)";
    }
    std::ofstream(scenario_path) << scenario_text;
    static int serial = 0;
    socket_path_ = "/tmp/vtm-run-" + std::to_string(::getpid()) + "-" + std::to_string(serial++) + ".sock";
    ::unlink(socket_path_.c_str());
    std::vector<std::string> args = {sim_executable, "serve", scenario_path, "--unix", socket_path_,
                                     "--accept-timeout", "120"};
    if (!frames.empty()) {
        args.push_back("--frames");
        args.push_back(frames);
    }
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    // The simulator's stdout (its progress) goes to stderr: vtm run's stdout is its summary.
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, STDERR_FILENO, STDOUT_FILENO);
    const int rc = ::posix_spawn(&child_, sim_executable.c_str(), &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0) {
        child_ = -1;
        return sim_executable + ": cannot start: " + std::strerror(rc);
    }
    stream_ = std::make_unique<hal::link::SocketStream>();
    // The simulator builds its world before it listens: allow a minute, and stop waiting
    // as soon as it has exited instead.
    Status st;
    for (int attempt = 0; attempt < 120; ++attempt) {
        st = stream_->connectUnix(socket_path_.c_str(), 500U);
        if (st.isOk()) break;
        int status = 0;
        if (::waitpid(child_, &status, WNOHANG) == child_) {
            child_ = -1;
            return "vtm-sim serve ended before it listened (" +
                   (WIFEXITED(status) ? "exit status " + std::to_string(WEXITSTATUS(status))
                                      : "signal " + std::to_string(WTERMSIG(status))) +
                   "; its message is above)";
        }
    }
    if (!st.isOk()) return "link: connecting to " + socket_path_ + ": " + st.reason();
    session_ = std::make_unique<hal::link::LinkSession>();
    hal::link::LinkSession::Config lc;
    lc.timeout_ms = 120000U;  // a 1024 x 1024 frame is rendered before it is sent
    st = session_->init(lc, *stream_, clock_);
    if (!st.isOk()) return std::string("link: ") + st.reason();
    link_camera_ = std::make_unique<hal::link::LinkCamera>(*session_);
    link_odometry_ = std::make_unique<hal::link::LinkOdometry>(*session_);
    camera_ = link_camera_.get();
    odometry_ = link_odometry_.get();
    return "";
}

std::string RunDrivers::finish() {
    if (child_ <= 0) return "";
    if (stream_) stream_->close();
    int status = 0;
    const pid_t r = ::waitpid(child_, &status, 0);
    child_ = -1;
    if (r < 0) return std::string("vtm-sim: waitpid: ") + std::strerror(errno);
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return "";
    if (WIFEXITED(status)) return "vtm-sim serve exited with status " + std::to_string(WEXITSTATUS(status));
    return "vtm-sim serve ended by signal " + std::to_string(WTERMSIG(status));
}

unsigned long long RunDrivers::linkFaults() const {
    return session_ ? static_cast<unsigned long long>(session_->counters().totalFaults()) : 0ULL;
}

std::string buildDirectory() {
    char self[PATH_MAX];
    const ssize_t n = ::readlink("/proc/self/exe", self, sizeof self - 1);
    if (n <= 0) return "";
    self[n] = '\0';
    return std::filesystem::path(self).parent_path().parent_path().parent_path().string();  // <dir>/tools/vtm/vtm
}

std::string defaultSimExecutable() {
    const std::string build = buildDirectory();
    if (build.empty()) return "";
    const std::filesystem::path sim = std::filesystem::path(build) / "tools" / "sim" / "vtm-sim";
    return std::filesystem::exists(sim) ? sim.string() : "";
}

}  // namespace vtm::tools
