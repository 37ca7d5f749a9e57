#include "run_target.hpp"
#include "command_support.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "build_info.hpp"
#include "vtm/ground/exit_codes.hpp"
#include "run_drivers.hpp"

extern char** environ;

namespace vtm::tools {
namespace {

namespace fs = std::filesystem;

struct TargetInfo {
    const char* name;
    const char* emulator;  // qemu-user binary (Debian package qemu-user); binaries are static
};

constexpr TargetInfo kTargets[] = {
    {"aarch64", "qemu-aarch64"}, {"armhf", "qemu-arm"},         {"ppc750", "qemu-ppc"},
    {"leon3", "qemu-sparc32plus"}, {"riscv64", "qemu-riscv64"},
};

// build/<target>/tools/vtm/vtm beside this build (build/<preset>/tools/vtm/vtm), or "".
std::string defaultFlightExecutable(const std::string& target) {
    const std::string build = buildDirectory();
    if (build.empty()) return "";
    return (fs::path(build).parent_path() / target / "tools" / "vtm" / "vtm").string();
}

// The program's path on PATH, or "" if it is not there.
std::string onPath(const std::string& program) {
    const char* path = std::getenv("PATH");
    std::string dirs = path != nullptr ? path : "/usr/bin:/bin";
    std::size_t start = 0;
    while (start <= dirs.size()) {
        const std::size_t end = dirs.find(':', start);
        const std::string dir = dirs.substr(start, end == std::string::npos ? std::string::npos : end - start);
        const std::string candidate = (dir.empty() ? "." : dir) + "/" + program;
        if (::access(candidate.c_str(), X_OK) == 0) return candidate;
        if (end == std::string::npos) break;
        start = end + 1;
    }
    return "";
}

// Runs argv, waits; the exit code, or -signal when it was killed. errno-style error text
// in `error` when it could not start.
int spawnAndWait(const std::vector<std::string>& args, std::string& error) {
    std::vector<char*> argv;
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    pid_t child = -1;
    const int rc = ::posix_spawn(&child, args[0].c_str(), nullptr, nullptr, argv.data(), environ);
    if (rc != 0) {
        error = args[0] + ": cannot start: " + std::strerror(rc);
        return -1000;
    }
    int status = 0;
    while (::waitpid(child, &status, 0) < 0) {
        if (errno != EINTR) {
            error = std::string("waitpid: ") + std::strerror(errno);
            return -1000;
        }
    }
    if (WIFSIGNALED(status)) return -WTERMSIG(status);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1000;
}

}  // namespace

std::string runTargetNames() {
    std::string names;
    for (const TargetInfo& t : kTargets) names += (names.empty() ? "" : " ") + std::string(t.name);
    return names;
}

int runOnTarget(const RunOptions& o) {
    const TargetInfo* target = nullptr;
    for (const TargetInfo& t : kTargets) {
        if (o.target == t.name) target = &t;
    }
    if (target == nullptr) {
        return failCommand("run", kExitInputError, "--target '" + o.target + "': unknown (one of: " + runTargetNames() + ")");
    }
    if (std::string(kTarget) != "host") {
        return failCommand("run", kExitInputError, std::string("--target: this vtm is the ") + kTarget +
                    " build; run --target from the host build (build/host-release/tools/vtm/vtm)");
    }
    const std::string flight = o.flight_executable.empty() ? defaultFlightExecutable(target->name) : o.flight_executable;
    if (flight.empty() || ::access(flight.c_str(), X_OK) != 0) {
        return failCommand("run", kExitInputError, "--flight '" + flight + "': no " + target->name + " vtm there (build it: cmake --preset " +
                    target->name + " && cmake --build --preset " + target->name + " --target vtm)");
    }
    const std::string emulator = onPath(target->emulator);
    if (emulator.empty()) {
        return failCommand("run", kExitInputError, std::string(target->emulator) + ": not found on PATH (Debian package qemu-user)");
    }
    const std::string sim = o.sim_executable.empty() ? defaultSimExecutable() : o.sim_executable;
    if (sim.empty() || ::access(sim.c_str(), X_OK) != 0) {
        return failCommand("run", kExitInputError, "--sim '" + sim + "': no native vtm-sim there (build it: cmake --build --preset host-release)");
    }
    std::vector<std::string> args = {emulator, flight, "run"};
    if (!o.scenario.empty()) args.push_back(o.scenario);
    args.insert(args.end(), {"--link", "--sim", fs::absolute(sim).string(), "--out", o.out_dir,
                             "--expect-target", target->name});
    if (o.size_px > 0) args.insert(args.end(), {"--size", std::to_string(o.size_px)});
    std::string line;
    for (const std::string& a : args) line += (line.empty() ? "" : " ") + a;
    std::fprintf(stderr, "vtm run: flying on %s under qemu: %s\n", target->name, line.c_str());
    const auto t0 = std::chrono::steady_clock::now();
    std::string error;
    const int rc = spawnAndWait(args, error);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (rc == -1000) return failCommand("run", kExitInputError, error);
    if (rc < 0) {
        return failCommand("run", kExitInputError, flight + " under " + target->emulator + ": killed by signal " + std::to_string(-rc) + " (" +
                    strsignal(-rc) + ") after " + std::to_string(static_cast<int>(seconds)) + " s");
    }
    std::fprintf(stderr, "vtm run: the %s vtm ended with exit code %d after %.1f s under %s\n", target->name, rc,
                 seconds, target->emulator);
    return rc;
}

}  // namespace vtm::tools
