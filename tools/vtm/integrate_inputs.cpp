#include "integrate_inputs.hpp"

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "vtm/ground/pfm.hpp"
#include "vtm/ground/ply_reader.hpp"
#include "vtm/ground/sim_output.hpp"

namespace vtm::tools {
namespace {

using ground::Result;

struct Georeference {
    double north0_m = 0.0;  // pixel (0, 0)'s centre
    double east0_m = 0.0;
    double cell_m = 0.0;
    long width_px = 0;
    long height_px = 0;
};

// "vtm-orbital-geo 1", '#' comments, "key value..." lines; the five keys used here.
Result<Georeference> readGeoreference(const std::string& path) {
    std::ifstream in(path);
    if (!in) return Result<Georeference>::failure(path + ": cannot open");
    std::string line;
    if (!std::getline(in, line) || line.rfind("vtm-orbital-geo 1", 0) != 0) {
        return Result<Georeference>::failure(path + ": line 1: expected 'vtm-orbital-geo 1'");
    }
    std::map<std::string, double> kv;
    while (std::getline(in, line)) {
        std::istringstream s(line);
        std::string key;
        double value = 0.0;
        if (!(s >> key) || key[0] == '#') continue;
        if (s >> value) kv[key] = value;
    }
    Georeference g;
    const char* keys[] = {"north0_m", "east0_m", "cell_m", "width_px", "height_px"};
    for (const char* k : keys) {
        if (kv.count(k) == 0U || !std::isfinite(kv[k])) {
            return Result<Georeference>::failure(path + ": no numeric '" + k + "'");
        }
    }
    g.north0_m = kv["north0_m"];
    g.east0_m = kv["east0_m"];
    g.cell_m = kv["cell_m"];
    g.width_px = std::lround(kv["width_px"]);
    g.height_px = std::lround(kv["height_px"]);
    if (!(g.cell_m > 0.0)) return Result<Georeference>::failure(path + ": cell_m must be > 0");
    return Result<Georeference>::success(g);
}

// One point per finite pixel: north = north0 - row cell, east = east0 + col cell, z = -elevation.
// cell_m: the map's cell (the default footprint).
Result<std::vector<Vec3>> pfmPoints(const std::string& path, const std::string& geo_path, double& cell_m) {
    using R = Result<std::vector<Vec3>>;
    if (geo_path.empty()) return R::failure(path + ": a PFM elevation map needs geo=FILE (its georeference)");
    const Result<ground::FloatImage> image = ground::readPfm(path);
    if (!image.ok) return R::failure(image.error);
    const Result<Georeference> geo = readGeoreference(geo_path);
    if (!geo.ok) return R::failure(geo.error);
    const Georeference& g = geo.value;
    cell_m = g.cell_m;
    if (g.width_px != image.value.width || g.height_px != image.value.height) {
        return R::failure(path + ": " + std::to_string(image.value.width) + "x" + std::to_string(image.value.height) +
                          " pixels, but " + geo_path + " says " + std::to_string(g.width_px) + "x" +
                          std::to_string(g.height_px));
    }
    std::vector<Vec3> points;
    for (int row = 0; row < image.value.height; ++row) {
        for (int col = 0; col < image.value.width; ++col) {
            const float e = image.value.at(col, row);
            if (std::isfinite(e)) points.emplace_back(g.north0_m - row * g.cell_m, g.east0_m + col * g.cell_m, -e);
        }
    }
    if (points.empty()) return R::failure(path + ": no finite elevation");
    return R::success(std::move(points));
}

// "key=value" options after the path.
struct SpecParts {
    std::string path, pose, geo, footprint, source;
};

Result<SpecParts> splitSpec(const std::string& spec) {
    SpecParts p;
    std::istringstream s(spec);
    std::string item;
    std::getline(s, p.path, ',');
    while (std::getline(s, item, ',')) {
        const std::size_t eq = item.find('=');
        const std::string key = item.substr(0, eq);
        const std::string value = eq == std::string::npos ? "" : item.substr(eq + 1);
        std::string* slot = key == "pose" ? &p.pose : key == "geo" ? &p.geo : key == "footprint" ? &p.footprint
                          : key == "source" ? &p.source : nullptr;
        if (slot == nullptr || value.empty()) {
            return Result<SpecParts>::failure("input '" + spec + "': unknown or empty option '" + item +
                                              "' (pose=, geo=, footprint=, source=)");
        }
        *slot = value;
    }
    if (p.path.empty()) return Result<SpecParts>::failure("input '" + spec + "': no file");
    return Result<SpecParts>::success(p);
}

bool parseNumber(const std::string& text, double& value) {
    std::istringstream s(text);
    return (s >> value) && s.eof() && std::isfinite(value);
}

}  // namespace

Result<IntegrateInput> loadIntegrateInput(const std::string& spec, int index) {
    using R = Result<IntegrateInput>;
    const Result<SpecParts> parts = splitSpec(spec);
    if (!parts.ok) return R::failure(parts.error);
    const SpecParts& p = parts.value;
    IntegrateInput in;
    in.spec = spec;
    in.path = p.path;
    in.source = index;
    const bool pfm = ground::looksLikePfm(p.path);
    in.footprint_m = kDefaultPlyFootprintM;
    Result<std::vector<Vec3>> points = pfm ? pfmPoints(p.path, p.geo, in.footprint_m) : ground::readPlyPoints(p.path);
    if (!points.ok) return R::failure(points.error);
    in.points_m = std::move(points.value);
    if (!p.footprint.empty() && (!parseNumber(p.footprint, in.footprint_m) || in.footprint_m <= 0.0)) {
        return R::failure("input '" + spec + "': footprint=" + p.footprint + ": expected metres > 0");
    }
    if (!p.source.empty()) {
        double s = 0.0;
        if (!parseNumber(p.source, s) || s != std::floor(s) || s < 0.0 || s > 15.0) {
            return R::failure("input '" + spec + "': source=" + p.source + ": expected a whole number 0..15");
        }
        in.source = static_cast<int>(s);
    }
    if (!p.pose.empty()) {
        const Result<ground::SimCameraPose> pose = ground::readCameraPoseSpec(p.pose);
        if (!pose.ok) return R::failure("input '" + spec + "': " + pose.error);
        in.map_from_model = ground::siteFromCam(pose.value);
    }
    return R::success(std::move(in));
}

}  // namespace vtm::tools
