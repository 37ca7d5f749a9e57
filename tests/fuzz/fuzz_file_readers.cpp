// libFuzzer target (2): hal/file's readers. The first input byte picks the reader, the
// rest is the file: 0 PGM decoder, 1 PNG decoder (stb_image on the static pool),
// 2 frame manifest, 3 pose log (the text readers take a path: the bytes are written to
// a scratch file first). Properties: no crash, no sanitizer report, no assertion.
#include <fcntl.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "frame_target.hpp"
#include "hal/file/frame_manifest.hpp"
#include "pgm_decode.hpp"
#include "png_decode.hpp"
#include "pose_log.hpp"
#include "vtm/core/assert.hpp"

namespace {

using namespace vtm;
using namespace vtm::hal;

void abortOnAssert(const AssertInfo&) { std::abort(); }

const char* scratchPath() {
    static char path[64] = {};
    if (path[0] == '\0') {
        // tmpfs when there is one: a file rewritten per input on a disk file system
        // (ext4 here) costs milliseconds, a hundred times the parse.
        const char* dir = ::access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
        std::snprintf(path, sizeof(path), "%s/vtm_fuzz_file_%d.txt", dir, static_cast<int>(::getpid()));
    }
    return path;
}

bool writeScratch(const std::uint8_t* data, std::size_t size) {
    const int fd = ::open(scratchPath(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    if (fd < 0) {
        return false;
    }
    const bool ok = ::write(fd, data, size) == static_cast<ssize_t>(size);
    ::close(fd);
    return ok;
}

void decodeImage(std::uint8_t which, const std::uint8_t* data, std::size_t size) {
    // Output sizes a manifest might declare: small, so each run is fast.
    static std::uint8_t px8[64 * 64];
    static std::uint16_t px16[64 * 64];
    const std::int32_t w = 1 + (size > 1U ? data[size - 1U] % 64 : 0);
    const std::int32_t h = 1 + (size > 2U ? data[size - 2U] % 64 : 0);
    const bool wide = size > 3U && (data[size - 3U] & 1U) != 0U;
    const detail::FrameTarget target = wide ? detail::FrameTarget(ImageView<std::uint16_t>(px16, w, h), 12U)
                                            : detail::FrameTarget(ImageView<std::uint8_t>(px8, w, h));
    if (which == 0U) {
        (void)detail::decodePgm(data, size, target);
    } else {
        (void)detail::decodePng(data, size, target);
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    (void)setAssertHook(abortOnAssert);
    if (size < 1U) {
        return 0;
    }
    const std::uint8_t which = data[0] % 4U;
    const std::uint8_t* file = data + 1;
    const std::size_t file_size = size - 1U;
    if (which <= 1U) {
        decodeImage(which, file, file_size);
        return 0;
    }
    if (!writeScratch(file, file_size)) {
        return 0;
    }
    if (which == 2U) {
        static FrameManifest manifest;
        (void)loadFrameManifest(scratchPath(), manifest);
    } else {
        static FixedVector<PoseEstimate, file_limits::kMaxPoses> poses;
        (void)detail::loadPoseLog(scratchPath(), poses);
    }
    return 0;
}
