#include "scene_fixture.hpp"

#include <cmath>
#include <cstddef>

namespace vtm::tiepoints::test {

const Scene& scene() {
    static Scene* built = [] {
        auto* s = new Scene();
        static std::vector<std::byte> pool(8U << 20U);
        static Arena arena(pool.data(), pool.size());
        static sim::Terrain terrain;
        if (!terrain.build(vtm::test::panoramaTerrainParams(s->spec), arena).isOk()) {
            return s;
        }
        s->model = makePinhole(static_cast<std::uint16_t>(s->spec.width), static_cast<std::uint16_t>(s->spec.height),
                               s->spec.hfov_deg);
        const auto n = static_cast<std::size_t>(s->spec.width * s->spec.height);
        bool ok = true;
        for (std::int32_t k = 0; k < kStations; ++k) {
            vtm::test::truePoses(s->spec, terrain, k, s->left[k], s->right[k]);
            s->stations[k] = vtm::test::approximateStation(s->spec, s->model, s->left[k], s->right[k], k);
            auto& l = s->pixels[2 * k];
            auto& r = s->pixels[2 * k + 1];
            l.assign(n, 0U);
            r.assign(n, 0U);
            s->range[k].assign(n, 0.0F);
            ok = ok && vtm::test::renderEye(s->spec, terrain, s->model, s->left[k], static_cast<std::uint32_t>(2 * k),
                                            l.data(), s->range[k].data())
                           .isOk();
            ok = ok && vtm::test::renderEye(s->spec, terrain, s->model, s->right[k],
                                            static_cast<std::uint32_t>(2 * k + 1), r.data(), nullptr)
                           .isOk();
            s->images[k].left = ImageView<const std::uint8_t>(l.data(), s->spec.width, s->spec.height);
            s->images[k].right = ImageView<const std::uint8_t>(r.data(), s->spec.width, s->spec.height);
        }
        s->ok = ok;
        return s;
    }();
    return *built;
}

Config sceneConfig() {
    Config c;
    c.max_width = 256;
    c.max_height = 256;
    c.max_stations = kStations;
    c.max_observations = 2048;
    c.detector.grid_cols = 12;
    c.detector.grid_rows = 12;
    c.detector.per_cell = 2;
    c.detector.max_features = 256;
    c.matcher.pyramid_levels = 1;
    c.range_min_m = 1.0;
    c.range_max_m = 60.0;
    c.map_cell_m = 0.5;
    c.map_side = 64;
    return c;
}

bool trueRange(const Scene& s, std::int32_t station, const Vec2& pixel, double& range_m) {
    const std::int32_t w = s.spec.width;
    const std::int32_t h = s.spec.height;
    const auto x0 = static_cast<std::int32_t>(std::floor(pixel.x()));
    const auto y0 = static_cast<std::int32_t>(std::floor(pixel.y()));
    if (x0 < 0 || y0 < 0 || x0 + 1 >= w || y0 + 1 >= h) {
        return false;
    }
    const std::vector<float>& r = s.range[station];
    const double v00 = r[static_cast<std::size_t>(y0 * w + x0)];
    const double v10 = r[static_cast<std::size_t>(y0 * w + x0 + 1)];
    const double v01 = r[static_cast<std::size_t>((y0 + 1) * w + x0)];
    const double v11 = r[static_cast<std::size_t>((y0 + 1) * w + x0 + 1)];
    const double lo = std::fmin(std::fmin(v00, v10), std::fmin(v01, v11));
    const double hi = std::fmax(std::fmax(v00, v10), std::fmax(v01, v11));
    if (!std::isfinite(lo) || !std::isfinite(hi) || hi > 1.03 * lo) {
        return false;
    }
    const double fx = pixel.x() - x0;
    const double fy = pixel.y() - y0;
    range_m = (1 - fy) * ((1 - fx) * v00 + fx * v10) + fy * ((1 - fx) * v01 + fx * v11);
    return true;
}

bool trueGround(const Scene& s, std::int32_t station, const Vec2& pixel, Vec3& site_m) {
    double range = 0.0;
    CameraRay ray;
    if (!trueRange(s, station, pixel, range) || !backProjectPixel(s.model, pixel, ray).isOk()) {
        return false;
    }
    site_m = transformPoint(s.left[station], ray.origin_m + range * ray.direction);
    return true;
}

}  // namespace vtm::tiepoints::test
