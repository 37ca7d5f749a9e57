#include "geotiff_crs.hpp"

#include <cmath>
#include <cstdlib>

namespace vtm::ground::detail {
namespace {

const char* const kCrsName = "VTM site frame, Mars (2015) sphere, transverse Mercator";
const char* const kGeogName = "Mars (2015) - Sphere / Ocentric";  // as IAU_2015:49900 names it
const char* const kDatumName = "Mars (2015) - Sphere";

}  // namespace

std::string checkSiteOrigin(const SiteOrigin& site) {
    if (!(site.latitude_deg >= -90.0 && site.latitude_deg <= 90.0)) {
        return "site origin latitude " + std::to_string(site.latitude_deg) + " deg outside [-90, 90]";
    }
    if (!(site.longitude_deg >= -180.0 && site.longitude_deg <= 360.0)) {
        return "site origin longitude " + std::to_string(site.longitude_deg) + " deg outside [-180, 360]";
    }
    return "";
}

OGRSpatialReference siteCrs(const SiteOrigin& site) {
    OGRSpatialReference crs;
    crs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    (void)crs.SetProjCS(kCrsName);
    (void)crs.SetGeogCS(kGeogName, kDatumName, kDatumName, kMarsRadiusM, 0.0, "Reference Meridian", 0.0,
                        SRS_UA_DEGREE, std::atof(SRS_UA_DEGREE_CONV));
    (void)crs.SetTM(site.latitude_deg, site.longitude_deg, 1.0, 0.0, 0.0);
    (void)crs.SetLinearUnits(SRS_UL_METER, 1.0);
    return crs;
}

std::string recogniseSiteCrs(const OGRSpatialReference& crs, SiteOrigin& site) {
    if (!crs.IsProjected()) return "CRS is not projected";
    const char* projection = crs.GetAttrValue("PROJECTION");
    if (projection == nullptr || std::string(projection) != SRS_PT_TRANSVERSE_MERCATOR) {
        return std::string("projection ") + (projection != nullptr ? projection : "(none)") +
               ", not Transverse_Mercator";
    }
    OGRErr err = OGRERR_NONE;
    const double a = crs.GetSemiMajor(&err);
    if (err != OGRERR_NONE || std::fabs(a - kMarsRadiusM) > 0.5 || crs.GetInvFlattening() != 0.0) {
        return "not on the Mars sphere of radius 3396190 m (semi-major " + std::to_string(a) + " m)";
    }
    if (crs.GetProjParm(SRS_PP_SCALE_FACTOR, 0.0) != 1.0 || crs.GetProjParm(SRS_PP_FALSE_EASTING, 1.0) != 0.0 ||
        crs.GetProjParm(SRS_PP_FALSE_NORTHING, 1.0) != 0.0 || crs.GetLinearUnits() != 1.0) {
        return "transverse Mercator with scale, false easting/northing or units other than 1, 0, 0, metre";
    }
    site.latitude_deg = crs.GetProjParm(SRS_PP_LATITUDE_OF_ORIGIN, 0.0);
    site.longitude_deg = crs.GetProjParm(SRS_PP_CENTRAL_MERIDIAN, 0.0);
    return checkSiteOrigin(site);
}

}  // namespace vtm::ground::detail
