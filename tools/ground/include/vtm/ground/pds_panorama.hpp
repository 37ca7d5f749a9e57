// Neighbouring frames of a PDS panorama (MER Navcam frames of one pointing sequence, read by
// pds_image.hpp): tie points in their overlap with fsw/features (Förstner points of frame A
// in the part frame B can see, guided NCC template matching into B), their residuals under
// the labels' pointing, and a mosaic of the frames on a cylinder about the site's vertical
// (docs/pds.md). Ground side: the heap, std::vector.
//
// Geometry: each frame's camera model is in its rover frame, placed in the site frame by
// its site_from_rover; frame B sees frame A's point X (rover A) at
// R_b^T (R_a X + t_a - t_b). Both residuals are measured in B, in pixels:
//  - epipolar_px: distance from the matched pixel to the image in B of A's ray (ranges
//    range_min_m .. infinity). The Navcam's projection centres of one sequence are a few
//    cm apart, so this is nearly the full pointing error, whatever the range;
//  - sphere_px: distance from the matched pixel to where A's pixel lands when its ray is
//    met at sphere_radius_m (the usual "far scene" prediction; includes parallax).
#pragma once

#include <cstdint>
#include <vector>

#include "vtm/core/eigen.hpp"
#include "vtm/ground/image.hpp"
#include "vtm/ground/pds_image.hpp"

namespace vtm::ground {

struct PdsTieConfig {
    double camera_height_m = 1.5;    // Navcam above the ground, for the visibility prior
    double range_min_m = 0.5;        // nearest scene along a ray (the rover deck is ~1 m away)
    double range_max_m = 1000.0;     // farthest (the horizon)
    double margin_px = 30.0;         // pointing uncertainty around the predicted region
    double sphere_radius_m = 20.0;   // the far-scene prediction of sphere_px
    float min_score = 0.8F;          // NCC of an accepted match
};

struct PdsTie {
    Vec2 pixel_a = Vec2::Zero();
    Vec2 pixel_b = Vec2::Zero();
    float score = 0.0F;
    double epipolar_px = 0.0;
    double sphere_px = 0.0;
};

struct PdsTieResult {
    std::int32_t features = 0;   // Förstner points of A in the predicted overlap
    std::int32_t attempted = 0;  // matcher statistics (fsw/features MatchStats)
    std::int32_t low_score = 0, not_refined = 0, not_mutual = 0, no_region = 0;
    std::vector<PdsTie> ties;
};

// Both frames need a camera model and a rover pose (errors name the frame's product id).
Result<PdsTieResult> matchPdsNeighbours(const PdsImage& a, const PdsImage& b, const PdsTieConfig& config);

// Pixel of B where frame A's point at `range_m` along A's ray through `pixel_a` is seen
// (false when it does not project in front of B).
bool pdsTransferPixel(const PdsImage& a, const PdsImage& b, const Vec2& pixel_a, double range_m, Vec2& pixel_b);

// Distance in B from pixel_b to the image of A's ray through pixel_a, ranges range_min_m to
// infinity (the ray sampled uniformly in inverse range, 512 segments).
double pdsEpipolarDistance(const PdsImage& a, const PdsImage& b, const Vec2& pixel_a, const Vec2& pixel_b,
                           double range_min_m);

struct PdsMosaicConfig {
    double azimuth_min_deg = 60.0, azimuth_max_deg = 300.0;  // site azimuth, clockwise from north
    double elevation_min_deg = -45.0, elevation_max_deg = 12.0;  // up positive
    double step_deg = 0.1;                                    // per output pixel
    double radius_m = 20.0;                                   // the scene's assumed distance from the mast
};

// An 8-bit mosaic: each output pixel's site direction (azimuth, elevation) met at radius_m
// from the first frame's projection centre, seen by the frame whose image holds it
// farthest from its edges, sampled bilinearly from that frame's pdsStretchToGrey8 view;
// 0 where no frame sees it. Rows go down in elevation, columns right in azimuth.
GreyImage pdsCylinderMosaic(const std::vector<PdsImage>& frames, const PdsMosaicConfig& config);

}  // namespace vtm::ground
