// Measures of the traverse-and-descent fusion against the truth (fusion_measures.hpp).
#include "fusion_measures.hpp"
#include "command_support.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "vtm/core/rotation.hpp"
#include "vtm/ground/image_io.hpp"
#include "vtm/ground/terrain_products.hpp"

namespace vtm::traverse {

const char* const kBandNames[kBands] = {"0-5 m", "5-10 m", "10-20 m", ">= 20 m"};

namespace {

using tools::kDegPerRad;

// printf into a std::string (the report's and the test's tables).
template <typename... Args>
std::string format(const char* f, Args... args) {
    const int n = std::snprintf(nullptr, 0, f, args...);
    std::string out(static_cast<std::size_t>(n > 0 ? n : 0), '\0');
    if (n > 0) std::snprintf(out.data(), out.size() + 1U, f, args...);
    return out;
}
}  // namespace

RigidPose Truth::mapFromModel(std::size_t k) const {
    if (!isDescent(k)) return (*stops)[k].truth;
    RigidPose inv;
    inv.R = descent_error.R.transpose();
    inv.t_m = -(inv.R * descent_error.t_m);
    return inv;
}

std::vector<Vec3> Truth::modelPoints(std::size_t k) const {
    if (!isDescent(k)) return (*stops)[k].points;
    std::vector<Vec3> out;
    for (const Vec3& p : descent->points) out.push_back(descent_error.R * p + descent_error.t_m);
    return out;
}

double Truth::elevationInMap(double north_m, double east_m) const { return terrain->elevationAt(north_m, east_m); }

double Truth::distanceToStops(double north_m, double east_m) const {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < stops->size(); ++k) {
        const Vec3 p = (*stops)[k].truth.t_m;
        best = std::min(best, std::hypot(p.x() - north_m, p.y() - east_m));
    }
    return best;
}

double Truth::stepM(std::size_t k) const {
    const std::size_t i = std::min(k, stops->size() - 1);  // the descent (k == stops): the last stop's step
    const std::size_t j = i == 0 ? 1 : i - 1;
    return ((*stops)[i].truth.t_m - (*stops)[j].truth.t_m).norm();
}

Vec3 Truth::centroid(std::size_t k) const {
    const std::vector<Vec3> pts = modelPoints(k);
    Vec3 c = Vec3::Zero();
    for (const Vec3& p : pts) c += p;
    return c / static_cast<double>(std::max<std::size_t>(1U, pts.size()));
}

PoseError poseError(const Truth& truth, std::size_t k, const RigidPose& map_from_model) {
    const RigidPose t = truth.mapFromModel(k);
    const Vec3 c = truth.centroid(k);
    PoseError e;
    e.rotation_deg = kDegPerRad * rotationAngleRad(map_from_model.R, t.R);
    e.translation_m = ((map_from_model.R * c + map_from_model.t_m) - (t.R * c + t.t_m)).norm();
    e.translation_percent = 100.0 * e.translation_m / truth.stepM(k);
    return e;
}

std::vector<PoseError> poseErrors(const Truth& truth, const std::vector<app::AddResult>& results) {
    std::vector<PoseError> out;
    for (std::size_t k = 0; k < results.size(); ++k) out.push_back(poseError(truth, k, results[k].map_from_model));
    return out;
}

TargetCount countTargets(const Truth& truth, const std::vector<app::AddResult>& results) {
    TargetCount t;
    const std::vector<PoseError> e = poseErrors(truth, results);
    for (std::size_t k = 1; k < truth.stops->size(); ++k) {
        t.registered += results[k].registered ? 1 : 0;
        t.rotation_met += e[k].rotation_deg <= kRotationTarget_deg ? 1 : 0;
        t.translation_met += e[k].translation_percent <= kTranslationTarget_percent ? 1 : 0;
    }
    return t;
}

std::string stopTable(const Truth& truth, const std::vector<app::AddResult>& reg, const std::vector<app::AddResult>& nav,
                      const std::vector<double>& seconds) {
    std::string out =
        "| stop | points | step m | navigation error: rot deg / at centroid m | registered: rot deg | "
        "about site x / y / z deg | translation mm | % of step | overlap | RMS residual mm | map points | iterations | s |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    // (The descent's step column is the last stops' step: its translation is also given in mm.)
    for (std::size_t k = 0; k < reg.size(); ++k) {
        const PoseError n = poseError(truth, k, nav[k].map_from_model);
        const PoseError r = poseError(truth, k, reg[k].map_from_model);
        const std::string name = truth.isDescent(k) ? "descent" : std::to_string(k) + (k == 0 ? " (reference)" : "");
        const Vec3 v = kDegPerRad * rotationLog(reg[k].map_from_model.R * truth.mapFromModel(k).R.transpose());
        out += format("| %s | %zu | %.3f | %.3f / %.3f | %.4f%s | %.3f / %.3f / %.3f | %.1f | %.2f%s | %.2f | %.1f | %lld | %d | %.2f |\n",
                      name.c_str(), truth.modelPoints(k).size(), truth.stepM(k), n.rotation_deg, n.translation_m,
                      r.rotation_deg, r.rotation_deg <= kRotationTarget_deg ? "" : " (miss)", v.x(), v.y(), v.z(),
                      1000.0 * r.translation_m, r.translation_percent,
                      r.translation_percent <= kTranslationTarget_percent ? "" : " (miss)", reg[k].icp.overlap,
                      1000.0 * reg[k].icp.rms_residual_m, static_cast<long long>(reg[k].map_model_points),
                      reg[k].icp.iterations, seconds[k]);
    }
    return out;
}

void Rms::finish() {
    rms_m = bins > 0 ? std::sqrt(sum2_ / static_cast<double>(bins)) : 0.0;
    mean_m = bins > 0 ? sum_ / static_cast<double>(bins) : 0.0;
}

HeightReport heightReport(const Truth& truth, const octree::HeightProducts& products) {
    HeightReport out;
    for (std::int32_t p = 0; p < std::min<std::int32_t>(3, products.count()); ++p) {
        const terrain::HeightMap& map = products.map(p);
        const bool finest = p == products.count() - 1;
        const std::int32_t cols = map.grid().cols, rows = map.grid().rows;
        std::vector<double> err(static_cast<std::size_t>(cols) * rows, std::numeric_limits<double>::quiet_NaN());
        for (std::int32_t row = 0; row < rows; ++row) {
            for (std::int32_t col = 0; col < cols; ++col) {
                const float e = map.elevation(col, row);
                if (terrain::isNoData(e)) continue;
                const double north = map.centreNorthM(row), east = map.centreEastM(col);
                const std::size_t i = static_cast<std::size_t>(row) * cols + col;
                err[i] = e - truth.elevationInMap(north, east);
                out.product[p].add(err[i]);
                if (!finest) continue;
                const double d = truth.distanceToStops(north, east);
                out.band[d < 5.0 ? 0 : (d < 10.0 ? 1 : (d < 20.0 ? 2 : 3))].add(err[i]);
                const std::uint16_t s = products.sources(p, col, row);
                ((s & 1U) != 0U ? out.rover : out.descent).add(err[i]);
            }
        }
        if (!finest) continue;
        // Neighbour pairs (right, below): rover bin next to a descent-only bin.
        Rms seam;
        for (std::int32_t row = 0; row < rows; ++row) {
            for (std::int32_t col = 0; col < cols; ++col) {
                const std::size_t i = static_cast<std::size_t>(row) * cols + col;
                for (int dir = 0; dir < 2; ++dir) {
                    const std::int32_t c2 = col + (dir == 0 ? 1 : 0), r2 = row + (dir == 1 ? 1 : 0);
                    if (c2 >= cols || r2 >= rows) continue;
                    const std::size_t j = static_cast<std::size_t>(r2) * cols + c2;
                    if (std::isnan(err[i]) || std::isnan(err[j])) continue;
                    const std::uint16_t si = products.sources(p, col, row), sj = products.sources(p, c2, r2);
                    const bool ri = (si & 1U) != 0U, rj = (sj & 1U) != 0U;
                    if (ri != rj) {
                        seam.add(ri ? err[i] - err[j] : err[j] - err[i]);  // rover side minus descent side
                    } else if (!ri) {
                        out.descent_steps.add(err[i] - err[j]);
                    }
                }
            }
        }
        seam.finish();
        out.seam.pairs = seam.bins;
        out.seam.mean_m = seam.mean_m;
        out.seam.rms_m = seam.rms_m;
    }
    for (Rms& r : out.product) r.finish();
    for (Rms& r : out.band) r.finish();
    out.rover.finish();
    out.descent.finish();
    out.descent_steps.finish();
    return out;
}

std::string heightTables(const std::vector<const char*>& names, const std::vector<HeightReport>& reports) {
    std::string out =
        "Fused height maps against the terrain (mean elevation - terrain at the bin centre, map frame): RMS mm (bins)\n\n"
        "| run | 2 m | 0.5 m | 0.25 m |";
    for (const char* b : kBandNames) out += format(" 0.25 m, %s |", b);
    out += " 0.25 m, rover bins | 0.25 m, descent-only bins |\n|---|---|---|---|---|---|---|---|---|---|\n";
    for (std::size_t r = 0; r < reports.size(); ++r) {
        const HeightReport& h = reports[r];
        out += format("| %s |", names[r]);
        for (const Rms& p : h.product) out += format(" %.1f (%ld) |", 1000.0 * p.rms_m, p.bins);
        for (const Rms& b : h.band) out += format(" %.1f (%ld) |", 1000.0 * b.rms_m, b.bins);
        out += format(" %.1f (%ld) | %.1f (%ld) |\n", 1000.0 * h.rover.rms_m, h.rover.bins, 1000.0 * h.descent.rms_m,
                      h.descent.bins);
    }
    out += "\nSeam (0.25 m product): height step between a rover bin and its descent-only neighbour minus the "
           "terrain's step there\n\n| run | pairs | mean mm | RMS mm | descent-only neighbours: mean / RMS mm |\n"
           "|---|---|---|---|---|\n";
    for (std::size_t r = 0; r < reports.size(); ++r) {
        const HeightReport& h = reports[r];
        out += format("| %s | %ld | %.1f | %.1f | %.1f / %.1f |\n", names[r], h.seam.pairs, 1000.0 * h.seam.mean_m,
                      1000.0 * h.seam.rms_m, 1000.0 * h.descent_steps.mean_m, 1000.0 * h.descent_steps.rms_m);
    }
    return out;
}

ground::GreyImage enlarged(const ground::GreyImage& in, std::int32_t f) {
    ground::GreyImage out(in.width * f, in.height * f, in.channels, 0);
    for (std::int32_t y = 0; y < out.height; ++y) {
        for (std::int32_t x = 0; x < out.width; ++x) {
            for (std::int32_t c = 0; c < in.channels; ++c) out.at(x, y, c) = in.at(x / f, y / f, c);
        }
    }
    return out;
}

std::string writePictures(const Truth& truth, const octree::HeightProducts& products, const std::string& dir,
                          std::int32_t enlarge) {
    const terrain::HeightMap& map = products.map(products.count() - 1);
    ground::FloatImage elev = ground::elevationImage(map);
    ground::FloatImage err = elev;
    for (std::int32_t row = 0; row < err.height; ++row) {
        for (std::int32_t col = 0; col < err.width; ++col) {
            float& e = err.at(col, row);
            if (std::isfinite(e)) e = static_cast<float>(e - truth.elevationInMap(map.centreNorthM(row), map.centreEastM(col)));
        }
    }
    elev = ground::cropToFinite(elev);
    err = ground::cropToFinite(err);
    const ground::Outcome a = ground::writePng(dir + "/traverse_fused_0.25m.png",
                                               enlarged(ground::shadedRelief(elev, map.grid().cell_m), enlarge));
    // Error: grey 128 = 0, +-0.25 m to white / black; no data black.
    ground::GreyImage g(err.width, err.height, 1, 0);
    for (std::size_t i = 0; i < err.pixels.size(); ++i) {
        const float e = err.pixels[i];
        if (std::isfinite(e)) g.pixels[i] = static_cast<std::uint8_t>(std::clamp(128.0 + 512.0 * e, 1.0, 255.0));
    }
    const ground::Outcome b = ground::writePng(dir + "/traverse_fused_error_0.25m.png", enlarged(g, enlarge));
    if (!a.ok) return a.error;
    return b.ok ? "" : b.error;
}

}  // namespace vtm::traverse
