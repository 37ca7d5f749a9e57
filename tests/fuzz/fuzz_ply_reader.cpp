// libFuzzer target (6): tools/ground's PLY point reader (user files for `vtm integrate`),
// decodePlyPoints on the input bytes as a file's contents. Properties: no crash, no
// sanitizer report, no assertion; an accepted file has at most kMaxPlyVertices points.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "vtm/core/assert.hpp"
#include "vtm/ground/ply_reader.hpp"

namespace {

void abortOnAssert(const vtm::AssertInfo&) { std::abort(); }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    (void)vtm::setAssertHook(abortOnAssert);
    const std::vector<unsigned char> bytes(data, data + size);
    const vtm::ground::Result<std::vector<vtm::Vec3>> r = vtm::ground::decodePlyPoints(bytes, "fuzz.ply");
    if (r.ok && r.value.size() > vtm::ground::kMaxPlyVertices) {
        std::abort();
    }
    if (!r.ok && r.error.empty()) {
        std::abort();  // every refusal names a reason
    }
    return 0;
}
