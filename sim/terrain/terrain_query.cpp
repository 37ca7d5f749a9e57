// Read-only queries of a built Terrain: elevation, shading normal, albedo, grid geometry
// and the content hash.
#include <cmath>
#include <cstring>

#include "noise.hpp"
#include "terrain_model.hpp"

namespace vtm::sim {
namespace {

constexpr double kTextureGain = 0.7;  // amplitude ratio per texture octave (finer = weaker)

double clampUnit(double a) noexcept { return a < 0.0 ? 0.0 : (a > 1.0 ? 1.0 : a); }

}  // namespace

double Terrain::cellSize_m(int level) const noexcept {
    return (level >= 0 && level < levels_) ? level_[level].cell_m : 0.0;
}

double Terrain::halfExtent_m(int level) const noexcept { return 0.5 * static_cast<double>(n_) * cellSize_m(level); }

int Terrain::governingLevel(double north_m, double east_m) const noexcept {
    if (!built_) {
        return -1;
    }
    // Offsets in level-0 cells: level k covers |offset| <= (n / 2) * 2^k exactly.
    const double sn = std::fabs((north_m - params_.centre_north_m) / params_.finest_cell_m);
    const double se = std::fabs((east_m - params_.centre_east_m) / params_.finest_cell_m);
    double half = 0.5 * static_cast<double>(n_);
    for (int k = 0; k < levels_; ++k) {  // bound: levels
        if (sn <= half && se <= half) {
            return k;
        }
        half *= 2.0;
    }
    return -1;
}

// Grid coordinate (0 .. n) on `level` of an offset from the centre given in level-0 cells.
double Terrain::gridU(int level, double d_finest_cells) const noexcept {
    return d_finest_cells / static_cast<double>(std::int64_t{1} << static_cast<unsigned>(level)) +
           0.5 * static_cast<double>(n_);
}

double Terrain::gridValue(int level, bool albedo, double u, double v) const noexcept {
    const double top = static_cast<double>(n_);
    const double cu = u < 0.0 ? 0.0 : (u > top ? top : u);
    const double cv = v < 0.0 ? 0.0 : (v > top ? top : v);
    const double fu = std::fmin(std::floor(cu), top - 1.0);
    const double fv = std::fmin(std::floor(cv), top - 1.0);
    const std::size_t side = static_cast<std::size_t>(n_) + 1U;
    const std::size_t i00 = static_cast<std::size_t>(fu) * side + static_cast<std::size_t>(fv);
    const double a = cu - fu;
    const double b = cv - fv;
    double h00 = 0.0;
    double h10 = 0.0;
    double h01 = 0.0;
    double h11 = 0.0;
    const Level& lv = level_[level];
    if (albedo) {
        h00 = static_cast<double>(lv.albedo[i00]) / 65535.0;
        h10 = static_cast<double>(lv.albedo[i00 + side]) / 65535.0;
        h01 = static_cast<double>(lv.albedo[i00 + 1U]) / 65535.0;
        h11 = static_cast<double>(lv.albedo[i00 + side + 1U]) / 65535.0;
    } else {
        h00 = static_cast<double>(lv.height_m[i00]);
        h10 = static_cast<double>(lv.height_m[i00 + side]);
        h01 = static_cast<double>(lv.height_m[i00 + 1U]);
        h11 = static_cast<double>(lv.height_m[i00 + side + 1U]);
    }
    // The same expression as the ray caster's patch: h00 + a dh_u + b dh_v + a b k.
    return h00 + a * (h10 - h00) + b * (h01 - h00) + a * b * (h11 - h10 - h01 + h00);
}

double Terrain::elevationAt(double north_m, double east_m) const noexcept {
    if (!built_) {
        return 0.0;
    }
    int k = governingLevel(north_m, east_m);
    k = k < 0 ? levels_ - 1 : k;
    const double sn = (north_m - params_.centre_north_m) / params_.finest_cell_m;
    const double se = (east_m - params_.centre_east_m) / params_.finest_cell_m;
    return gridValue(k, false, gridU(k, sn), gridU(k, se));
}

Vec3 Terrain::shadingNormal(double north_m, double east_m, double scale_m) const noexcept {
    const int k = governingLevel(north_m, east_m);
    const double cell = cellSize_m(k < 0 ? levels_ - 1 : k);
    const double h = scale_m > cell ? scale_m : cell;
    const double dn = (elevationAt(north_m + h, east_m) - elevationAt(north_m - h, east_m)) / (2.0 * h);
    const double de = (elevationAt(north_m, east_m + h) - elevationAt(north_m, east_m - h)) / (2.0 * h);
    // Surface z = -elevation(x, y); the upward normal is -(d elev/dx, d elev/dy, 1) normalised.
    const Vec3 n(-dn, -de, -1.0);
    return n / std::sqrt(n.squaredNorm());
}

double Terrain::albedoAt(double north_m, double east_m, double footprint_m) const noexcept {
    if (!built_) {
        return 0.0;
    }
    const double footprint = footprint_m > 0.0 ? footprint_m : 0.0;
    int k = governingLevel(north_m, east_m);
    k = k < 0 ? levels_ - 1 : k;
    // A coarser grid where a cell is below half the footprint: its rocks are the mean.
    while (k + 1 < levels_ && 2.0 * level_[k].cell_m < footprint) {  // bound: levels
        ++k;
    }
    const double sn = (north_m - params_.centre_north_m) / params_.finest_cell_m;
    const double se = (east_m - params_.centre_east_m) / params_.finest_cell_m;
    const double base = gridValue(k, true, gridU(k, sn), gridU(k, se));
    double sum = 0.0;
    double wavelength = params_.texture_longest_wavelength_m;
    double amplitude = 1.0;
    for (int o = 0; o < texture_octaves_; ++o) {  // bound: texture_octaves_ <= kMaxTextureOctaves
        // Full weight from two footprints up, none at one footprint (the octave's mean, 0).
        const double w = footprint > 0.0 ? noise::smoothstep(wavelength / footprint - 1.0) : 1.0;
        if (w <= 0.0) {
            break;
        }
        const noise::Rotation r = noise::octaveRotation(o + 3);
        const double x = (r.c * north_m - r.s * east_m) / wavelength;
        const double y = (r.s * north_m + r.c * east_m) / wavelength;
        sum += w * amplitude * noise::value(noise::hash(params_.seed, noise::Stream::kTexture, o, 0), x, y);
        wavelength *= 0.5;
        amplitude *= kTextureGain;
    }
    return clampUnit(base * (1.0 + params_.texture_contrast * 1.5 * sum / texture_norm_));
}

std::uint64_t Terrain::contentHash() const noexcept {
    std::uint64_t h = 0xCBF29CE484222325ULL;
    const auto eat = [&h](std::uint32_t word, int bytes) noexcept {
        for (int b = 0; b < bytes; ++b) {  // bound: 4 bytes, least significant first
            h ^= (word >> (8U * static_cast<unsigned>(b))) & 0xFFU;
            h *= 0x100000001B3ULL;
        }
    };
    if (!built_) {
        return h;
    }
    const std::size_t side = static_cast<std::size_t>(n_) + 1U;
    for (int k = 0; k < levels_; ++k) {  // bound: levels
        const Level& lv = level_[k];
        for (std::size_t i = 0U; i < side * side; ++i) {  // bound: (n + 1)^2
            std::uint32_t bits = 0U;
            std::memcpy(&bits, &lv.height_m[i], sizeof bits);
            eat(bits, 4);
            eat(lv.albedo[i], 2);
        }
        for (int m = 1; m <= n_log2_; ++m) {  // bound: samples_log2
            const std::size_t cells = static_cast<std::size_t>(n_) >> static_cast<unsigned>(m);
            for (std::size_t i = 0U; i < cells * cells; ++i) {  // bound: (n >> m)^2
                std::uint32_t bits = 0U;
                std::memcpy(&bits, &lv.mip_max_m[m][i], sizeof bits);
                eat(bits, 4);
            }
        }
    }
    return h;
}

}  // namespace vtm::sim
