// Measures of the traverse-and-descent fusion against the truth: registered poses, fused
// height maps by distance band and source, the seam between sources, pictures. Ground side
// (`vtm run`'s report, tests/integrate's evaluation, which adds the OpenCV peer).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "sim/terrain.hpp"
#include "traverse_world.hpp"
#include "vtm/app/terrain_integrator.hpp"
#include "vtm/ground/image.hpp"
#include "vtm/octree/height_products.hpp"

namespace vtm::traverse {

constexpr double kRotationTarget_deg = 0.05;       // issue 25 item 4
constexpr double kTranslationTarget_percent = 1.0;  // of the stop-to-stop distance
constexpr std::size_t kBands = 4;                   // 0-5, 5-10, 10-20, >= 20 m from the stops
extern const char* const kBandNames[kBands];

// The truth in the map frame = stop 0's navigation frame = the site frame (the odometry
// starts at the true first pose). Models 0..7 are the stops, model 8 the descent map
// (its frame: descent = E site, E its navigation error).
struct Truth {
    const sim::Terrain* terrain = nullptr;
    RigidPose descent_error;  // E
    const std::vector<StopMap>* stops = nullptr;
    const DescentMap* descent = nullptr;

    [[nodiscard]] bool isDescent(std::size_t k) const { return k == stops->size(); }
    [[nodiscard]] RigidPose mapFromModel(std::size_t k) const;
    // The model's points in its own frame (the descent's: its cells moved by E).
    [[nodiscard]] std::vector<Vec3> modelPoints(std::size_t k) const;
    // The terrain's elevation (-z) in the map frame at map (north, east).
    [[nodiscard]] double elevationInMap(double north_m, double east_m) const;
    // Horizontal distance from map (north, east) to the nearest stop (true position).
    [[nodiscard]] double distanceToStops(double north_m, double east_m) const;
    // Stop k's distance to its neighbour (k - 1; stop 0: stop 1), true positions; for the
    // descent (k == stops->size()) the last stop's.
    [[nodiscard]] double stepM(std::size_t k) const;
    // The model's points' centroid in its own frame.
    [[nodiscard]] Vec3 centroid(std::size_t k) const;
};

struct PoseError {
    double rotation_deg = 0.0;
    double translation_m = 0.0;  // at the model's centroid
    double translation_percent = 0.0;
};
PoseError poseError(const Truth& truth, std::size_t k, const RigidPose& map_from_model);
std::vector<PoseError> poseErrors(const Truth& truth, const std::vector<app::AddResult>& results);

// Issue 25's targets over the registered stops (1..n-1; stop 0 is the reference).
struct TargetCount {
    int registered = 0, rotation_met = 0, translation_met = 0;
};
TargetCount countTargets(const Truth& truth, const std::vector<app::AddResult>& results);

// Markdown table, a row per model: the navigation's and the registered pose's errors.
std::string stopTable(const Truth& truth, const std::vector<app::AddResult>& reg,
                      const std::vector<app::AddResult>& nav, const std::vector<double>& seconds);

struct Rms {
    double rms_m = 0.0;
    double mean_m = 0.0;
    long bins = 0;
    void add(double e) { sum2_ += e * e; sum_ += e; ++bins; }
    void finish();
private:
    double sum2_ = 0.0, sum_ = 0.0;
};

struct Seam {
    long pairs = 0;
    double mean_m = 0.0;  // step error (measured step - true step), rover minus descent side
    double rms_m = 0.0;
};

struct HeightReport {
    Rms product[3];       // each product, every bin with data
    Rms band[kBands];     // finest product by distance band
    Rms rover, descent;   // finest product: bins with rover data / descent-only bins
    Rms descent_steps;    // finest product: step error between descent-only neighbours (reference)
    Seam seam;
};
HeightReport heightReport(const Truth& truth, const octree::HeightProducts& products);
// Markdown: RMS per product, band and source for each run, then the seam.
std::string heightTables(const std::vector<const char*>& names, const std::vector<HeightReport>& reports);

// PNGs of the finest product, DIR/traverse_fused_0.25m.png (shaded relief) and
// DIR/traverse_fused_error_0.25m.png (its error against the terrain: grey 128 = 0,
// +-0.25 m to white / black), each cell `enlarge` x `enlarge` pixels; "" or the first
// write's error.
std::string writePictures(const Truth& truth, const octree::HeightProducts& products, const std::string& dir,
                          std::int32_t enlarge);

// Nearest-neighbour enlargement by f (f x f pixels per cell), for display.
ground::GreyImage enlarged(const ground::GreyImage& in, std::int32_t f);

}  // namespace vtm::traverse
