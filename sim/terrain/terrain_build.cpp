// Terrain::build(): carves the grids from the arena and fills them, coarsest level
// first, because each finer level blends its outer band towards the coarser one.
#include <algorithm>
#include <cmath>

#include "noise.hpp"
#include "terrain_model.hpp"
#include "vtm/core/random.hpp"

namespace vtm::sim {

class TerrainBuilder {
public:
    TerrainBuilder(Terrain& terrain, Span<float> scratch, Span<TerrainRock> rocks) noexcept
        : t_(terrain), p_(terrain.params_), scratch_(scratch), rocks_(rocks),
          rock_density_(model::rockNumberDensity(terrain.params_)) {}

    void buildLevel(int k) noexcept {
        fillBase(k);
        if (p_.kind == TerrainKind::kMars) {
            stampCraters(k);
            stampRocks(k);
        }
        if (k + 1 < t_.levels_) {
            blendWithCoarser(k);
        }
        buildMips(k);
    }

private:
    [[nodiscard]] std::size_t side() const noexcept { return static_cast<std::size_t>(t_.n_) + 1U; }
    [[nodiscard]] std::size_t index(std::int32_t i, std::int32_t j) const noexcept {
        return static_cast<std::size_t>(i) * side() + static_cast<std::size_t>(j);
    }
    // Offset of sample index i from the centre (metres): (i - n/2) * cell, exact for
    // dyadic cells.
    [[nodiscard]] double offset(int k, std::int32_t i) const noexcept {
        return (static_cast<double>(i) - 0.5 * static_cast<double>(t_.n_)) * t_.level_[k].cell_m;
    }
    static std::uint16_t quantiseAlbedo(double a) noexcept {
        const double c = a < 0.0 ? 0.0 : (a > 1.0 ? 1.0 : a);
        return static_cast<std::uint16_t>(std::floor(c * 65535.0 + 0.5));
    }
    // Sample index range [lo, hi] covering [centre_offset - reach, centre_offset + reach].
    void sampleRange(int k, double centre_offset_m, double reach_m, std::int32_t& lo, std::int32_t& hi) const noexcept {
        const double cell = t_.level_[k].cell_m;
        const double half = 0.5 * static_cast<double>(t_.n_);
        const double a = std::ceil((centre_offset_m - reach_m) / cell + half);
        const double b = std::floor((centre_offset_m + reach_m) / cell + half);
        lo = static_cast<std::int32_t>(std::max(a, 0.0));
        hi = static_cast<std::int32_t>(std::min(b, static_cast<double>(t_.n_)));
    }

    void fillBase(int k) noexcept {
        Terrain::Level& lv = t_.level_[k];
        const model::GroundModel ground(p_, lv.cell_m);
        for (std::int32_t i = 0; i <= t_.n_; ++i) {  // bound: n + 1 rows
            const double dn = offset(k, i);
            for (std::int32_t j = 0; j <= t_.n_; ++j) {  // bound: n + 1 columns
                const double de = offset(k, j);
                double h = 0.0;
                if (p_.kind == TerrainKind::kPlane) {
                    h = model::planeElevation(p_, dn, de);
                } else if (p_.kind == TerrainKind::kDome) {
                    h = model::domeElevation(p_, dn, de);
                } else {
                    h = p_.base_elevation_m + ground.relief(p_.centre_north_m + dn, p_.centre_east_m + de);
                }
                const std::size_t idx = index(i, j);
                lv.height_m[idx] = static_cast<float>(h);
                lv.albedo[idx] = quantiseAlbedo(ground.albedo(p_.centre_north_m + dn, p_.centre_east_m + de));
            }
        }
    }

    void stampCrater(int k, const model::Crater& c, double weight) noexcept {
        Terrain::Level& lv = t_.level_[k];
        const double cn = c.north_m - p_.centre_north_m;
        const double ce = c.east_m - p_.centre_east_m;
        std::int32_t i0 = 0;
        std::int32_t i1 = -1;
        std::int32_t j0 = 0;
        std::int32_t j1 = -1;
        sampleRange(k, cn, c.diameter_m, i0, i1);
        sampleRange(k, ce, c.diameter_m, j0, j1);
        for (std::int32_t i = i0; i <= i1; ++i) {  // bound: n + 1 rows
            const double dn = offset(k, i) - cn;
            for (std::int32_t j = j0; j <= j1; ++j) {  // bound: n + 1 columns
                const double de = offset(k, j) - ce;
                const double r = std::sqrt(dn * dn + de * de);
                const std::size_t idx = index(i, j);
                const double h = static_cast<double>(lv.height_m[idx]) + weight * model::craterProfile(c, r);
                lv.height_m[idx] = static_cast<float>(h);
            }
        }
    }

    // Every crater of the bins that level k resolves, regenerated from (seed, bin).
    void stampCraters(int k) noexcept {
        const double cell = t_.level_[k].cell_m;
        const double slope = p_.crater_sfd_slope;
        for (int b = k; b < t_.levels_; ++b) {  // bound: levels
            const model::CraterBin bin = model::craterBin(p_, b);
            Random rng(noise::hash(p_.seed, noise::Stream::kCraters, b, 0));
            const double lo_pow = model::power(bin.lo_m, -slope);
            const double hi_pow = model::power(bin.hi_m, -slope);
            for (std::int64_t c = 0; c < bin.count; ++c) {  // bound: count <= kMaxCratersPerBin (validate)
                const double un = rng.uniform01();
                const double ue = rng.uniform01();
                const double ud = rng.uniform01();
                const double u_depth = rng.uniform01();
                const double u_rim = rng.uniform01();
                model::Crater crater{};
                crater.north_m = p_.centre_north_m + (2.0 * un - 1.0) * bin.half_m;
                crater.east_m = p_.centre_east_m + (2.0 * ue - 1.0) * bin.half_m;
                // Truncated power law N(>D) ~ D^-slope by its inverse CDF.
                crater.diameter_m = model::power(lo_pow - ud * (lo_pow - hi_pow), -1.0 / slope);
                crater.depth_m = p_.crater_depth_ratio * crater.diameter_m * (0.7 + 0.6 * u_depth);
                crater.rim_m = p_.crater_rim_ratio * crater.diameter_m * (0.7 + 0.6 * u_rim);
                const double weight = noise::octaveWeight(crater.diameter_m, cell);
                if (weight > 0.0) {
                    stampCrater(k, crater, weight);
                }
            }
        }
    }

    void stampRock(int k, const TerrainRock& r, double weight) noexcept {
        Terrain::Level& lv = t_.level_[k];
        const double cn = r.north_m - p_.centre_north_m;
        const double ce = r.east_m - p_.centre_east_m;
        std::int32_t i0 = 0;
        std::int32_t i1 = -1;
        std::int32_t j0 = 0;
        std::int32_t j1 = -1;
        sampleRange(k, cn, model::rockReach_m(r), i0, i1);
        sampleRange(k, ce, model::rockReach_m(r), j0, j1);
        const std::uint16_t albedo = quantiseAlbedo(r.albedo);
        for (std::int32_t i = i0; i <= i1; ++i) {  // bound: n + 1 rows
            const double north = p_.centre_north_m + offset(k, i);
            for (std::int32_t j = j0; j <= j1; ++j) {  // bound: n + 1 columns
                const double h = weight * model::rockProfile(r, north, p_.centre_east_m + offset(k, j));
                const std::size_t idx = index(i, j);
                if (h > 0.0 && h > static_cast<double>(scratch_[idx])) {
                    scratch_[idx] = static_cast<float>(h);
                    lv.albedo[idx] = albedo;
                }
            }
        }
    }

    // Rocks resolvable on level k (diameter >= 1.5 cells, full height from 3 cells),
    // combined by max() in the scratch layer, then added to the ground.
    void stampRocks(int k) noexcept {
        Terrain::Level& lv = t_.level_[k];
        const double cell = lv.cell_m;
        if (!(rock_density_ > 0.0) || p_.rock_max_diameter_m < 1.5 * cell || p_.rock_region_radius_m <= 0.0) {
            return;
        }
        std::fill(scratch_.begin(), scratch_.end(), 0.0F);
        const double half = 0.5 * static_cast<double>(t_.n_) * cell;
        const double reach = std::min(half, p_.rock_region_radius_m) + 0.7 * p_.rock_max_diameter_m;
        const auto t0 = static_cast<std::int64_t>(std::floor(-reach / kRockTile_m));
        const auto t1 = static_cast<std::int64_t>(std::floor(reach / kRockTile_m));
        for (std::int64_t tn = t0; tn <= t1; ++tn) {  // bound: (2 * 2000 m + 6 m) / 4 m tiles (validate)
            for (std::int64_t te = t0; te <= t1; ++te) {  // bound: same
                const std::size_t count = model::rocksInTile(p_, rock_density_, tn, te, rocks_);
                for (std::size_t r = 0U; r < count; ++r) {  // bound: kMaxRocksPerTile
                    const double weight = noise::smoothstep((rocks_[r].diameter_m / cell - 1.5) / 1.5);
                    if (weight > 0.0) {
                        stampRock(k, rocks_[r], weight);
                    }
                }
            }
        }
        const std::size_t count = side() * side();
        for (std::size_t idx = 0U; idx < count; ++idx) {  // bound: (n + 1)^2
            if (scratch_[idx] > 0.0F) {
                lv.height_m[idx] =
                    static_cast<float>(static_cast<double>(lv.height_m[idx]) + static_cast<double>(scratch_[idx]));
            }
        }
    }

    // Bilinear value of a coarser level's grid at grid coordinates (u, v), both inside.
    template <typename T>
    [[nodiscard]] double bilinear(const T* grid, double u, double v) const noexcept {
        const double fu = std::min(std::floor(u), static_cast<double>(t_.n_ - 1));
        const double fv = std::min(std::floor(v), static_cast<double>(t_.n_ - 1));
        const auto i = static_cast<std::int32_t>(fu);
        const auto j = static_cast<std::int32_t>(fv);
        const double a = u - fu;
        const double b = v - fv;
        const double h00 = static_cast<double>(grid[index(i, j)]);
        const double h10 = static_cast<double>(grid[index(i + 1, j)]);
        const double h01 = static_cast<double>(grid[index(i, j + 1)]);
        const double h11 = static_cast<double>(grid[index(i + 1, j + 1)]);
        return (h00 + a * (h10 - h00)) + b * ((h01 + a * (h11 - h01)) - (h00 + a * (h10 - h00)));
    }

    // Outer band (n/8 samples) of level k eased towards level k+1, equal on the border.
    void blendWithCoarser(int k) noexcept {
        Terrain::Level& lv = t_.level_[k];
        const Terrain::Level& coarse = t_.level_[k + 1];
        const std::int32_t n = t_.n_;
        const std::int32_t band = n / 8;
        const double quarter = 0.25 * static_cast<double>(n);
        for (std::int32_t i = 0; i <= n; ++i) {  // bound: n + 1 rows
            for (std::int32_t j = 0; j <= n; ++j) {  // bound: n + 1 columns
                const std::int32_t d = std::min(std::min(i, j), std::min(n - i, n - j));
                if (d >= band) {
                    continue;
                }
                const double w = noise::smoothstep(static_cast<double>(d) / static_cast<double>(band));
                const double u = 0.5 * static_cast<double>(i) + quarter;
                const double v = 0.5 * static_cast<double>(j) + quarter;
                const std::size_t idx = index(i, j);
                const double hc = bilinear(coarse.height_m, u, v);
                lv.height_m[idx] = static_cast<float>(hc + w * (static_cast<double>(lv.height_m[idx]) - hc));
                const double ac = bilinear(coarse.albedo, u, v);
                lv.albedo[idx] = static_cast<std::uint16_t>(
                    std::floor(ac + w * (static_cast<double>(lv.albedo[idx]) - ac) + 0.5));
            }
        }
    }

    // mip m >= 1 holds, per block of 2^m x 2^m cells, the largest sample height in it
    // (a bilinear patch never exceeds its corners).
    void buildMips(int k) noexcept {
        Terrain::Level& lv = t_.level_[k];
        const std::int32_t cells1 = t_.n_ / 2;
        for (std::int32_t ci = 0; ci < cells1; ++ci) {  // bound: n / 2
            for (std::int32_t cj = 0; cj < cells1; ++cj) {  // bound: n / 2
                float m = lv.height_m[index(2 * ci, 2 * cj)];
                for (std::int32_t a = 0; a <= 2; ++a) {  // bound: 3
                    for (std::int32_t b = 0; b <= 2; ++b) {  // bound: 3
                        m = std::max(m, lv.height_m[index(2 * ci + a, 2 * cj + b)]);
                    }
                }
                lv.mip_max_m[1][static_cast<std::size_t>(ci) * static_cast<std::size_t>(cells1) +
                                static_cast<std::size_t>(cj)] = m;
            }
        }
        for (int mip = 2; mip <= t_.n_log2_; ++mip) {  // bound: samples_log2
            const std::size_t cells = static_cast<std::size_t>(t_.n_) >> static_cast<unsigned>(mip);
            const float* below = lv.mip_max_m[mip - 1];
            for (std::size_t ci = 0U; ci < cells; ++ci) {  // bound: n >> mip
                for (std::size_t cj = 0U; cj < cells; ++cj) {  // bound: n >> mip
                    const std::size_t b0 = 2U * ci * 2U * cells + 2U * cj;
                    const std::size_t b1 = b0 + 2U * cells;
                    lv.mip_max_m[mip][ci * cells + cj] =
                        std::max(std::max(below[b0], below[b0 + 1U]), std::max(below[b1], below[b1 + 1U]));
                }
            }
        }
    }

    Terrain& t_;
    const TerrainParams& p_;
    Span<float> scratch_;
    Span<TerrainRock> rocks_;
    double rock_density_;
};

Status Terrain::build(const TerrainParams& params, Arena& arena) noexcept {
    built_ = false;
    VTM_RETURN_IF_ERROR(params.validate());
    params_ = params;
    n_log2_ = params.samples_log2;
    n_ = std::int32_t{1} << static_cast<unsigned>(n_log2_);
    levels_ = params.levels;
    const std::size_t n = static_cast<std::size_t>(n_);
    const std::size_t samples = (n + 1U) * (n + 1U);
    for (int k = 0; k < levels_; ++k) {  // bound: levels <= kMaxTerrainLevels
        Level& lv = level_[k];
        lv = Level{};
        lv.cell_m = params.finest_cell_m * static_cast<double>(std::int64_t{1} << static_cast<unsigned>(k));
        lv.height_m = arena.allocateArray<float>(samples).data();
        lv.albedo = arena.allocateArray<std::uint16_t>(samples).data();
        bool ok = lv.height_m != nullptr && lv.albedo != nullptr;
        for (int m = 1; m <= n_log2_; ++m) {  // bound: samples_log2
            const std::size_t cells = n >> static_cast<unsigned>(m);
            lv.mip_max_m[m] = arena.allocateArray<float>(cells * cells).data();
            ok = ok && lv.mip_max_m[m] != nullptr;
        }
        if (!ok) {
            return Status(StatusCode::kOutOfMemory, "arena: smaller than Terrain::storageBytes(params)",
                          static_cast<std::int64_t>(storageBytes(params)));
        }
    }
    const Span<float> scratch = arena.allocateArray<float>(samples);
    const Span<TerrainRock> rocks = arena.allocateArray<TerrainRock>(kMaxRocksPerTile);
    if (scratch.data() == nullptr || rocks.data() == nullptr) {
        return Status(StatusCode::kOutOfMemory, "arena: smaller than Terrain::storageBytes(params)",
                      static_cast<std::int64_t>(storageBytes(params)));
    }
    texture_octaves_ = 0;
    texture_norm_ = 0.0;
    double wavelength = params.texture_longest_wavelength_m;
    double amplitude = 1.0;
    // Octaves from the longest texture wavelength down to the finest (validate: <= 24).
    while (texture_octaves_ < model::kMaxTextureOctaves &&
           wavelength >= params.texture_finest_wavelength_m * (1.0 - 1e-9)) {  // bound: kMaxTextureOctaves
        ++texture_octaves_;
        texture_norm_ += amplitude;
        wavelength *= 0.5;
        amplitude *= 0.7;  // kTextureGain in terrain_query.cpp
    }
    TerrainBuilder builder(*this, scratch, rocks);
    for (int k = levels_ - 1; k >= 0; --k) {  // bound: levels
        builder.buildLevel(k);
    }
    built_ = true;
    return Status::ok();
}

}  // namespace vtm::sim
