// A cylinder mosaic of PDS frames (pds_panorama.hpp).
#include <cmath>

#include "vtm/core/pose.hpp"
#include "vtm/ground/pds_panorama.hpp"

namespace vtm::ground {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

}  // namespace

GreyImage pdsCylinderMosaic(const std::vector<PdsImage>& frames, const PdsMosaicConfig& config) {
    const double step = config.step_deg > 0.0 ? config.step_deg : 0.1;
    const int width = static_cast<int>(std::ceil((config.azimuth_max_deg - config.azimuth_min_deg) / step - 1e-9));
    const int height = static_cast<int>(std::ceil((config.elevation_max_deg - config.elevation_min_deg) / step - 1e-9));
    if (frames.empty() || width <= 0 || height <= 0 || width > 20000 || height > 20000) return GreyImage();
    GreyImage out(width, height);
    std::vector<GreyImage> grey;
    for (const PdsImage& f : frames) grey.push_back(pdsStretchToGrey8(f.pixels));
    CameraRay first;
    const Vec2 centre(0.5 * (frames[0].camera_model.width_px - 1), 0.5 * (frames[0].camera_model.height_px - 1));
    (void)backProjectPixel(frames[0].camera_model, centre, first);
    const Vec3 origin_site = transformPoint(frames[0].site_from_rover, first.origin_m);
    for (int row = 0; row < height; ++row) {
        const double el = (config.elevation_max_deg - (row + 0.5) * step) * kDeg;
        for (int col = 0; col < width; ++col) {
            const double az = (config.azimuth_min_deg + (col + 0.5) * step) * kDeg;
            // Site frame: x north, y east, z down; elevation up positive.
            const Vec3 d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), -std::sin(el));
            const Vec3 x_site = origin_site + config.radius_m * d;
            double best_margin = 0.0;
            double value = 0.0;
            for (std::size_t k = 0; k < frames.size(); ++k) {
                const PdsImage& f = frames[k];
                if (!f.has_camera_model || !f.has_rover_pose) continue;
                const Vec3 x_rover = f.site_from_rover.R.transpose() * (x_site - f.site_from_rover.t_m);
                Vec2 px;
                if (!projectPoint(f.camera_model, x_rover, px).isOk()) continue;
                const double margin = std::min(std::min(px.x(), grey[k].width - 1.0 - px.x()),
                                               std::min(px.y(), grey[k].height - 1.0 - px.y()));
                if (margin > best_margin) {
                    best_margin = margin;
                    value = bilinearAt(grey[k], px.x(), px.y());
                }
            }
            out.at(col, row) = static_cast<std::uint8_t>(std::lround(std::min(255.0, std::max(0.0, value))));
        }
    }
    return out;
}

}  // namespace vtm::ground
