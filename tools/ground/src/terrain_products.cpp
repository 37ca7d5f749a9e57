#include "vtm/ground/terrain_products.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cerrno>
#include <cstring>

#include "vtm/ground/disparity_colormap.hpp"

namespace vtm::ground {

FloatImage elevationImage(const terrain::HeightMap& map) {
    const terrain::GridConfig& g = map.grid();
    FloatImage out(g.cols, g.rows);
    for (std::int32_t row = 0; row < g.rows; ++row) {
        for (std::int32_t col = 0; col < g.cols; ++col) out.at(col, row) = map.elevation(col, row);
    }
    return out;
}

FloatImage cropToFinite(const FloatImage& g) {
    std::int32_t x0 = g.width, y0 = g.height, x1 = -1, y1 = -1;
    for (std::int32_t y = 0; y < g.height; ++y) {
        for (std::int32_t x = 0; x < g.width; ++x) {
            if (std::isfinite(g.at(x, y))) {
                x0 = std::min(x0, x);
                x1 = std::max(x1, x);
                y0 = std::min(y0, y);
                y1 = std::max(y1, y);
            }
        }
    }
    if (x1 < x0) return g;
    FloatImage out(x1 - x0 + 1, y1 - y0 + 1);
    for (std::int32_t y = y0; y <= y1; ++y) {
        for (std::int32_t x = x0; x <= x1; ++x) out.at(x - x0, y - y0) = g.at(x, y);
    }
    return out;
}

GreyImage shadedRelief(const FloatImage& elevation_m, double cell_m) {
    GreyImage out(elevation_m.width, elevation_m.height, 3, 0U);
    std::vector<float> values;
    for (const float v : elevation_m.pixels) {
        if (std::isfinite(v)) values.push_back(v);
    }
    if (values.empty() || !(cell_m > 0.0)) return out;
    std::sort(values.begin(), values.end());
    const float lo = values[values.size() / 100];
    const float hi = values[values.size() - 1 - values.size() / 100];
    // Sun direction (x east, y north, z up): from the north-west, 45 degrees up.
    const double s = std::sqrt(0.5);                // cos 45 = sin 45
    const double sun[3] = {-s * s, s * s, s};       // horizontal part toward the north-west
    const double sn = std::sqrt(sun[0] * sun[0] + sun[1] * sun[1] + sun[2] * sun[2]);
    for (std::int32_t y = 1; y + 1 < elevation_m.height; ++y) {
        for (std::int32_t x = 1; x + 1 < elevation_m.width; ++x) {
            const float c = elevation_m.at(x, y);
            if (!std::isfinite(c)) continue;
            // A missing neighbour takes the centre's value (a flat side, not a black seam).
            auto around = [&](std::int32_t u, std::int32_t v) {
                const float z = elevation_m.at(u, v);
                return std::isfinite(z) ? z : c;
            };
            const float e = around(x + 1, y), w = around(x - 1, y);
            const float n = around(x, y - 1), so = around(x, y + 1);
            // Surface normal from central differences: (-dz/dx, -dz/dy, 1), x east, y north.
            const double dzdx = static_cast<double>(e - w) / (2.0 * cell_m);
            const double dzdy = static_cast<double>(n - so) / (2.0 * cell_m);
            const double nn = std::sqrt(dzdx * dzdx + dzdy * dzdy + 1.0);
            const double lambert = std::max(0.0, (-dzdx * sun[0] - dzdy * sun[1] + sun[2]) / (nn * sn));
            const double shade = 0.3 + 0.7 * lambert;
            const Rgb rgb = disparityColor(c, lo, hi);
            for (int k = 0; k < 3; ++k) {
                out.at(x, y, k) = static_cast<std::uint8_t>(std::lround(std::min(255.0, rgb[static_cast<std::size_t>(k)] * shade)));
            }
        }
    }
    return out;
}

Outcome writePly(const std::string& path, const std::vector<Vec3>& points) {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (f == nullptr) return Outcome::failure(path + ": cannot open for writing: " + std::strerror(errno));
    const std::string header = "ply\nformat binary_little_endian 1.0\ncomment VTM terrain points, site frame "
                               "(x north, y east, z down), metres\nelement vertex " +
                               std::to_string(points.size()) +
                               "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
    bool ok = std::fwrite(header.data(), 1, header.size(), f) == header.size();
    for (std::size_t i = 0; ok && i < points.size(); ++i) {
        unsigned char bytes[12];
        for (int k = 0; k < 3; ++k) {
            const float v = static_cast<float>(points[i][k]);
            std::uint32_t u = 0U;
            std::memcpy(&u, &v, sizeof u);
            for (int b = 0; b < 4; ++b) {
                bytes[4 * k + b] = static_cast<unsigned char>((u >> (8 * b)) & 0xFFU);  // little-endian on any host
            }
        }
        ok = std::fwrite(bytes, 1, sizeof bytes, f) == sizeof bytes;
    }
    ok = (std::fclose(f) == 0) && ok;
    return ok ? Outcome::success() : Outcome::failure(path + ": write failed");
}

}  // namespace vtm::ground
