// PLY reader: files written by hand in this test (ASCII and binary little endian, float
// and double, extra properties and elements, any property order) give their points; every
// malformed file is refused with one line naming it and the reason.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "ground_test_files.hpp"
#include "vtm/ground/ply_reader.hpp"
#include "vtm/ground/terrain_products.hpp"

namespace vtm::ground {
namespace {

using test::Bytes;
using test::textBytes;

void appendRaw(Bytes& b, const void* p, std::size_t n) {  // the host is little endian (x86-64)
    const auto* c = static_cast<const unsigned char*>(p);
    b.insert(b.end(), c, c + n);
}
template <typename T>
void put(Bytes& b, T v) {
    appendRaw(b, &v, sizeof v);
}

std::string errorOf(const std::string& text) {
    const Result<std::vector<Vec3>> r = decodePlyPoints(textBytes(text), "in.ply");
    EXPECT_FALSE(r.ok);
    return r.error;
}

const char* const kAsciiHeader =
    "ply\nformat ascii 1.0\ncomment by hand\nelement vertex 3\nproperty float x\nproperty float y\n"
    "property float z\nproperty uchar red\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";

TEST(PlyReader, ReadsAsciiFloatsSkippingExtraPropertiesAndElements) {
    const std::string text = std::string(kAsciiHeader) + "1.5 -2 0.25 255\n\n0 0 -3.125 7\n1e3 2 3 0\n3 0 1 2\n";
    const Result<std::vector<Vec3>> r = decodePlyPoints(textBytes(text), "a.ply");
    ASSERT_TRUE(r.ok) << r.error;
    ASSERT_EQ(r.value.size(), 3U);
    EXPECT_EQ(r.value[0], Vec3(1.5, -2.0, 0.25));
    EXPECT_EQ(r.value[1], Vec3(0.0, 0.0, -3.125));
    EXPECT_EQ(r.value[2], Vec3(1000.0, 2.0, 3.0));
}

TEST(PlyReader, AsciiFloatPropertiesAreRoundedToFloat) {
    const std::string text = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty double y\n"
                             "property float z\nend_header\n0.1 0.1 0.1\n";
    const Result<std::vector<Vec3>> r = decodePlyPoints(textBytes(text), "f.ply");
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_EQ(r.value[0], Vec3(static_cast<double>(0.1F), 0.1, static_cast<double>(0.1F)));
}

TEST(PlyReader, ReadsBinaryDoublesInAnyOrderWithListsBeforeAndAfter) {
    Bytes b = textBytes("ply\nformat binary_little_endian 1.0\nelement camera 1\nproperty list uint8 float32 k\n"
                        "element vertex 2\nproperty int id\nproperty double z\nproperty short s\n"
                        "property double x\nproperty double y\nelement face 1\n"
                        "property list int uint vertex_indices\nend_header\n");
    put<std::uint8_t>(b, 2);
    put<float>(b, 1.0F);
    put<float>(b, 2.0F);
    for (int i = 0; i < 2; ++i) {
        put<std::int32_t>(b, -7);
        put<double>(b, 0.1 * (i + 1));  // z
        put<std::int16_t>(b, 3);
        put<double>(b, -1.0e6 - i);      // x
        put<double>(b, 1.0 / 3.0);       // y
    }
    put<std::int32_t>(b, 2);
    put<std::uint32_t>(b, 0);
    put<std::uint32_t>(b, 1);
    const Result<std::vector<Vec3>> r = decodePlyPoints(b, "b.ply");
    ASSERT_TRUE(r.ok) << r.error;
    ASSERT_EQ(r.value.size(), 2U);
    EXPECT_EQ(r.value[0], Vec3(-1.0e6, 1.0 / 3.0, 0.1));
    EXPECT_EQ(r.value[1], Vec3(-1.0e6 - 1.0, 1.0 / 3.0, 0.2));
}

TEST(PlyReader, ReadsWhatWritePlyWrites) {
    test::TempDir dir;
    const std::vector<Vec3> points = {Vec3(1.0, 2.0, -0.5), Vec3(-3.25, 1e-3, 7.0)};
    const std::string path = dir.file("points.ply");
    ASSERT_TRUE(writePly(path, points).ok);
    const Result<std::vector<Vec3>> r = readPlyPoints(path);
    ASSERT_TRUE(r.ok) << r.error;
    ASSERT_EQ(r.value.size(), 2U);
    EXPECT_EQ(r.value[0], points[0]);
    EXPECT_EQ(r.value[1], Vec3(-3.25, static_cast<double>(1e-3F), 7.0));  // stored as float
}

struct BadCase {
    const char* what;
    std::string text;
    std::string message;  // the whole error after "in.ply: "
};

TEST(PlyReader, RefusesMalformedHeadersNamingTheLine) {
    const std::string v = "element vertex 1\nproperty float x\nproperty float y\nproperty float z\n";
    const BadCase cases[] = {
        {"not ply", "plx\nformat ascii 1.0\n", "not a PLY file (first line is not 'ply')"},
        {"big endian", "ply\nformat binary_big_endian 1.0\n" + v + "end_header\n",
         "PLY header line 2: binary_big_endian is not supported (ascii or binary_little_endian)"},
        {"unknown keyword", "ply\nformat ascii 1.0\nvertices 3\n", "PLY header line 3: unknown keyword 'vertices'"},
        {"bad type", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\n",
         "PLY header line 4: expected 'property <type> <name>' or 'property list <count type> <type> <name>'"},
        {"no end", "ply\nformat ascii 1.0\n" + v, "PLY header line 7: no 'end_header' in the first 65536 bytes (or the file ends)"},
        {"bad count", "ply\nformat ascii 1.0\nelement vertex -1\n", "PLY header line 3: expected 'element <name> <count>'"},
        {"int x", "ply\nformat ascii 1.0\nelement vertex 1\nproperty int x\nproperty float y\nproperty float z\nend_header\n1 2 3\n",
         "PLY vertex property x must be float or double"},
        {"no z", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n1 2\n",
         "PLY no vertex property z"},
        {"no vertex", "ply\nformat ascii 1.0\nelement point 1\nproperty float x\nend_header\n1\n", "PLY has no 'vertex' element"},
        {"absurd count", "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n"
                         "property float y\nproperty float z\nend_header\n",
         "PLY declares 4000000000 vertices, more than the 16777216 accepted"},
    };
    for (const BadCase& c : cases) EXPECT_EQ(errorOf(c.text), std::string("in.ply: ") + c.message) << c.what;
}

TEST(PlyReader, RefusesDataThatDoesNotMatchTheHeader) {
    const std::string ascii = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                              "property float z\nend_header\n";
    const std::string binary = "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\n"
                               "property float y\nproperty float z\nend_header\n";
    const std::string header_bytes = std::to_string(binary.size());       // the data's first byte
    const std::string end_bytes = std::to_string(binary.size() + 24U);    // two vertices of 12 bytes later
    const BadCase cases[] = {
        {"ascii short", ascii + "1 2 3\n", "PLY: the file ends after line 8, at vertex 2 of 2"},
        {"ascii long", ascii + "1 2 3\n4 5 6\n7 8 9\n", "PLY line 10: data after the last element (wrong counts in the header?)"},
        {"ascii few values", ascii + "1 2\n4 5 6\n", "PLY line 8: fewer values than the element declares"},
        {"ascii many values", ascii + "1 2 3 4\n4 5 6\n", "PLY line 8: 4 values, vertex declares 3"},
        {"ascii not a number", ascii + "1 abc 3\n4 5 6\n", "PLY line 8: value 2 'abc' is not a number"},
        {"binary truncated", binary + std::string(20, '\0'),
         "PLY declares 2 vertex elements of at least 12 bytes, but 20 bytes remain at byte " + header_bytes},
        {"binary long", binary + std::string(25, '\0'), "PLY has 1 bytes after the last element (byte " + end_bytes + "; wrong counts in the header?)"},
    };
    for (const BadCase& c : cases) EXPECT_EQ(errorOf(c.text), std::string("in.ply: ") + c.message) << c.what;
}

TEST(PlyReader, RefusesATruncatedListAndAMissingFile) {
    Bytes b = textBytes("ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                        "property float z\nproperty list uchar int n\nend_header\n");
    const std::size_t body = b.size();
    put<float>(b, 1.0F);
    put<float>(b, 2.0F);
    put<float>(b, 3.0F);
    put<std::uint8_t>(b, 200);  // 200 ints announced, 1 present
    put<std::int32_t>(b, 5);
    const Result<std::vector<Vec3>> r = decodePlyPoints(b, "list.ply");
    EXPECT_EQ(r.error, "list.ply: truncated PLY: vertex 1 of 1 needs bytes " + std::to_string(body + 13U) + ".." +
                           std::to_string(body + 13U + 800U - 1U) + ", the file has " + std::to_string(b.size()));
    test::TempDir dir;
    const std::string missing = dir.file("none.ply");
    EXPECT_EQ(readPlyPoints(missing).error, missing + ": cannot open: No such file or directory");
}

}  // namespace
}  // namespace vtm::ground
