// The render cache (sim/render_cache.hpp) with its file store (tests/support
// render_cache_file.hpp): a frame read back is the frame renderFrame renders, byte for
// byte, in every view and only in the band asked for; any change of the request changes
// the key; a damaged file is a miss that renders; no heap on either path.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include "no_heap_guard.hpp"
#include "render_cache_file.hpp"
#include "sim/render.hpp"
#include "sim/render_cache.hpp"
#include "sim/terrain.hpp"
#include "terrain_pool.hpp"
#include "vtm/core/camera_model.hpp"

namespace vtm::sim {
namespace {

constexpr std::int32_t kW = 40;
constexpr std::int32_t kH = 30;

TerrainParams worldParams() {
    TerrainParams p = defaultMarsTerrainParams();
    p.seed = 5U;
    p.finest_cell_m = 0.02;
    p.samples_log2 = 6;
    p.levels = 6;
    p.rock_region_radius_m = 5.0;
    return p;
}

FrameRequest request(int bit_depth) {
    FrameRequest r;
    r.terrain = &terrainInPool(worldParams(), 0);
    r.model = makePinhole(kW, kH, 60.0);
    r.pose = poseLookingAt(Vec3(0.0, 0.0, -1.5), Vec3(4.0, 0.5, 0.0));
    r.sensor.bit_depth = bit_depth;
    r.frame_index = 3U;
    r.first_row = 4;
    r.row_count = 20;
    return r;
}

// Every view renderFrame can write, filled with a pattern it never writes.
struct Buffers {
    explicit Buffers(std::uint8_t fill)
        : image8(kW * kH, fill), image16(kW * kH, fill), range(kW * kH), depth(kW * kH), point(3 * kW * kH),
          normal(3 * kW * kH) {
        for (std::vector<float>* v : {&range, &depth, &point, &normal}) {
            std::memset(v->data(), fill, v->size() * sizeof(float));
        }
    }
    FrameOutput output(int bit_depth, bool truth) {
        FrameOutput o;
        if (bit_depth == 8) {
            o.image8 = ImageView<std::uint8_t>(image8.data(), kW, kH);
        } else {
            o.image16 = ImageView<std::uint16_t>(image16.data(), kW, kH);
        }
        if (truth) {
            o.truth.range_m = ImageView<float>(range.data(), kW, kH);
            o.truth.depth_m = ImageView<float>(depth.data(), kW, kH);
            o.truth.point_site_m = ImageView<float>(point.data(), 3 * kW, kH);
            o.truth.normal_site = ImageView<float>(normal.data(), 3 * kW, kH);
        }
        return o;
    }
    bool sameBytes(const Buffers& o) const {
        auto same = [](const auto& a, const auto& b) {
            return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0;
        };
        return same(image8, o.image8) && same(image16, o.image16) && same(range, o.range) && same(depth, o.depth) &&
               same(point, o.point) && same(normal, o.normal);
    }
    std::vector<std::uint8_t> image8;
    std::vector<std::uint16_t> image16;
    std::vector<float> range, depth, point, normal;
};

bool sameStats(const RenderStats& a, const RenderStats& b) {
    return a.hit_pixels == b.hit_pixels && a.sky_pixels == b.sky_pixels && a.shadowed_pixels == b.shadowed_pixels &&
           a.saturated_pixels == b.saturated_pixels && a.bad_ray_pixels == b.bad_ray_pixels;
}

// A fresh directory under $TMPDIR (or /tmp) for one test's cache, removed with the files
// in it when the test ends.
class TempDirectory {
public:
    TempDirectory() {
        const char* tmp = std::getenv("TMPDIR");
        std::string pattern = std::string(tmp != nullptr && tmp[0] != '\0' ? tmp : "/tmp") + "/vtm_render_cache_XXXXXX";
        std::vector<char> buf(pattern.begin(), pattern.end());
        buf.push_back('\0');
        const char* made = ::mkdtemp(buf.data());
        EXPECT_NE(made, nullptr) << pattern;
        path_ = made != nullptr ? std::string(made) : std::string();
    }
    ~TempDirectory() {
        if (!path_.empty()) {
            std::error_code ignored;
            std::filesystem::remove_all(path_, ignored);
        }
    }
    TempDirectory(const TempDirectory&) = delete;
    TempDirectory& operator=(const TempDirectory&) = delete;
    [[nodiscard]] const std::string& path() const { return path_; }

private:
    std::string path_;
};

// Installs a cache for one test and takes it away after.
class CacheScope {
public:
    explicit CacheScope(test::FileRenderCache& cache) { setRenderCache(&cache); }
    ~CacheScope() { setRenderCache(nullptr); }
    CacheScope(const CacheScope&) = delete;
    CacheScope& operator=(const CacheScope&) = delete;
};

void roundTrip(int bit_depth) {
    SCOPED_TRACE(bit_depth);
    const FrameRequest r = request(bit_depth);
    Buffers reference(0xA5U);
    RenderStats reference_stats;
    ASSERT_EQ(renderCache(), nullptr);
    ASSERT_TRUE(renderFrame(r, reference.output(bit_depth, true), &reference_stats).isOk());
    ASSERT_GT(reference_stats.hit_pixels, 0);

    const TempDirectory dir;
    test::FileRenderCache cache(dir.path().c_str());
    ASSERT_TRUE(cache.usable());
    const CacheScope scope(cache);
    Buffers rendered(0xA5U);
    RenderStats rendered_stats;
    {
        const test::NoHeapScope guard;
        ASSERT_TRUE(renderFrame(r, rendered.output(bit_depth, true), &rendered_stats).isOk());
        EXPECT_EQ(guard.heapCalls(), 0U);
    }
    EXPECT_EQ(cache.misses(), 1U);
    EXPECT_EQ(cache.stores(), 1U);
    EXPECT_TRUE(rendered.sameBytes(reference));
    EXPECT_TRUE(sameStats(rendered_stats, reference_stats));

    Buffers loaded(0xA5U);  // rows outside the band must keep this pattern
    RenderStats loaded_stats;
    {
        const test::NoHeapScope guard;
        ASSERT_TRUE(renderFrame(r, loaded.output(bit_depth, true), &loaded_stats).isOk());
        EXPECT_EQ(guard.heapCalls(), 0U);
    }
    EXPECT_EQ(cache.hits(), 1U);
    EXPECT_TRUE(loaded.sameBytes(reference));
    EXPECT_TRUE(sameStats(loaded_stats, reference_stats));
}

TEST(RenderCache, AFrameReadBackIsTheRenderedFrameInEveryViewAndOnlyInItsBand8Bit) { roundTrip(8); }
TEST(RenderCache, AFrameReadBackIsTheRenderedFrameInEveryViewAndOnlyInItsBand12Bit) { roundTrip(12); }

TEST(RenderCache, EveryInputThatReachesAPixelChangesTheKey) {
    const FrameRequest base = request(8);
    Buffers b(0U);
    const FrameOutput with_truth = b.output(8, true);
    const std::uint64_t k0 = frameKey(base, with_truth);
    EXPECT_EQ(frameKey(request(8), b.output(8, true)), k0);  // the same request built again

    // The terrain enters through its parameters: a world that differs in one of them.
    TerrainParams other_albedo = worldParams();
    other_albedo.texture_contrast += 0.01;
    TerrainParams other_seed = worldParams();
    other_seed.seed += 1U;
    Terrain unbuilt_a;
    Terrain unbuilt_b;
    std::vector<std::byte> pool_a(Terrain::storageBytes(other_albedo));
    std::vector<std::byte> pool_b(Terrain::storageBytes(other_seed));
    Arena arena_a(pool_a.data(), pool_a.size());
    Arena arena_b(pool_b.data(), pool_b.size());
    ASSERT_TRUE(unbuilt_a.build(other_albedo, arena_a).isOk());
    ASSERT_TRUE(unbuilt_b.build(other_seed, arena_b).isOk());

    std::vector<FrameRequest> changed(10, base);
    changed[0].terrain = &unbuilt_a;
    changed[1].terrain = &unbuilt_b;
    changed[2].model.fx_px += 1e-9;
    changed[3].pose.t_m.x() += 1e-9;
    changed[4].lighting.shadows = false;
    changed[5].sensor.noise_seed += 1U;
    changed[6].frame_index += 1U;
    changed[7].first_row += 1;
    changed[8].max_range_m *= 0.5;
    changed[9].sensor.read_noise_e += 1.0;
    for (std::size_t i = 0; i < changed.size(); ++i) {
        EXPECT_NE(frameKey(changed[i], with_truth), k0) << "change " << i;
    }
    FrameOutput fewer = with_truth;
    fewer.truth.normal_site = ImageView<float>();
    EXPECT_NE(frameKey(base, fewer), k0);
}

TEST(RenderCache, ADamagedFileIsAMissAndTheFrameIsRendered) {
    const FrameRequest r = request(8);
    Buffers reference(0x11U);
    ASSERT_TRUE(renderFrame(r, reference.output(8, true), nullptr).isOk());

    const TempDirectory dir;
    test::FileRenderCache cache(dir.path().c_str());
    const CacheScope scope(cache);
    Buffers first(0x11U);
    ASSERT_TRUE(renderFrame(r, first.output(8, true), nullptr).isOk());
    ASSERT_EQ(cache.stores(), 1U);

    // Flip one byte in the middle of the stored frame.
    char path[test::FileRenderCache::kMaxDirChars + 32];
    ASSERT_TRUE(cache.framePath(frameKey(r, first.output(8, true)), path, sizeof path));
    const int fd = ::open(path, O_RDWR);
    ASSERT_GE(fd, 0) << path;
    const off_t size = ::lseek(fd, 0, SEEK_END);
    std::uint8_t byte = 0U;
    ASSERT_EQ(::pread(fd, &byte, 1, size / 2), 1);
    byte = static_cast<std::uint8_t>(byte ^ 0x40U);
    ASSERT_EQ(::pwrite(fd, &byte, 1, size / 2), 1);
    ::close(fd);

    Buffers second(0x11U);
    ASSERT_TRUE(renderFrame(r, second.output(8, true), nullptr).isOk());
    EXPECT_EQ(cache.hits(), 0U);
    EXPECT_EQ(cache.misses(), 2U);
    EXPECT_TRUE(second.sameBytes(reference));
}

TEST(RenderCache, NoDirectoryNoCache) {
    EXPECT_FALSE(test::FileRenderCache(nullptr).usable());
    EXPECT_FALSE(test::FileRenderCache("").usable());
    const std::string too_long(test::FileRenderCache::kMaxDirChars, 'x');
    EXPECT_FALSE(test::FileRenderCache(too_long.c_str()).usable());
}

}  // namespace
}  // namespace vtm::sim
