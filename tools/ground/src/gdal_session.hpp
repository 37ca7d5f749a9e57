// GDAL as the ground library uses it: drivers registered once, and GDAL's error messages
// collected for our one-line errors instead of printed on stderr.
#pragma once

#include <string>

namespace vtm::ground::detail {

// GDALAllRegister(), once per process.
void registerGdalDrivers();

// While alive, GDAL's errors on this thread are kept quiet; lastError() is the latest one.
class QuietGdalErrors {
public:
    QuietGdalErrors();
    ~QuietGdalErrors();
    QuietGdalErrors(const QuietGdalErrors&) = delete;
    QuietGdalErrors& operator=(const QuietGdalErrors&) = delete;
    // GDAL's last error message ("" when none), for "<file>: <what>: <lastError()>".
    [[nodiscard]] std::string lastError() const;
    // True when GDAL reported a failure (CE_Failure or worse) since construction.
    [[nodiscard]] bool failed() const;
};

}  // namespace vtm::ground::detail
