// AssertCapture: while alive, VTM_ASSERT failures are recorded instead of aborting, so a
// test can prove that a programmer error is detected (and that the code after the
// assertion stays safe).
#pragma once

#include <cstdint>

#include "vtm/core/assert.hpp"

namespace vtm::test {

class AssertCapture {
public:
    AssertCapture() noexcept;
    ~AssertCapture();
    AssertCapture(const AssertCapture&) = delete;
    AssertCapture& operator=(const AssertCapture&) = delete;

    [[nodiscard]] std::int32_t count() const noexcept;
    // The most recent failure (valid when count() > 0).
    [[nodiscard]] const AssertInfo& last() const noexcept;

private:
    AssertHook previous_;
};

}  // namespace vtm::test
