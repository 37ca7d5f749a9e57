// The CRS of VTM's GeoTIFFs (geotiff.hpp, docs/geotiff.md): transverse Mercator on the IAU
// 2015 Mars sphere centred on the site origin. Built and recognised here only.
#pragma once

#include <ogr_spatialref.h>

#include <string>

#include "vtm/ground/geotiff.hpp"

namespace vtm::ground::detail {

// "" when the origin is usable, else what is wrong with it.
std::string checkSiteOrigin(const SiteOrigin& site);

// The site frame's CRS (axis order easting, northing).
OGRSpatialReference siteCrs(const SiteOrigin& site);

// "" and the origin when `crs` is the site frame's CRS of some origin, else what differs.
std::string recogniseSiteCrs(const OGRSpatialReference& crs, SiteOrigin& site);

}  // namespace vtm::ground::detail
