// libFuzzer target (5): the ground's pose files (tools/ground sim_output.hpp), which vtm
// refine / rectify / descent take from the command line (docs/cli-poses.md). The first
// input byte picks the reader, the rest is the file (written to a scratch file, as the
// readers take a path): 0 readCameraPoses (vtm-camera-poses 1), 1 readPoseLog (vtm-poses 1),
// 2 readCameraPoseSpec("FILE:INDEX", INDEX from the second byte), 3 readCameraPoseSpec("FILE").
// A camera pose the spec reader accepts must have a unit quaternion within 1e-6, as it
// promises. Properties: no crash, no sanitizer report, no uncaught exception.
#include <fcntl.h>
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "vtm/ground/sim_output.hpp"

namespace {

const std::string& scratchPath() {
    // tmpfs when there is one (as fuzz_file_readers: a disk file per input costs milliseconds).
    static const std::string path = std::string(::access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp") +
                                    "/vtm_fuzz_poses_" + std::to_string(::getpid()) + ".txt";
    return path;
}

bool writeScratch(const std::uint8_t* data, std::size_t size) {
    const int fd = ::open(scratchPath().c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    if (fd < 0) {
        return false;
    }
    const bool ok = ::write(fd, data, size) == static_cast<ssize_t>(size);
    ::close(fd);
    return ok;
}

void checkSpec(const std::string& spec) {
    const auto pose = vtm::ground::readCameraPoseSpec(spec);
    if (!pose.ok) {
        return;
    }
    const double* q = pose.value.attitude_wxyz;
    const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (!(std::fabs(norm - 1.0) <= 1e-6)) {
        std::abort();
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 2U || !writeScratch(data + 2, size - 2U)) {
        return 0;
    }
    switch (data[0] % 4U) {
        case 0U:
            (void)vtm::ground::readCameraPoses(scratchPath());
            break;
        case 1U:
            (void)vtm::ground::readPoseLog(scratchPath());
            break;
        case 2U:
            checkSpec(scratchPath() + ":" + std::to_string(data[1]));
            break;
        default:
            checkSpec(scratchPath());
            break;
    }
    return 0;
}
