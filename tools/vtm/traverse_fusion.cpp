// The traverse and the descent fused by TerrainIntegrator (traverse_fusion.hpp).
#include "traverse_fusion.hpp"
#include "command_support.hpp"

#include <chrono>
#include <cmath>

#include <Eigen/Geometry>

namespace vtm::traverse {
namespace {

using tools::secondsSince;

constexpr int kRegistrationLevel = 9;

RigidPose inverse(const RigidPose& a) {
    RigidPose p;
    p.R = a.R.transpose();
    p.t_m = -(p.R * a.t_m);
    return p;
}

void add(Fusion& f, const app::ModelInput& m, const std::string& name) {
    app::AddResult r;
    const auto t0 = std::chrono::steady_clock::now();
    const Status st = f.integrator->addModel(m, r);
    f.seconds.push_back(secondsSince(t0));
    if (!st.isOk()) f.refusals.push_back(name + ": " + st.reason() + " (" + std::to_string(st.detail()) + ")");
    f.results.push_back(r);
}

}  // namespace

const RigidPose& descentError() {
    static const RigidPose e = [] {
        const double k = 3.14159265358979323846 / 180.0;
        RigidPose p;
        p.R = (Eigen::AngleAxisd(0.3 * k, Vec3::UnitZ()) * Eigen::AngleAxisd(-0.1 * k, Vec3::UnitY()) *
               Eigen::AngleAxisd(0.1 * k, Vec3::UnitX()))
                  .toRotationMatrix();
        p.t_m = Vec3(0.35, -0.25, 0.15);
        return p;
    }();
    return e;
}

app::IntegratorConfig fusionConfig() {
    app::IntegratorConfig c;
    c.octree.north_edge_m = 40.0;
    c.octree.west_edge_m = -24.0;
    c.octree.top_z_m = -32.0;
    c.octree.side_m = 64.0;
    c.octree.max_depth = 9;
    c.octree.max_nodes = 1 << 19;
    c.products.levels = {{5, 7, 8, 0, 0, 0}};
    c.products.count = 3;
    c.products.reducer = terrain::Reducer::kMean;
    c.registration_level = kRegistrationLevel;
    // The ICP's gate and normal radius scaled with the registration cell (0.25 m defaults).
    const double scale = std::ldexp(c.octree.side_m, -kRegistrationLevel) / 0.25;
    c.icp.normal_radius_m *= scale;
    c.icp.min_gate_m *= scale;
    c.icp.min_overlap = 0.2;
    c.icp.max_model_points = 1 << 17;
    return c;
}

const char* modeName(Mode m) {
    return m == Mode::kRegistered ? "registered" : (m == Mode::kNavigation ? "navigation only" : "true poses");
}

std::unique_ptr<Fusion> fuse(const World& world, Mode mode) {
    auto f = std::make_unique<Fusion>();
    const app::IntegratorConfig c = fusionConfig();
    f->pool.resize(app::TerrainIntegrator::workspaceBytes(c));
    Arena arena(f->pool.data(), f->pool.size());
    const Status init = f->integrator->init(c, arena, f->clock, f->events);
    if (!init.isOk()) {
        f->error = std::string("TerrainIntegrator::init: ") + init.reason();
        return f;
    }
    for (std::size_t k = 0; k < world.stops.size(); ++k) {
        const StopMap& s = world.stops[k];
        app::ModelInput m;
        m.points_m = Span<const Vec3>(s.points.data(), s.points.size());
        m.map_from_model_guess = mode == Mode::kTruePoses ? s.truth : s.odometry;
        m.footprint.kind = app::FootprintKind::kRangeTimesAngle;
        m.footprint.sensor_m = s.sensor_m;
        m.footprint.pixel_angle_rad = s.pixel_angle_rad;
        m.source = 0U;
        m.register_model = mode == Mode::kRegistered && k > 0;
        add(*f, m, "stop " + std::to_string(k));
    }
    // The descent map in its own frame: every cell moved by the descent's navigation error.
    std::vector<Vec3> descent;
    for (const Vec3& p : world.descent_map.points) descent.push_back(descentError().R * p + descentError().t_m);
    app::ModelInput in;
    in.points_m = Span<const Vec3>(descent.data(), descent.size());
    in.map_from_model_guess = mode == Mode::kTruePoses ? inverse(descentError()) : RigidPose{};
    in.footprint.footprint_m = world.descent_map.cell_m;
    in.source = 1U;
    in.register_model = mode == Mode::kRegistered;
    add(*f, in, "descent");
    const Status st = f->integrator->extractProducts();
    if (!st.isOk()) f->error = std::string("extractProducts: ") + st.reason();
    return f;
}

}  // namespace vtm::traverse
