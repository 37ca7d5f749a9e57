// The camera and odometry `vtm run` flies a scenario with: the simulated drivers in
// process (hal/sim), or — with --link — hal/link's LinkCamera and LinkOdometry on a Unix
// socket served by a separate `vtm-sim serve` process that this object starts and reaps.
#pragma once

#include <sys/types.h>

#include <memory>
#include <string>

#include "hal/camera.hpp"
#include "hal/link/link_session.hpp"
#include "hal/link/socket_stream.hpp"
#include "hal/odometry.hpp"
#include "hal/posix/monotonic_clock.hpp"
#include "hal/sim/sim_camera.hpp"
#include "hal/sim/sim_odometry.hpp"
#include "vtm/ground/sim_world.hpp"

namespace vtm::tools {

class RunDrivers {
public:
    RunDrivers() = default;
    ~RunDrivers();
    RunDrivers(const RunDrivers&) = delete;
    RunDrivers& operator=(const RunDrivers&) = delete;

    // In process: SimCamera (main camera) and SimOdometry on the world. "" or the error.
    std::string startInProcess(const ground::SimWorld& world);
    // Over the link: writes the scenario text to scenario_path, starts
    // `SIM serve scenario_path --unix SOCKET [--frames COUNT]` (the first COUNT frames) and
    // connects. "" or the error.
    std::string startLink(const std::string& sim_executable, const std::string& scenario_text,
                          const std::string& scenario_path, const std::string& frames);
    // Waits for the simulator to exit (after the stream ended); "" or how it ended.
    std::string finish();

    [[nodiscard]] hal::Camera& camera() { return *camera_; }
    [[nodiscard]] hal::Odometry& odometry() { return *odometry_; }
    [[nodiscard]] bool linked() const { return child_ > 0; }
    // Link faults counted by the session (0 when in process).
    [[nodiscard]] unsigned long long linkFaults() const;

private:
    std::unique_ptr<hal::SimCamera> sim_camera_;
    std::unique_ptr<hal::SimOdometry> sim_odometry_;
    hal::MonotonicClock clock_;
    std::unique_ptr<hal::link::SocketStream> stream_;
    std::unique_ptr<hal::link::LinkSession> session_;
    std::unique_ptr<hal::link::LinkCamera> link_camera_;
    std::unique_ptr<hal::link::LinkOdometry> link_odometry_;
    hal::Camera* camera_ = nullptr;
    hal::Odometry* odometry_ = nullptr;
    pid_t child_ = -1;
    std::string socket_path_;
};

// The build directory this vtm belongs to (build/<preset> of build/<preset>/tools/vtm/vtm),
// or "" if /proc/self/exe cannot be read.
std::string buildDirectory();
// The vtm-sim next to this vtm (build/<preset>/tools/sim/vtm-sim), or "" if not found.
std::string defaultSimExecutable();

}  // namespace vtm::tools
