// vtm::crc32: the IEEE 802.3 / zlib / PNG CRC-32 shared by the HIL link and the ground
// PNG writer.
#include <gtest/gtest.h>

#include <cstdint>

#include "vtm/core/crc32.hpp"

namespace vtm {
namespace {

TEST(Crc32, MatchesTheIeeeCheckValue) {
    const char* text = "123456789";
    EXPECT_EQ(crc32(reinterpret_cast<const std::uint8_t*>(text), 9U), 0xCBF43926U);
    EXPECT_EQ(crc32(nullptr, 0U), 0U);
    // Running form equals the one-shot form.
    const auto* bytes = reinterpret_cast<const std::uint8_t*>(text);
    EXPECT_EQ(crc32Final(crc32Update(crc32Update(crc32Init(), bytes, 4U), bytes + 4, 5U)), 0xCBF43926U);
}

}  // namespace
}  // namespace vtm
