#include "gdal_session.hpp"

#include <gdal.h>

#include <cpl_error.h>

#include <mutex>

namespace vtm::ground::detail {

void registerGdalDrivers() {
    static std::once_flag once;
    std::call_once(once, [] { GDALAllRegister(); });
}

QuietGdalErrors::QuietGdalErrors() {
    CPLPushErrorHandler(CPLQuietErrorHandler);
    CPLErrorReset();
}

QuietGdalErrors::~QuietGdalErrors() { CPLPopErrorHandler(); }

std::string QuietGdalErrors::lastError() const {
    const char* message = CPLGetLastErrorMsg();
    return (message != nullptr && message[0] != '\0') ? std::string(message) : std::string("GDAL gave no reason");
}

bool QuietGdalErrors::failed() const { return CPLGetLastErrorType() >= CE_Failure; }

}  // namespace vtm::ground::detail
