// Installs a FileRenderCache on the directory $VTM_RENDER_CACHE names, for the whole
// process, when the variable is set and not empty (tools/test.sh sets it; a plain ctest
// run renders every frame). Linked, as an object library, into the test executables
// that vtm_add_test(... RENDER_CACHE) marks: those whose scenes are inputs, not the
// renderer's own tests nor the determinism suite (docs/sim-render.md "Render cache").
#include <cstdlib>

#include "render_cache_file.hpp"

namespace vtm::test {
namespace {

struct Installation {
    Installation() noexcept : cache(std::getenv("VTM_RENDER_CACHE")) {
        if (cache.usable()) {
            sim::setRenderCache(&cache);
        }
    }
    ~Installation() { sim::setRenderCache(nullptr); }
    Installation(const Installation&) = delete;
    Installation& operator=(const Installation&) = delete;
    FileRenderCache cache;
};

Installation g_installation;

}  // namespace
}  // namespace vtm::test
