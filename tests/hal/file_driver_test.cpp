// hal/file: FileCamera (frame manifest + PGM/PNG frames) and FileOdometry (pose log).
//
// Every input is written by this test into a fresh temporary directory: PGM files by
// hand, PNG files either by a hand-written encoder below (stored deflate blocks, any bit
// depth and colour type, an independent peer of the decoder) or by stb_image_write
// (real deflate compression, 8-bit only). Expected pixels are the ones the test wrote;
// expected poses come from the analytic motion the log was sampled from.
#include <gtest/gtest.h>

#include <stdlib.h>  // mkdtemp
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_WRITE_NO_STDIO
#include <stb_image_write.h>

#include "hal/file/file_camera.hpp"
#include "hal/file/file_odometry.hpp"
#include "no_heap_guard.hpp"

namespace vtm {
// gtest prints StatusCode by name.
inline void PrintTo(StatusCode code, std::ostream* os) { *os << statusCodeName(code); }
}  // namespace vtm

namespace vtm::hal {
namespace {

namespace fl = file_limits;
using Bytes = std::vector<std::uint8_t>;
using Samples = std::vector<std::uint16_t>;

// ---- checks ------------------------------------------------------------------------------

::testing::AssertionResult hasStatus(const Status& s, StatusCode code, const char* reason) {
    if (s.code() == code && std::strcmp(s.reason(), reason) == 0) {
        return ::testing::AssertionSuccess();
    }
    return ::testing::AssertionFailure() << "got " << statusCodeName(s.code()) << " \"" << s.reason()
                                         << "\" detail " << s.detail() << ", want " << statusCodeName(code)
                                         << " \"" << reason << "\"";
}
::testing::AssertionResult hasStatus(const Status& s, StatusCode code, const char* reason, std::int64_t detail) {
    ::testing::AssertionResult first = hasStatus(s, code, reason);
    if (!first) {
        return first;
    }
    if (s.detail() != detail) {
        return ::testing::AssertionFailure() << "\"" << s.reason() << "\": detail " << s.detail() << ", want " << detail;
    }
    return ::testing::AssertionSuccess();
}
::testing::AssertionResult isOk(const Status& s) { return hasStatus(s, StatusCode::kOk, ""); }

// ---- files -------------------------------------------------------------------------------

// A fresh directory per test (mkdtemp: host and cross runs may share /tmp), removed after.
class TempDir {
public:
    TempDir() {
        std::string pattern = (std::filesystem::path(::testing::TempDir()) / "vtm_hal_file_XXXXXX").string();
        std::vector<char> buffer(pattern.begin(), pattern.end());
        buffer.push_back('\0');
        const char* made = mkdtemp(buffer.data());
        path_ = (made != nullptr) ? made : "";
    }
    ~TempDir() {
        std::error_code ignored;
        std::filesystem::remove_all(path_, ignored);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    [[nodiscard]] std::string file(const std::string& name) const { return path_ + "/" + name; }
    [[nodiscard]] bool ok() const { return !path_.empty(); }

private:
    std::string path_;
};

void writeBytes(const std::string& path, const Bytes& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    ASSERT_TRUE(out.good()) << path;
}
void writeText(const std::string& path, const std::string& text) {
    writeBytes(path, Bytes(text.begin(), text.end()));
}

// ---- images ------------------------------------------------------------------------------

struct Image {
    int w = 0;
    int h = 0;
    Samples px;  // row-major, one sample per pixel
};

// A pattern with every value class: gradients, a ramp through the full range, the extremes.
Image pattern(int w, int h, std::uint32_t max_value, std::uint32_t seed) {
    Image img{w, h, Samples(static_cast<std::size_t>(w * h))};
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const std::uint32_t v = (static_cast<std::uint32_t>(x) * 2654435761U + static_cast<std::uint32_t>(y) * 40503U +
                                     seed * 977U) % (max_value + 1U);
            img.px[static_cast<std::size_t>(y * w + x)] = static_cast<std::uint16_t>(v);
        }
    }
    img.px[0] = 0;
    img.px.back() = static_cast<std::uint16_t>(max_value);
    return img;
}

// Binary PGM, header with a comment and mixed whitespace; 2-byte samples big-endian.
Bytes pgm(const Image& img, unsigned maxval) {
    const std::string head = "P5\n# written by file_driver_test\n" + std::to_string(img.w) + "\t" +
                             std::to_string(img.h) + "\n" + std::to_string(maxval) + "\n";
    Bytes b(head.begin(), head.end());
    for (const std::uint16_t v : img.px) {
        if (maxval > 255U) {
            b.push_back(static_cast<std::uint8_t>(v >> 8U));
        }
        b.push_back(static_cast<std::uint8_t>(v & 0xFFU));
    }
    return b;
}

// ---- a PNG encoder with stored (uncompressed) deflate blocks -------------------------------

std::uint32_t crc32(const std::uint8_t* p, std::size_t n) {
    std::uint32_t crc = 0xFFFFFFFFU;
    for (std::size_t i = 0; i < n; ++i) {
        crc ^= p[i];
        for (int k = 0; k < 8; ++k) {
            crc = (crc >> 1U) ^ (0xEDB88320U & (0U - (crc & 1U)));
        }
    }
    return ~crc;
}
void put32(Bytes& b, std::uint32_t v) {
    for (int shift = 24; shift >= 0; shift -= 8) {
        b.push_back(static_cast<std::uint8_t>(v >> static_cast<unsigned>(shift)));
    }
}
void pngChunk(Bytes& out, const char* type, const Bytes& data) {
    put32(out, static_cast<std::uint32_t>(data.size()));
    Bytes body(type, type + 4);
    body.insert(body.end(), data.begin(), data.end());
    out.insert(out.end(), body.begin(), body.end());
    put32(out, crc32(body.data(), body.size()));
}
std::uint32_t adler32(const Bytes& data) {
    std::uint32_t a = 1, b = 0;
    for (const std::uint8_t v : data) {
        a = (a + v) % 65521U;
        b = (b + a) % 65521U;
    }
    return (b << 16U) | a;
}
Bytes zlibStored(const Bytes& raw) {
    Bytes z = {0x78, 0x01};
    std::size_t pos = 0;
    do {
        const std::size_t n = std::min<std::size_t>(65535U, raw.size() - pos);
        z.push_back(pos + n == raw.size() ? 1U : 0U);
        z.push_back(static_cast<std::uint8_t>(n & 0xFFU));
        z.push_back(static_cast<std::uint8_t>(n >> 8U));
        z.push_back(static_cast<std::uint8_t>(~n & 0xFFU));
        z.push_back(static_cast<std::uint8_t>((~n >> 8U) & 0xFFU));
        z.insert(z.end(), raw.begin() + static_cast<std::ptrdiff_t>(pos), raw.begin() + static_cast<std::ptrdiff_t>(pos + n));
        pos += n;
    } while (pos < raw.size());
    put32(z, adler32(raw));
    return z;
}

struct PngSpec {
    PngSpec(int w_, int h_, int depth_, int colour_, int interlace_ = 0)
        : w(w_), h(h_), depth(depth_), colour(colour_), interlace(interlace_) {}
    int w = 0;
    int h = 0;
    int depth = 8;
    int colour = 0;  // 0 grey, 2 RGB, 3 palette, 4 grey+alpha, 6 RGBA
    int interlace = 0;
    Bytes plte;
    Bytes trns;
    std::size_t idat_chunk = 1U << 30U;  // IDAT split into chunks of this many bytes
};
int channelsOf(int colour) { return colour == 2 ? 3 : colour == 4 ? 2 : colour == 6 ? 4 : 1; }

// samples: w * h * channels values, packed per row (MSB first below 8 bits, big-endian at 16).
Bytes pngStored(const PngSpec& s, const Samples& samples, const Bytes& zlib_override = {}) {
    const int per_row = s.w * channelsOf(s.colour);
    Bytes raw;
    for (int y = 0; y < s.h; ++y) {
        raw.push_back(0);  // filter type None
        std::uint32_t acc = 0;
        int bits = 0;
        for (int i = 0; i < per_row; ++i) {
            const std::uint16_t v = samples[static_cast<std::size_t>(y * per_row + i)];
            if (s.depth == 16) {
                raw.push_back(static_cast<std::uint8_t>(v >> 8U));
                raw.push_back(static_cast<std::uint8_t>(v & 0xFFU));
                continue;
            }
            acc = (acc << static_cast<unsigned>(s.depth)) | v;
            bits += s.depth;
            if (bits == 8) {
                raw.push_back(static_cast<std::uint8_t>(acc));
                acc = 0;
                bits = 0;
            }
        }
        if (bits > 0) {
            raw.push_back(static_cast<std::uint8_t>(acc << static_cast<unsigned>(8 - bits)));
        }
    }
    Bytes out = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    Bytes ihdr;
    put32(ihdr, static_cast<std::uint32_t>(s.w));
    put32(ihdr, static_cast<std::uint32_t>(s.h));
    ihdr.insert(ihdr.end(), {static_cast<std::uint8_t>(s.depth), static_cast<std::uint8_t>(s.colour), 0, 0,
                             static_cast<std::uint8_t>(s.interlace)});
    pngChunk(out, "IHDR", ihdr);
    if (!s.plte.empty()) {
        pngChunk(out, "PLTE", s.plte);
    }
    if (!s.trns.empty()) {
        pngChunk(out, "tRNS", s.trns);
    }
    const Bytes z = zlib_override.empty() ? zlibStored(raw) : zlib_override;
    for (std::size_t pos = 0; pos < z.size(); pos += s.idat_chunk) {
        const std::size_t n = std::min(s.idat_chunk, z.size() - pos);
        pngChunk(out, "IDAT", Bytes(z.begin() + static_cast<std::ptrdiff_t>(pos), z.begin() + static_cast<std::ptrdiff_t>(pos + n)));
    }
    pngChunk(out, "IEND", {});
    return out;
}

// A zlib stream that inflates to `n` zero bytes (n - 1 a multiple of 258) in fixed-Huffman
// codes: one literal 0, then length-258 distance-1 copies. Tiny input, huge output.
Bytes zlibZeros(std::size_t n) {
    Bytes z = {0x78, 0x01};
    std::uint32_t acc = 0;
    int bits = 0;
    auto putBits = [&](std::uint32_t v, int count) {  // LSB first
        for (int i = 0; i < count; ++i) {
            acc |= ((v >> static_cast<unsigned>(i)) & 1U) << static_cast<unsigned>(bits);
            if (++bits == 8) {
                z.push_back(static_cast<std::uint8_t>(acc));
                acc = 0;
                bits = 0;
            }
        }
    };
    auto putCode = [&](std::uint32_t code, int len) {  // Huffman codes go MSB first
        for (int i = len - 1; i >= 0; --i) {
            putBits((code >> static_cast<unsigned>(i)) & 1U, 1);
        }
    };
    putBits(1, 1);     // BFINAL
    putBits(1, 2);     // BTYPE 01: fixed Huffman codes
    putCode(0x30, 8);  // literal 0
    for (std::size_t done = 1; done < n; done += 258) {
        putCode(0xC5, 8);  // length code 285 (258 bytes)
        putCode(0, 5);     // distance code 0 (distance 1)
    }
    putCode(0, 7);  // end of block
    if (bits > 0) {
        z.push_back(static_cast<std::uint8_t>(acc));
    }
    put32(z, static_cast<std::uint32_t>((n % 65521U) << 16U) | 1U);
    return z;
}

// 8-bit PNG with real deflate compression and adaptive filters (stb_image_write).
Bytes pngCompressed(int w, int h, int comp, const Bytes& interleaved) {
    Bytes out;
    auto sink = [](void* ctx, void* data, int size) {
        auto* o = static_cast<Bytes*>(ctx);
        const auto* p = static_cast<const std::uint8_t*>(data);
        o->insert(o->end(), p, p + size);
    };
    EXPECT_NE(stbi_write_png_to_func(sink, &out, w, h, comp, interleaved.data(), w * comp), 0);
    return out;
}
Bytes toBytes(const Samples& s) {
    Bytes b;
    for (const std::uint16_t v : s) {
        b.push_back(static_cast<std::uint8_t>(v));
    }
    return b;
}

// The documented colour-to-grey rule.
std::uint16_t greyOf(std::uint32_t r, std::uint32_t g, std::uint32_t b) {
    return static_cast<std::uint16_t>((77U * r + 150U * g + 29U * b + 128U) >> 8U);
}

// ---- manifests ---------------------------------------------------------------------------

std::string header(int w, int h, int depth, const std::string& extra = "") {
    return "vtm-frames 1\n# recorded by file_driver_test\ncamera_id 3\nwidth_px " + std::to_string(w) +
           "\nheight_px " + std::to_string(h) + "\nbit_depth " + std::to_string(depth) + "\n" + extra;
}
std::string frameLine(std::uint32_t seq, std::uint64_t ts, std::uint32_t exposure, const std::string& path) {
    return "frame " + std::to_string(seq) + " " + std::to_string(ts) + " " + std::to_string(exposure) + " " + path +
           "\n";
}

class FileCameraTest : public ::testing::Test {
protected:
    void SetUp() override { ASSERT_TRUE(dir_.ok()); }

    Status initWith(const std::string& manifest) {
        manifest_path_ = dir_.file("frames.txt");
        writeText(manifest_path_, manifest);
        FileCamera::Config config;
        config.manifest_path = manifest_path_.c_str();
        return camera_->init(config);
    }
    Status capture8(const Image& expect_size, std::vector<std::uint8_t>& px, FrameInfo& info) {
        px.assign(static_cast<std::size_t>(expect_size.w * expect_size.h), 0xEEU);
        return camera_->capture(ImageView<std::uint8_t>(px.data(), expect_size.w, expect_size.h), info);
    }
    Status capture16(const Image& expect_size, std::vector<std::uint16_t>& px, FrameInfo& info) {
        px.assign(static_cast<std::size_t>(expect_size.w * expect_size.h), 0xEEEEU);
        return camera_->capture16(ImageView<std::uint16_t>(px.data(), expect_size.w, expect_size.h), info);
    }
    // Captures the next 8-bit frame and compares it with `want`, pixel for pixel.
    void expectFrame8(const Image& want) {
        std::vector<std::uint8_t> px;
        FrameInfo info;
        ASSERT_TRUE(isOk(capture8(want, px, info)));
        ASSERT_EQ(px.size(), want.px.size());
        for (std::size_t i = 0; i < px.size(); ++i) {
            ASSERT_EQ(px[i], want.px[i]) << "pixel " << i;
        }
    }
    void expectFrame16(const Image& want) {
        std::vector<std::uint16_t> px;
        FrameInfo info;
        ASSERT_TRUE(isOk(capture16(want, px, info)));
        for (std::size_t i = 0; i < px.size(); ++i) {
            ASSERT_EQ(px[i], want.px[i]) << "pixel " << i;
        }
    }

    TempDir dir_;
    std::string manifest_path_;
    // About 150 KiB: on the heap in the test, created before any NoHeapScope.
    std::unique_ptr<FileCamera> camera_ = std::make_unique<FileCamera>();
};

// ==== FileCamera: configuration and manifest ===============================================

TEST(FileCameraConfig, ValidateNamesTheBadField) {
    FileCamera::Config c;
    EXPECT_TRUE(hasStatus(c.validate(), StatusCode::kInvalidConfig, "FileCamera::Config: manifest_path is null"));
    c.manifest_path = "";
    EXPECT_TRUE(hasStatus(c.validate(), StatusCode::kInvalidConfig, "FileCamera::Config: manifest_path is empty"));
    const std::string long_path(fl::kMaxPathChars + 1U, 'a');
    c.manifest_path = long_path.c_str();
    EXPECT_TRUE(hasStatus(c.validate(), StatusCode::kInvalidConfig,
                          "FileCamera::Config: manifest_path longer than kMaxPathChars (255)"));
    const std::string longest(fl::kMaxPathChars, 'a');
    c.manifest_path = longest.c_str();
    EXPECT_TRUE(isOk(c.validate()));
    FileCamera camera;
    c.manifest_path = nullptr;
    EXPECT_EQ(camera.init(c).code(), StatusCode::kInvalidConfig);
}

std::string manyFields(int n) {
    std::string s;
    for (int i = 0; i < n; ++i) {
        s += " 1";
    }
    return s;
}

struct ManifestCase {
    const char* name;
    std::string text;
    StatusCode code;
    const char* reason;
    std::int64_t line;
};

TEST_F(FileCameraTest, ManifestErrorsNameTheFieldAndLine) {
    const std::string ok_header = header(4, 3, 8);  // 6 lines
    const std::string f1 = frameLine(1, 100, 10, "a.pgm");
    const std::string model = "model pinhole 100 100 1.5 1 0 0 0 0 0\n";
    const std::string path128(128, 'p');
    const std::vector<ManifestCase> cases = {
        {"empty file", "", StatusCode::kCorruptData, "manifest: first line must be 'vtm-frames 1'", 1},
        {"wrong magic", "vtm-framez 1\n", StatusCode::kCorruptData, "manifest: first line must be 'vtm-frames 1'", 1},
        {"version 2", "vtm-frames 2\n", StatusCode::kUnsupported, "manifest: version other than 1", 1},
        {"unknown key", ok_header + "colour red\n" + f1, StatusCode::kCorruptData, "manifest: unknown key", 7},
        {"duplicate key", ok_header + "camera_id 4\n" + f1, StatusCode::kCorruptData, "manifest: key given twice", 7},
        {"camera_id 256", "vtm-frames 1\ncamera_id 256\n", StatusCode::kCorruptData,
         "manifest: camera_id must be one integer 0..255", 2},
        {"camera_id -1", "vtm-frames 1\ncamera_id -1\n", StatusCode::kCorruptData,
         "manifest: camera_id must be one integer 0..255", 2},
        {"width 0", "vtm-frames 1\nwidth_px 0\n", StatusCode::kCorruptData,
         "manifest: width_px must be one positive integer", 2},
        {"width two values", "vtm-frames 1\nwidth_px 4 5\n", StatusCode::kCorruptData,
         "manifest: width_px must be one positive integer", 2},
        {"width 4097", "vtm-frames 1\nwidth_px 4097\n", StatusCode::kUnsupported,
         "manifest: width_px above kMaxFrameWidthPx (4096)", 2},
        {"height abc", "vtm-frames 1\nheight_px abc\n", StatusCode::kCorruptData,
         "manifest: height_px must be one positive integer", 2},
        {"height 4097", "vtm-frames 1\nheight_px 4097\n", StatusCode::kUnsupported,
         "manifest: height_px above kMaxFrameHeightPx (4096)", 2},
        {"bit_depth 7", "vtm-frames 1\nbit_depth 7\n", StatusCode::kCorruptData,
         "manifest: bit_depth must be one integer 8..16", 2},
        {"bit_depth 17", "vtm-frames 1\nbit_depth 17\n", StatusCode::kCorruptData,
         "manifest: bit_depth must be one integer 8..16", 2},
        {"camera_id missing", "vtm-frames 1\nwidth_px 4\nheight_px 3\nbit_depth 8\n" + f1, StatusCode::kCorruptData,
         "manifest: camera_id missing before the first frame line", 5},
        {"width missing", "vtm-frames 1\ncamera_id 1\nheight_px 3\nbit_depth 8\n" + f1, StatusCode::kCorruptData,
         "manifest: width_px missing before the first frame line", 5},
        {"height missing", "vtm-frames 1\ncamera_id 1\nwidth_px 4\nbit_depth 8\n" + f1, StatusCode::kCorruptData,
         "manifest: height_px missing before the first frame line", 5},
        {"bit_depth missing", "vtm-frames 1\ncamera_id 1\nwidth_px 4\nheight_px 3\n", StatusCode::kCorruptData,
         "manifest: bit_depth missing before the first frame line", 5},
        {"frame too large", header(2048, 1024, 8) + f1, StatusCode::kUnsupported,
         "manifest: width_px * height_px above kMaxFramePixels (1048576)", 7},
        {"model kind", ok_header + "model fisheye 1 2 3\n" + f1, StatusCode::kCorruptData,
         "manifest: model kind must be pinhole, cahv or cahvor", 7},
        {"model count", ok_header + "model pinhole 100 100 1 1 0 0 0 0\n" + f1, StatusCode::kCorruptData,
         "manifest: model has the wrong number of values (pinhole 9, cahv 12, cahvor 18)", 7},
        {"model nan", ok_header + "model pinhole 100 nan 1 1 0 0 0 0 0\n" + f1, StatusCode::kCorruptData,
         "manifest: model value is not a finite number", 7},
        {"model text", ok_header + "model pinhole 100 1O0 1 1 0 0 0 0 0\n" + f1, StatusCode::kCorruptData,
         "manifest: model value is not a finite number", 7},
        // The model's own rules are validateCameraModel's (vtm/core), reported on the model's line.
        {"model fx 0", ok_header + "model pinhole 0 100 1 1 0 0 0 0 0\n" + f1, StatusCode::kCorruptData,
         "camera model: fx_px must be positive", 7},
        {"model fy -1", ok_header + "model pinhole 100 -1 1 1 0 0 0 0 0\n" + f1, StatusCode::kCorruptData,
         "camera model: fy_px must be positive", 7},
        {"model folds", ok_header + "model pinhole 1 1 1.5 1 -1 0 0 0 0\n" + f1, StatusCode::kCorruptData,
         "camera model: k1 k2 k3 fold the image over (radial distortion not invertible to the corners)", 7},
        {"cahv A", ok_header + "model cahv 0 0 0  0 0 2  100 0 1.5  0 100 1\n" + f1, StatusCode::kCorruptData,
         "camera model: A is not a unit vector", 7},
        {"cahv H", ok_header + "model cahv 0 0 0  0 0 1  0 0 1.5  0 100 1\n" + f1, StatusCode::kCorruptData,
         "camera model: H is parallel to A", 7},
        {"cahvor O", ok_header + "model cahvor 0 0 0  0 0 1  100 0 1.5  0 100 1  0 0.1 1  0 0 0\n" + f1,
         StatusCode::kCorruptData, "camera model: O is not a unit vector", 7},
        {"model twice", ok_header + model + model + f1, StatusCode::kCorruptData, "manifest: key given twice", 8},
        {"frame fields", ok_header + "frame 1 100 10\n", StatusCode::kCorruptData,
         "manifest: frame line needs: frame <sequence> <timestamp_ns> <exposure_us> <path>", 7},
        {"frame sequence", ok_header + frameLine(1, 100, 10, "a.pgm") + "frame 4294967296 200 10 b.pgm\n",
         StatusCode::kCorruptData, "manifest: frame sequence is not an integer 0..4294967295", 8},
        {"frame sequence sign", ok_header + "frame -1 100 10 a.pgm\n", StatusCode::kCorruptData,
         "manifest: frame sequence is not an integer 0..4294967295", 7},
        {"frame timestamp", ok_header + "frame 1 1.5 10 a.pgm\n", StatusCode::kCorruptData,
         "manifest: frame timestamp_ns is not an integer 0..18446744073709551615", 7},
        {"frame timestamp overflow", ok_header + "frame 1 18446744073709551616 10 a.pgm\n", StatusCode::kCorruptData,
         "manifest: frame timestamp_ns is not an integer 0..18446744073709551615", 7},
        {"frame exposure", ok_header + "frame 1 100 99999999999 a.pgm\n", StatusCode::kCorruptData,
         "manifest: frame exposure_us is not an integer 0..4294967295", 7},
        {"absolute path", ok_header + frameLine(1, 100, 10, "/tmp/a.pgm"), StatusCode::kCorruptData,
         "manifest: frame path is absolute (must be relative to the manifest)", 7},
        {"path too long", ok_header + frameLine(1, 100, 10, path128), StatusCode::kUnsupported,
         "manifest: frame path longer than kMaxFramePathChars (127)", 7},
        {"timestamp backwards", ok_header + f1 + frameLine(2, 200, 10, "b.pgm") + frameLine(3, 150, 10, "c.pgm"),
         StatusCode::kOutOfOrder, "manifest: frame timestamp_ns not greater than the previous frame's", 9},
        {"timestamp repeated", ok_header + f1 + frameLine(2, 100, 10, "b.pgm"), StatusCode::kOutOfOrder,
         "manifest: frame timestamp_ns not greater than the previous frame's", 8},
        {"sequence backwards", ok_header + frameLine(5, 100, 10, "a.pgm") + frameLine(5, 200, 10, "b.pgm"),
         StatusCode::kOutOfOrder, "manifest: frame sequence not greater than the previous frame's", 8},
        {"key after frames", ok_header + f1 + "bit_depth 8\n", StatusCode::kCorruptData,
         "manifest: header key after the first frame line", 8},
        {"no frame", ok_header + "# nothing recorded\n", StatusCode::kNoData, "manifest: no frame line", 8},
        {"too many fields", ok_header + "frame" + manyFields(48) + "\n", StatusCode::kCorruptData,
         "manifest: line has more than kMaxLineTokens (48) fields", 7},
        {"line too long", ok_header + "# " + std::string(fl::kMaxLineChars, 'c') + "\n" + f1, StatusCode::kUnsupported,
         "manifest: line longer than kMaxLineChars (2047)", 7},
        {"NUL byte", ok_header + std::string("frame 1 100 10 a\0.pgm\n", 22), StatusCode::kCorruptData,
         "manifest: NUL byte in a line", 7},
    };
    for (const ManifestCase& c : cases) {
        EXPECT_TRUE(hasStatus(initWith(c.text), c.code, c.reason, c.line)) << c.name;
        std::vector<std::uint8_t> px(12);
        FrameInfo info;
        EXPECT_EQ(camera_->capture(ImageView<std::uint8_t>(px.data(), 4, 3), info).code(),
                  StatusCode::kNotInitialized)
            << c.name;
    }
}

TEST_F(FileCameraTest, ManifestCapacityLimitsNameTheLine) {
    std::string text = header(4, 3, 8);  // 6 lines
    for (std::uint32_t i = 0; i < fl::kMaxFrames; ++i) {
        text += frameLine(i, 1000U + i, 10, "a.pgm");
    }
    ASSERT_TRUE(isOk(initWith(text)));
    EXPECT_EQ(camera_->frameCount(), fl::kMaxFrames);
    text += frameLine(5000, 999999, 10, "a.pgm");
    EXPECT_TRUE(hasStatus(initWith(text), StatusCode::kUnsupported, "manifest: more than kMaxFrames (1024) frame lines",
                          static_cast<std::int64_t>(6U + fl::kMaxFrames + 1U)));

    std::string many_lines = header(4, 3, 8) + frameLine(1, 100, 10, "a.pgm");  // 7 lines
    for (std::size_t i = 7; i < fl::kMaxTextLines; ++i) {
        many_lines += "#\n";
    }
    ASSERT_TRUE(isOk(initWith(many_lines)));
    many_lines += "#\n";
    EXPECT_TRUE(hasStatus(initWith(many_lines), StatusCode::kUnsupported,
                          "manifest: more than kMaxTextLines (65536) lines",
                          static_cast<std::int64_t>(fl::kMaxTextLines + 1U)));
}

TEST_F(FileCameraTest, MissingManifestIsIoError) {
    FileCamera::Config config;
    const std::string path = dir_.file("no_such_manifest.txt");
    config.manifest_path = path.c_str();
    EXPECT_TRUE(hasStatus(camera_->init(config), StatusCode::kIoError, "manifest: cannot open file", ENOENT));
}

TEST_F(FileCameraTest, UnreadableManifestIsIoError) {
    FileCamera::Config config;
    const std::string directory = dir_.file("");  // opens, but read() fails
    config.manifest_path = directory.c_str();
    EXPECT_TRUE(hasStatus(camera_->init(config), StatusCode::kIoError, "manifest: read failed", EISDIR));
}

TEST(FrameManifest, LoadRefusesAPathLongerThanTheLimit) {
    const auto manifest = std::make_unique<FrameManifest>();
    const std::string long_path(fl::kMaxPathChars + 1U, 'a');
    EXPECT_TRUE(hasStatus(loadFrameManifest(long_path.c_str(), *manifest), StatusCode::kInvalidArgument,
                          "manifest: path longer than kMaxPathChars (255)"));
}

TEST_F(FileCameraTest, AcceptsCommentsBlankLinesCrlfAndTheLongestPath) {
    const std::string path127(127, 'q');
    const Image img = pattern(4, 3, 255, 1);
    writeBytes(dir_.file(path127), pgm(img, 255));
    ASSERT_TRUE(isOk(initWith("vtm-frames 1\r\n\r\n  # comment\r\ncamera_id 9\r\n\twidth_px   4\r\nheight_px 3\r\n"
                              "bit_depth 8\r\nframe 1 5 6 " +
                              path127 + "\r\n")));
    expectFrame8(img);
}

TEST_F(FileCameraTest, DescribeReportsTheManifestAndItsModel) {
    writeBytes(dir_.file("a.pgm"), pgm(pattern(4, 3, 255, 1), 255));
    ASSERT_TRUE(isOk(initWith(header(4, 3, 8, "model pinhole 800.5 801 1.5 1 -0.1 0.01 0.001 0.0002 -0.0003\n") +
                              frameLine(1, 100, 10, "a.pgm"))));
    CameraDescription d;
    ASSERT_TRUE(isOk(camera_->describe(d)));
    EXPECT_EQ(d.camera_id, 3U);
    EXPECT_EQ(d.bit_depth, 8U);
    EXPECT_EQ(d.width_px, 4);
    EXPECT_EQ(d.height_px, 3);
    EXPECT_EQ(d.model.kind, CameraModelKind::kPinholeBrown);
    EXPECT_EQ(d.model.width_px, 4U);
    EXPECT_EQ(d.model.height_px, 3U);
    EXPECT_EQ(d.model.fx_px, 800.5);
    EXPECT_EQ(d.model.fy_px, 801.0);
    EXPECT_EQ(d.model.cx_px, 1.5);
    EXPECT_EQ(d.model.k1, -0.1);
    EXPECT_EQ(d.model.p2, -0.0003);

    ASSERT_TRUE(isOk(initWith(header(4, 3, 8, "model cahvor 0.1 0.2 0.3  0 0 1  100 0 1.5  0 100 1  0.6 0 0.8  1 0.5 0.25\n") +
                              frameLine(1, 100, 10, "a.pgm"))));
    ASSERT_TRUE(isOk(camera_->describe(d)));
    EXPECT_EQ(d.model.kind, CameraModelKind::kCahvor);
    EXPECT_EQ(d.model.c[2], 0.3);
    EXPECT_EQ(d.model.a[2], 1.0);
    EXPECT_EQ(d.model.h[0], 100.0);
    EXPECT_EQ(d.model.v[2], 1.0);
    EXPECT_EQ(d.model.o[0], 0.6);
    EXPECT_EQ(d.model.r[2], 0.25);
}

TEST(FileCameraState, CallsBeforeInitAreNotInitialized) {
    static FileCamera camera;
    CameraDescription d;
    FrameInfo info;
    std::uint8_t px8[4] = {};
    std::uint16_t px16[4] = {};
    EXPECT_EQ(camera.describe(d).code(), StatusCode::kNotInitialized);
    EXPECT_EQ(camera.capture(ImageView<std::uint8_t>(px8, 2, 2), info).code(), StatusCode::kNotInitialized);
    EXPECT_EQ(camera.capture16(ImageView<std::uint16_t>(px16, 2, 2), info).code(), StatusCode::kNotInitialized);
}

// ==== FileCamera: frames =====================================================================

TEST_F(FileCameraTest, PlaysPgm8FramesPixelExactInOrder) {
    const Image a = pattern(5, 3, 255, 1);
    const Image b = pattern(5, 3, 200, 2);  // maxval 200: samples delivered as stored
    writeBytes(dir_.file("a.pgm"), pgm(a, 255));
    std::filesystem::create_directory(dir_.file("sub"));
    writeBytes(dir_.file("sub/b.pgm"), pgm(b, 200));
    ASSERT_TRUE(isOk(initWith(header(5, 3, 8) + frameLine(41, 1000000000ULL, 2500, "a.pgm") +
                              frameLine(43, 1100000000ULL, 2600, "sub/b.pgm"))));
    EXPECT_EQ(camera_->frameCount(), 2U);
    std::vector<std::uint8_t> px;
    FrameInfo info;
    ASSERT_TRUE(isOk(capture8(a, px, info)));
    EXPECT_EQ(Samples(px.begin(), px.end()), a.px);
    EXPECT_EQ(info.sequence, 41U);
    EXPECT_EQ(info.timestamp_ns, 1000000000ULL);
    EXPECT_EQ(info.exposure_us, 2500U);
    EXPECT_EQ(info.camera_id, 3U);
    EXPECT_EQ(info.bit_depth, 8U);
    EXPECT_EQ(info.width_px, 5);
    EXPECT_EQ(info.height_px, 3);
    ASSERT_TRUE(isOk(capture8(b, px, info)));
    EXPECT_EQ(Samples(px.begin(), px.end()), b.px);
    EXPECT_EQ(info.sequence, 43U);
    EXPECT_EQ(info.timestamp_ns, 1100000000ULL);
}

TEST_F(FileCameraTest, PlaysPgm16FramesBigEndianPixelExact) {
    const Image a = pattern(6, 4, 4095, 3);   // 12-bit camera, maxval 4095
    const Image b = pattern(6, 4, 4095, 4);   // written with maxval 65535 (as OpenCV does)
    const Image c = pattern(6, 4, 255, 5);    // 1-byte samples, widened
    writeBytes(dir_.file("a.pgm"), pgm(a, 4095));
    writeBytes(dir_.file("b.pgm"), pgm(b, 65535));
    writeBytes(dir_.file("c.pgm"), pgm(c, 255));
    ASSERT_TRUE(isOk(initWith(header(6, 4, 12) + frameLine(1, 10, 1, "a.pgm") + frameLine(2, 20, 1, "b.pgm") +
                              frameLine(3, 30, 1, "c.pgm"))));
    expectFrame16(a);
    expectFrame16(b);
    expectFrame16(c);

    // Full 16-bit range; 0x0102 would read 0x0201 with the bytes swapped.
    Image d = pattern(6, 4, 65535, 6);
    d.px[1] = 0x0102;
    writeBytes(dir_.file("d.pgm"), pgm(d, 65535));
    ASSERT_TRUE(isOk(initWith(header(6, 4, 16) + frameLine(1, 10, 1, "d.pgm"))));
    expectFrame16(d);
}

TEST_F(FileCameraTest, PlaysPng8GreyPixelExact) {
    const Image a = pattern(7, 5, 255, 7);
    const Image b = pattern(7, 5, 255, 8);
    writeBytes(dir_.file("a.png"), pngCompressed(7, 5, 1, toBytes(a.px)));
    PngSpec spec{7, 5, 8, 0};
    spec.idat_chunk = 5;  // many IDAT chunks: the decoder concatenates them
    writeBytes(dir_.file("b.png"), pngStored(spec, b.px));
    ASSERT_TRUE(isOk(initWith(header(7, 5, 8) + frameLine(1, 10, 1, "a.png") + frameLine(2, 20, 1, "b.png"))));
    expectFrame8(a);
    expectFrame8(b);
}

TEST_F(FileCameraTest, LowBitDepthGreyPngIsScaledTo8Bits) {
    Image one = pattern(9, 2, 1, 1);
    Image two = pattern(9, 2, 3, 2);
    Image four = pattern(9, 2, 15, 3);
    writeBytes(dir_.file("1.png"), pngStored({9, 2, 1, 0}, one.px));
    writeBytes(dir_.file("2.png"), pngStored({9, 2, 2, 0}, two.px));
    writeBytes(dir_.file("4.png"), pngStored({9, 2, 4, 0}, four.px));
    ASSERT_TRUE(isOk(initWith(header(9, 2, 8) + frameLine(1, 10, 1, "1.png") + frameLine(2, 20, 1, "2.png") +
                              frameLine(3, 30, 1, "4.png"))));
    for (Image* img : {&one, &two, &four}) {
        const std::uint32_t max = img == &one ? 1U : img == &two ? 3U : 15U;
        for (std::uint16_t& v : img->px) {
            v = static_cast<std::uint16_t>(v * 255U / max);
        }
        expectFrame8(*img);
    }
}

TEST_F(FileCameraTest, PlaysPng16GreyPixelExact) {
    Image a = pattern(6, 5, 65535, 9);
    a.px[1] = 0x0102;
    const Image b = pattern(6, 5, 4095, 10);
    writeBytes(dir_.file("a.png"), pngStored({6, 5, 16, 0}, a.px));
    // Grey + alpha, 16 bits: the alpha sample is ignored.
    Samples ga;
    for (const std::uint16_t v : b.px) {
        ga.push_back(v);
        ga.push_back(static_cast<std::uint16_t>(65535U - v));
    }
    writeBytes(dir_.file("b.png"), pngStored({6, 5, 16, 4}, ga));
    // An 8-bit PNG on a 16-bit camera: values widened unchanged.
    const Image c = pattern(6, 5, 255, 11);
    writeBytes(dir_.file("c.png"), pngCompressed(6, 5, 1, toBytes(c.px)));
    ASSERT_TRUE(isOk(initWith(header(6, 5, 16) + frameLine(1, 10, 1, "a.png") + frameLine(2, 20, 1, "b.png") +
                              frameLine(3, 30, 1, "c.png"))));
    expectFrame16(a);
    expectFrame16(b);
    expectFrame16(c);
}

TEST_F(FileCameraTest, ConvertsColourToGreyWithTheDocumentedFormula) {
    const int w = 16;
    const int h = 16;
    Bytes rgb, rgba, grey_alpha;
    Image want_rgb{w, h, {}}, want_ga{w, h, {}};
    for (int i = 0; i < w * h; ++i) {
        const auto r = static_cast<std::uint8_t>(i * 37 + 11);
        const auto g = static_cast<std::uint8_t>(i * 101 + 5);
        const auto b = static_cast<std::uint8_t>(255 - i);
        rgb.insert(rgb.end(), {r, g, b});
        rgba.insert(rgba.end(), {r, g, b, static_cast<std::uint8_t>(i)});
        grey_alpha.insert(grey_alpha.end(), {r, static_cast<std::uint8_t>(i)});
        want_rgb.px.push_back(greyOf(r, g, b));
        want_ga.px.push_back(r);
    }
    // The formula's anchors: grey stays grey, white stays 255.
    EXPECT_EQ(greyOf(255, 255, 255), 255);
    EXPECT_EQ(greyOf(0, 0, 0), 0);
    EXPECT_EQ(greyOf(77, 77, 77), 77);
    // Palette: four entries, with a tRNS chunk (alpha ignored).
    const Bytes plte = {255, 0, 0, 0, 255, 0, 0, 0, 255, 10, 200, 30};
    const Image indices = pattern(w, h, 3, 12);
    Image want_pal{w, h, {}};
    for (const std::uint16_t k : indices.px) {
        want_pal.px.push_back(greyOf(plte[k * 3U], plte[k * 3U + 1U], plte[k * 3U + 2U]));
    }
    PngSpec pal{w, h, 2, 3};
    pal.plte = plte;
    pal.trns = {255, 128};
    writeBytes(dir_.file("rgb.png"), pngCompressed(w, h, 3, rgb));
    writeBytes(dir_.file("rgba.png"), pngCompressed(w, h, 4, rgba));
    writeBytes(dir_.file("ga.png"), pngCompressed(w, h, 2, grey_alpha));
    writeBytes(dir_.file("pal.png"), pngStored(pal, indices.px));
    ASSERT_TRUE(isOk(initWith(header(w, h, 8) + frameLine(1, 10, 1, "rgb.png") + frameLine(2, 20, 1, "rgba.png") +
                              frameLine(3, 30, 1, "ga.png") + frameLine(4, 40, 1, "pal.png"))));
    expectFrame8(want_rgb);
    expectFrame8(want_rgb);
    expectFrame8(want_ga);
    expectFrame8(want_pal);
}

TEST_F(FileCameraTest, HonoursTheOutputStride) {
    const Image a = pattern(5, 3, 255, 13);
    writeBytes(dir_.file("a.pgm"), pgm(a, 255));
    ASSERT_TRUE(isOk(initWith(header(5, 3, 8) + frameLine(1, 10, 1, "a.pgm"))));
    std::vector<std::uint8_t> px(8 * 3, 0xEE);
    FrameInfo info;
    ASSERT_TRUE(isOk(camera_->capture(ImageView<std::uint8_t>(px.data(), 5, 3, 8), info)));
    for (int y = 0; y < 3; ++y) {
        for (int x = 0; x < 8; ++x) {
            const std::uint16_t want = x < 5 ? a.px[static_cast<std::size_t>(y * 5 + x)] : 0xEE;
            EXPECT_EQ(px[static_cast<std::size_t>(y * 8 + x)], want) << x << "," << y;
        }
    }
}

TEST_F(FileCameraTest, EndOfSequenceIsNoDataUntilRewind) {
    const Image a = pattern(4, 3, 255, 14);
    writeBytes(dir_.file("a.pgm"), pgm(a, 255));
    ASSERT_TRUE(isOk(initWith(header(4, 3, 8) + frameLine(1, 10, 1, "a.pgm") + frameLine(2, 20, 1, "a.pgm"))));
    std::vector<std::uint8_t> px;
    FrameInfo info;
    ASSERT_TRUE(isOk(capture8(a, px, info)));
    ASSERT_TRUE(isOk(capture8(a, px, info)));
    info.sequence = 777;
    EXPECT_TRUE(hasStatus(capture8(a, px, info), StatusCode::kNoData, "FileCamera: end of the recording", 2));
    EXPECT_TRUE(hasStatus(capture8(a, px, info), StatusCode::kNoData, "FileCamera: end of the recording", 2));
    EXPECT_EQ(info.sequence, 777U);  // unchanged on failure
    camera_->rewind();
    ASSERT_TRUE(isOk(capture8(a, px, info)));
    EXPECT_EQ(info.sequence, 1U);
}

TEST_F(FileCameraTest, WrongBufferIsRefusedWithoutConsumingAFrame) {
    const Image a = pattern(5, 3, 255, 15);
    writeBytes(dir_.file("a.pgm"), pgm(a, 255));
    ASSERT_TRUE(isOk(initWith(header(5, 3, 8) + frameLine(1, 10, 1, "a.pgm"))));
    std::vector<std::uint8_t> px(64);
    FrameInfo info;
    EXPECT_TRUE(hasStatus(camera_->capture(ImageView<std::uint8_t>(px.data(), 4, 3), info), StatusCode::kSizeMismatch,
                          "FileCamera: output buffer size differs from the camera's", 4));
    EXPECT_TRUE(hasStatus(camera_->capture(ImageView<std::uint8_t>(px.data(), 5, 4), info), StatusCode::kSizeMismatch,
                          "FileCamera: output buffer size differs from the camera's", 4));
    EXPECT_TRUE(hasStatus(camera_->capture(ImageView<std::uint8_t>(nullptr, 5, 3), info),
                          StatusCode::kInvalidArgument, "FileCamera: output view is empty or malformed"));
    EXPECT_EQ(camera_->nextFrameIndex(), 0U);
    expectFrame8(a);
}

TEST_F(FileCameraTest, CapturePathMustMatchTheBitDepth) {
    const Image a8 = pattern(4, 3, 255, 16);
    const Image a12 = pattern(4, 3, 4095, 17);
    writeBytes(dir_.file("a8.pgm"), pgm(a8, 255));
    writeBytes(dir_.file("a12.pgm"), pgm(a12, 4095));
    std::vector<std::uint8_t> px8;
    std::vector<std::uint16_t> px16;
    FrameInfo info;
    ASSERT_TRUE(isOk(initWith(header(4, 3, 12) + frameLine(1, 10, 1, "a12.pgm"))));
    EXPECT_TRUE(hasStatus(capture8(a12, px8, info), StatusCode::kUnsupported,
                          "FileCamera: camera has more than 8 bits per pixel: use capture16", 12));
    EXPECT_EQ(camera_->nextFrameIndex(), 0U);
    ASSERT_TRUE(isOk(capture16(a12, px16, info)));
    EXPECT_EQ(info.bit_depth, 12U);

    ASSERT_TRUE(isOk(initWith(header(4, 3, 8) + frameLine(1, 10, 1, "a8.pgm"))));
    EXPECT_TRUE(hasStatus(capture16(a8, px16, info), StatusCode::kUnsupported,
                          "FileCamera: camera has 8 bits per pixel: use capture", 8));
    expectFrame8(a8);
}

// A recording with damaged frames between good ones: each damage is reported once with
// its reason, and the next capture plays the next frame.
struct DamagedFrame {
    const char* file;
    Bytes bytes;  // empty: the file is not written (or is a directory, see below)
    StatusCode code;
    const char* reason;
    std::int64_t detail;  // kAnyDetail: not checked
};
constexpr std::int64_t kAnyDetail = -12345;

TEST_F(FileCameraTest, DamagedFramesAreReportedAndSkipped) {
    const Image good = pattern(4, 3, 255, 18);
    const Bytes good_pgm = pgm(good, 255);
    Bytes truncated_raster = good_pgm;
    truncated_raster.resize(truncated_raster.size() - 5);
    Bytes sample_above_maxval = pgm(pattern(4, 3, 200, 19), 200);
    sample_above_maxval.back() = 201;
    const std::string big_head = "P5 4 3 255\n";
    Bytes png_ok = pngStored({4, 3, 8, 0}, good.px);
    Bytes png_cut(png_ok.begin(), png_ok.begin() + 45);
    Bytes png_empty_idat(png_ok.begin(), png_ok.begin() + 33);  // an empty IDAT right after IHDR (fuzz finding)
    pngChunk(png_empty_idat, "IDAT", {});
    png_empty_idat.insert(png_empty_idat.end(), png_ok.begin() + 33, png_ok.end());
    Bytes png_bad_stream = pngStored({4, 3, 8, 0}, good.px, Bytes{0x78, 0x01, 0xFF, 0xFF, 0xFF, 0xFF});
    Bytes png_bad_filter_method = png_ok;
    png_bad_filter_method[27] = 1;  // IHDR filter method (the decoder does not check CRCs)
    auto ascii = [](const char* t) { return Bytes(t, t + std::strlen(t)); };
    const std::vector<DamagedFrame> frames = {
        {"missing.pgm", {}, StatusCode::kIoError, "frame: cannot open file", ENOENT},
        {"dir.pgm", {}, StatusCode::kIoError, "frame: read failed", EISDIR},
        {"empty.pgm", Bytes{}, StatusCode::kCorruptData, "frame: not a binary PGM (P5) or PNG file", 0},
        {"ascii.pgm", Bytes{'P', '2', '\n', '4', ' ', '3', '\n'}, StatusCode::kCorruptData,
         "frame: not a binary PGM (P5) or PNG file", 7},
        {"head.pgm", Bytes{'P', '5', '\n', '4', ' ', '3', '\n'}, StatusCode::kCorruptData, "PGM: header truncated", 7},
        {"raster.pgm", truncated_raster, StatusCode::kCorruptData, "PGM: raster truncated", 5},
        {"maxval0.pgm", Bytes{'P', '5', ' ', '4', ' ', '3', ' ', '0', '\n'}, StatusCode::kCorruptData,
         "PGM: maxval outside 1..65535", 0},
        {"maxval70000.pgm", Bytes{'P', '5', ' ', '4', ' ', '3', ' ', '7', '0', '0', '0', '0', '\n'},
         StatusCode::kCorruptData, "PGM: maxval outside 1..65535", 70000},
        {"notnumber.pgm", Bytes{'P', '5', ' ', 'x', ' ', '3', ' ', '2', '5', '5', '\n'}, StatusCode::kCorruptData,
         "PGM: header field is not a separated decimal number", 3},
        {"nospace.pgm", Bytes{'P', '5', ' ', '4', ' ', '3', ' ', '2', '5', '5', '#', '\n'}, StatusCode::kCorruptData,
         "PGM: maxval not followed by one whitespace byte", 10},
        {"zero.pgm", ascii("P5 0 3 255\n"), StatusCode::kCorruptData, "PGM: width or height is zero", 0},
        {"digits.pgm", ascii("P5 123456789 3 255\n"), StatusCode::kCorruptData, "PGM: header number too large", 11},
        {"above.pgm", sample_above_maxval, StatusCode::kCorruptData, "PGM: sample exceeds maxval", 201},
        {"width.pgm", pgm(pattern(5, 3, 255, 1), 255), StatusCode::kSizeMismatch,
         "frame: width differs from the manifest's width_px", 5},
        {"height.pgm", pgm(pattern(4, 2, 255, 1), 255), StatusCode::kSizeMismatch,
         "frame: height differs from the manifest's height_px", 2},
        {"wide.pgm", pgm(good, 256), StatusCode::kSizeMismatch, "frame: 16-bit samples for an 8-bit camera", 256},
        {"cut.png", png_cut, StatusCode::kCorruptData, "PNG: stb_image rejected the data (corrupt stream)", 0},
        {"emptyidat.png", png_empty_idat, StatusCode::kCorruptData, "PNG: empty IDAT chunk", 33},
        {"ihdr.png", Bytes(png_ok.begin(), png_ok.begin() + 20), StatusCode::kCorruptData,
         "PNG: IHDR chunk missing or truncated", 20},
        {"zero.png", pngStored({0, 3, 8, 0}, {}), StatusCode::kCorruptData, "PNG: width or height is zero", 0},
        {"method.png", png_bad_filter_method, StatusCode::kCorruptData,
         "PNG: IHDR compression, filter or interlace method invalid", 0},
        {"stream.png", png_bad_stream, StatusCode::kCorruptData, "PNG: stb_image rejected the data (corrupt stream)", 0},
        {"bomb.png", pngStored({4, 3, 8, 0}, good.px, zlibZeros(1U + 258U * 40000U)), StatusCode::kCorruptData,
         "PNG: data inflates beyond the static pool", kAnyDetail},
        {"width.png", pngStored({5, 3, 8, 0}, pattern(5, 3, 255, 1).px), StatusCode::kSizeMismatch,
         "frame: width differs from the manifest's width_px", 5},
        {"wide.png", pngStored({4, 3, 16, 0}, good.px), StatusCode::kSizeMismatch,
         "frame: 16-bit samples for an 8-bit camera", 16},
        {"interlaced.png", pngStored({4, 3, 8, 0, 1}, good.px), StatusCode::kUnsupported,
         "PNG: interlaced (Adam7) frames are not supported", 0},
        {"rgb16.png", pngStored({4, 3, 16, 2}, Samples(36, 7)), StatusCode::kUnsupported,
         "PNG: 16-bit colour frames are not supported", 2},
        {"depth.png", pngStored({4, 3, 4, 2}, Samples(36, 1)), StatusCode::kCorruptData,
         "PNG: IHDR bit depth and colour type do not combine", 4},
    };
    std::filesystem::create_directory(dir_.file("dir.pgm"));
    std::string text = header(4, 3, 8);
    std::uint32_t seq = 1;
    for (const DamagedFrame& f : frames) {
        if (f.code != StatusCode::kIoError) {
            writeBytes(dir_.file(f.file), f.bytes);
        }
        text += frameLine(seq, seq * 10U, 1, f.file);
        ++seq;
        text += frameLine(seq, seq * 10U, 1, "good.pgm");
        ++seq;
    }
    writeBytes(dir_.file("good.pgm"), good_pgm);
    ASSERT_TRUE(isOk(initWith(text)));
    for (const DamagedFrame& f : frames) {
        std::vector<std::uint8_t> px;
        FrameInfo info;
        const Status s = capture8(good, px, info);
        EXPECT_TRUE(f.detail == kAnyDetail ? hasStatus(s, f.code, f.reason) : hasStatus(s, f.code, f.reason, f.detail))
            << f.file;
        expectFrame8(good);
    }
}

TEST_F(FileCameraTest, SampleAboveTheBitDepthIsCorruptData) {
    Image a = pattern(4, 3, 4095, 20);
    a.px[5] = 5000;
    writeBytes(dir_.file("a.pgm"), pgm(a, 65535));
    writeBytes(dir_.file("a.png"), pngStored({4, 3, 16, 0}, a.px));
    ASSERT_TRUE(isOk(initWith(header(4, 3, 12) + frameLine(1, 10, 1, "a.pgm") + frameLine(2, 20, 1, "a.png"))));
    std::vector<std::uint16_t> px;
    FrameInfo info;
    EXPECT_TRUE(hasStatus(capture16(a, px, info), StatusCode::kCorruptData,
                          "frame: sample exceeds the camera's bit depth", 5000));
    EXPECT_TRUE(hasStatus(capture16(a, px, info), StatusCode::kCorruptData,
                          "frame: sample exceeds the camera's bit depth", 5000));
}

TEST_F(FileCameraTest, FileLargerThanTheBufferIsRefused) {
    Bytes huge = pgm(pattern(4, 3, 255, 1), 255);
    huge.resize(fl::kMaxFrameFileBytes + 1U, 0);
    writeBytes(dir_.file("huge.pgm"), huge);
    Bytes exact = pgm(pattern(4, 3, 255, 1), 255);
    exact.resize(fl::kMaxFrameFileBytes, 0);  // trailing bytes after the image are allowed
    writeBytes(dir_.file("exact.pgm"), exact);
    ASSERT_TRUE(isOk(initWith(header(4, 3, 8) + frameLine(1, 10, 1, "huge.pgm") + frameLine(2, 20, 1, "exact.pgm"))));
    std::vector<std::uint8_t> px;
    FrameInfo info;
    EXPECT_TRUE(hasStatus(capture8(pattern(4, 3, 255, 1), px, info), StatusCode::kUnsupported,
                          "frame: file larger than kMaxFrameFileBytes",
                          static_cast<std::int64_t>(fl::kMaxFrameFileBytes)));
    expectFrame8(pattern(4, 3, 255, 1));
}

// The pool formula (file_limits.hpp) holds for the largest frames it was sized for.
TEST_F(FileCameraTest, LargestPngFramesDecodeWithinTheStaticPool) {
    // 1024 x 1024 RGBA (4 bytes per pixel decoded), compressed.
    const int w = 1024;
    Bytes rgba(static_cast<std::size_t>(w * w * 4));
    Image want{w, w, {}};
    want.px.reserve(static_cast<std::size_t>(w * w));
    for (int y = 0; y < w; ++y) {
        for (int x = 0; x < w; ++x) {
            const auto r = static_cast<std::uint8_t>(x), g = static_cast<std::uint8_t>(y),
                       b = static_cast<std::uint8_t>((x + y) / 8);
            std::uint8_t* p = &rgba[static_cast<std::size_t>((y * w + x) * 4)];
            p[0] = r, p[1] = g, p[2] = b, p[3] = 255;
            want.px.push_back(greyOf(r, g, b));
        }
    }
    const Bytes big = pngCompressed(w, w, 4, rgba);
    ASSERT_LE(big.size(), fl::kMaxFrameFileBytes);
    writeBytes(dir_.file("big.png"), big);
    ASSERT_TRUE(isOk(initWith(header(w, w, 8) + frameLine(1, 10, 1, "big.png"))));
    expectFrame8(want);
    EXPECT_LE(FileCamera::decoderPoolHighWaterBytes(), fl::kPngPoolBytes);

    // 720 x 720 RGBA stored (incompressible size, about 2 MB) in 4 KiB IDAT chunks: the
    // IDAT buffer doubles up to 2 MiB.
    const int s = 720;
    Samples samples(static_cast<std::size_t>(s * s * 4));
    Image want2{s, s, {}};
    for (std::size_t i = 0; i < samples.size(); i += 4) {
        samples[i] = static_cast<std::uint16_t>(i % 251U);
        samples[i + 1] = static_cast<std::uint16_t>(i % 241U);
        samples[i + 2] = static_cast<std::uint16_t>(i % 239U);
        samples[i + 3] = 255;
        want2.px.push_back(greyOf(samples[i], samples[i + 1], samples[i + 2]));
    }
    PngSpec spec{s, s, 8, 6};
    spec.idat_chunk = 4096;
    const Bytes stored = pngStored(spec, samples);
    ASSERT_LE(stored.size(), fl::kMaxFrameFileBytes);
    writeBytes(dir_.file("stored.png"), stored);
    ASSERT_TRUE(isOk(initWith(header(s, s, 8) + frameLine(1, 10, 1, "stored.png"))));
    expectFrame8(want2);
    // The blocks the formula counts, and no more: stb_image's IDAT buffer (4 KiB doubled
    // until the IDAT data fits: 2 MiB here), the inflated scanlines, the image. Copies
    // left behind by growth would exceed this (the pool grows the last block in place).
    const std::size_t idat_bytes = zlibStored(Bytes(static_cast<std::size_t>(s * (4 * s + 1)))).size();
    std::size_t idat_buffer = 4096;
    while (idat_buffer < idat_bytes) {
        idat_buffer *= 2;
    }
    const std::size_t scanlines = static_cast<std::size_t>(s * (4 * s + 1));
    const std::size_t image = static_cast<std::size_t>(s * s * 4);
    EXPECT_LE(FileCamera::decoderPoolLastDecodeBytes(), idat_buffer + scanlines + image + 3U * fl::kPngPoolAlignment);
    EXPECT_LE(FileCamera::decoderPoolHighWaterBytes(), fl::kPngPoolBytes);
    std::printf("PNG pool: last decode %zu, high water %zu of %zu bytes\n", FileCamera::decoderPoolLastDecodeBytes(),
                FileCamera::decoderPoolHighWaterBytes(), fl::kPngPoolBytes);
}

// ==== FileOdometry ===========================================================================

constexpr std::uint64_t kT0 = 1000000000ULL;  // first pose, ns
constexpr double kSecond = 1e9;

std::string num(double v) {
    char buffer[40];
    std::snprintf(buffer, sizeof buffer, "%.17g", v);
    return buffer;
}
std::string poseLine(std::uint64_t t, const double p[3], const double q[4], const double var[6]) {
    std::string s = std::to_string(t);
    for (int i = 0; i < 3; ++i) {
        s += " " + num(p[i]);
    }
    for (int i = 0; i < 4; ++i) {
        s += " " + num(q[i]);
    }
    for (int i = 0; i < 6; ++i) {
        s += " " + num(var[i]);
    }
    return s + "\n";
}
void quatMultiply(const double a[4], const double b[4], double out[4]) {
    out[0] = a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3];
    out[1] = a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2];
    out[2] = a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1];
    out[3] = a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0];
}
// Angle (rad) of the rotation between two unit quaternions, sign-independent.
double angleBetween(const double a[4], const double b[4]) {
    const double conj[4] = {a[0], -a[1], -a[2], -a[3]};
    double d[4];
    quatMultiply(conj, b, d);
    const double v = std::sqrt(d[1] * d[1] + d[2] * d[2] + d[3] * d[3]);
    return 2.0 * std::atan2(v, std::fabs(d[0]));
}

const double kVar[6] = {1e-4, 2e-4, 3e-4, 1e-6, 2e-6, 3e-6};

class FileOdometryTest : public ::testing::Test {
protected:
    void SetUp() override { ASSERT_TRUE(dir_.ok()); }
    Status initWith(const std::string& log, std::uint64_t max_gap_ns = 0) {
        path_ = dir_.file("poses.txt");
        writeText(path_, log);
        FileOdometry::Config config;
        config.pose_log_path = path_.c_str();
        config.max_interpolation_gap_ns = max_gap_ns;
        return odometry_->init(config);
    }

    TempDir dir_;
    std::string path_;
    // About 1.4 MiB: on the heap in the test, created before any NoHeapScope.
    std::unique_ptr<FileOdometry> odometry_ = std::make_unique<FileOdometry>();
};

TEST(FileOdometryConfig, ValidateNamesTheBadField) {
    FileOdometry::Config c;
    EXPECT_TRUE(hasStatus(c.validate(), StatusCode::kInvalidConfig, "FileOdometry::Config: pose_log_path is null"));
    c.pose_log_path = "";
    EXPECT_TRUE(hasStatus(c.validate(), StatusCode::kInvalidConfig, "FileOdometry::Config: pose_log_path is empty"));
    const std::string long_path(fl::kMaxPathChars + 1U, 'a');
    c.pose_log_path = long_path.c_str();
    EXPECT_TRUE(hasStatus(c.validate(), StatusCode::kInvalidConfig,
                          "FileOdometry::Config: pose_log_path longer than kMaxPathChars (255)"));
    static FileOdometry odometry;
    PoseEstimate p;
    EXPECT_TRUE(hasStatus(odometry.poseAt(0, p), StatusCode::kNotInitialized,
                          "FileOdometry: poseAt before a successful init()"));
}

// Constant velocity along a line: the interpolation is exact up to rounding.
TEST_F(FileOdometryTest, ConstantVelocityLineInterpolatesToTheTruePosition) {
    const double p0[3] = {10.0, -5.0, 2.0};
    const double v[3] = {0.5, -0.25, 0.125};  // m/s
    const double identity[4] = {1.0, 0.0, 0.0, 0.0};
    std::string log = "vtm-poses 1\n# straight drive\n";
    for (int k = 0; k <= 4; ++k) {
        const double p[3] = {p0[0] + v[0] * k, p0[1] + v[1] * k, p0[2] + v[2] * k};
        log += poseLine(kT0 + static_cast<std::uint64_t>(k) * 1000000000ULL, p, identity, kVar);
    }
    ASSERT_TRUE(isOk(initWith(log)));
    EXPECT_EQ(odometry_->poseCount(), 5U);
    for (std::uint64_t dt : {0ULL, 1ULL, 123456789ULL, 999999999ULL, 1000000000ULL, 2500000000ULL, 3999999999ULL,
                             4000000000ULL}) {
        PoseEstimate pose;
        ASSERT_TRUE(isOk(odometry_->poseAt(kT0 + dt, pose))) << dt;
        EXPECT_EQ(pose.timestamp_ns, kT0 + dt);
        const double t = static_cast<double>(dt) / kSecond;
        for (int i = 0; i < 3; ++i) {
            EXPECT_NEAR(pose.position_m[i], p0[i] + v[i] * t, 1e-9) << dt;
        }
        EXPECT_EQ(pose.attitude_wxyz[0], 1.0);  // a constant attitude stays exactly put
        EXPECT_EQ(pose.attitude_wxyz[3], 0.0);
        EXPECT_NEAR(pose.covariance[0], kVar[0], 1e-18);
        EXPECT_NEAR(pose.covariance[35], kVar[5], 1e-18);
    }
}

// A constant-rate rotation sampled once a second (0.3 rad apart, 3 rad in total): the
// interpolated attitude lies on the true arc, about z and about a tilted axis, starting
// from a non-identity attitude, with every other sample written with the opposite sign.
TEST_F(FileOdometryTest, ConstantRateRotationInterpolatesOnTheArc) {
    const double rate = 0.3;  // rad/s
    const double axes[2][3] = {{0.0, 0.0, 1.0}, {1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0}};
    const double base[2][4] = {{1.0, 0.0, 0.0, 0.0}, {0.5, 0.5, 0.5, 0.5}};
    for (int c = 0; c < 2; ++c) {
        auto truth = [&](double t, double q[4]) {
            const double half = 0.5 * rate * t;
            const double step[4] = {std::cos(half), std::sin(half) * axes[c][0], std::sin(half) * axes[c][1],
                                    std::sin(half) * axes[c][2]};
            quatMultiply(base[c], step, q);
        };
        std::string log = "vtm-poses 1\n";
        for (int k = 0; k <= 10; ++k) {
            double q[4];
            truth(k, q);
            if (k % 2 == 1) {
                for (double& x : q) {
                    x = -x;
                }
            }
            const double p[3] = {0.0, 0.0, 0.0};
            log += poseLine(kT0 + static_cast<std::uint64_t>(k) * 1000000000ULL, p, q, kVar);
        }
        ASSERT_TRUE(isOk(initWith(log)));
        double worst = 0.0;
        for (std::uint64_t dt = 0; dt <= 10000000000ULL; dt += 37037037ULL) {
            PoseEstimate pose;
            ASSERT_TRUE(isOk(odometry_->poseAt(kT0 + dt, pose)));
            double q[4];
            truth(static_cast<double>(dt) / kSecond, q);
            worst = std::max(worst, angleBetween(q, pose.attitude_wxyz));
        }
        EXPECT_LT(worst, 1e-12) << "case " << c;
        std::printf("rotation case %d: worst attitude error %.3g rad\n", c, worst);
    }
}

TEST_F(FileOdometryTest, CovarianceInterpolatesLinearlyInBothFormats) {
    const double p[3] = {0.0, 0.0, 0.0};
    const double q[4] = {1.0, 0.0, 0.0, 0.0};
    const double var_b[6] = {3e-4, 4e-4, 5e-4, 3e-6, 4e-6, 5e-6};
    std::string full_b;
    for (int r = 0; r < 6; ++r) {
        for (int c = 0; c < 6; ++c) {
            full_b += " " + num(r == c ? 1.0 : 0.25 / (1 + r + c));
        }
    }
    const std::string log = "vtm-poses 1\n" + poseLine(kT0, p, q, kVar) + poseLine(kT0 + 1000000000ULL, p, q, var_b) +
                            std::to_string(kT0 + 2000000000ULL) + " 0 0 0 1 0 0 0" + full_b + "\n";
    ASSERT_TRUE(isOk(initWith(log)));
    PoseEstimate pose;
    ASSERT_TRUE(isOk(odometry_->poseAt(kT0 + 250000000ULL, pose)));
    for (int i = 0; i < 6; ++i) {
        EXPECT_NEAR(pose.covariance[i * 7], 0.75 * kVar[i] + 0.25 * var_b[i], 1e-18);
    }
    EXPECT_EQ(pose.covariance[1], 0.0);
    ASSERT_TRUE(isOk(odometry_->poseAt(kT0 + 2000000000ULL, pose)));
    EXPECT_EQ(pose.covariance[1], 0.25 / 2);
    EXPECT_EQ(pose.covariance[6], 0.25 / 2);
    EXPECT_EQ(pose.covariance[35], 1.0);
    ASSERT_TRUE(isOk(odometry_->poseAt(kT0 + 1500000000ULL, pose)));
    EXPECT_NEAR(pose.covariance[1], 0.5 * 0.125, 1e-18);
    EXPECT_NEAR(pose.covariance[0], 0.5 * (var_b[0] + 1.0), 1e-15);
}

TEST_F(FileOdometryTest, TimesOutsideTheLogAreNoData) {
    const double p[3] = {1.0, 2.0, 3.0};
    const double q[4] = {1.0, 0.0, 0.0, 0.0};
    ASSERT_TRUE(isOk(initWith("vtm-poses 1\n" + poseLine(kT0, p, q, kVar) + poseLine(kT0 + 100, p, q, kVar))));
    PoseEstimate pose;
    pose.position_m[0] = 42.0;
    EXPECT_TRUE(hasStatus(odometry_->poseAt(kT0 - 1, pose), StatusCode::kNoData,
                          "FileOdometry: time before the first logged pose", -1));
    EXPECT_TRUE(hasStatus(odometry_->poseAt(kT0 + 101, pose), StatusCode::kNoData,
                          "FileOdometry: time after the last logged pose", 1));
    EXPECT_TRUE(hasStatus(odometry_->poseAt(0, pose), StatusCode::kNoData,
                          "FileOdometry: time before the first logged pose", -1));
    EXPECT_EQ(pose.position_m[0], 42.0);
    ASSERT_TRUE(isOk(odometry_->poseAt(kT0, pose)));
    EXPECT_EQ(pose.position_m[2], 3.0);
    ASSERT_TRUE(isOk(odometry_->poseAt(kT0 + 100, pose)));

    // A single pose covers exactly its own time.
    ASSERT_TRUE(isOk(initWith("vtm-poses 1\n" + poseLine(kT0, p, q, kVar))));
    EXPECT_TRUE(isOk(odometry_->poseAt(kT0, pose)));
    EXPECT_EQ(odometry_->poseAt(kT0 + 1, pose).code(), StatusCode::kNoData);
}

TEST_F(FileOdometryTest, GapLongerThanTheLimitIsNoData) {
    const double p[3] = {0.0, 0.0, 0.0};
    const double q[4] = {1.0, 0.0, 0.0, 0.0};
    const std::string log = "vtm-poses 1\n" + poseLine(kT0, p, q, kVar) + poseLine(kT0 + 1000000000ULL, p, q, kVar) +
                            poseLine(kT0 + 4000000000ULL, p, q, kVar);
    ASSERT_TRUE(isOk(initWith(log, 1500000000ULL)));
    PoseEstimate pose;
    EXPECT_TRUE(isOk(odometry_->poseAt(kT0 + 500000000ULL, pose)));
    EXPECT_TRUE(hasStatus(odometry_->poseAt(kT0 + 2000000000ULL, pose), StatusCode::kNoData,
                          "FileOdometry: time inside a log gap longer than max_interpolation_gap_ns", 3000000000LL));
    EXPECT_TRUE(isOk(odometry_->poseAt(kT0 + 4000000000ULL, pose)));  // a logged pose is always served
    ASSERT_TRUE(isOk(initWith(log, 0)));                                // 0: no limit
    EXPECT_TRUE(isOk(odometry_->poseAt(kT0 + 2000000000ULL, pose)));
}

struct PoseLogCase {
    const char* name;
    std::string text;
    StatusCode code;
    const char* reason;
    std::int64_t line;
};

TEST_F(FileOdometryTest, PoseLogErrorsNameTheLine) {
    const double p[3] = {0.0, 0.0, 0.0};
    const double q[4] = {1.0, 0.0, 0.0, 0.0};
    const std::string l1 = poseLine(kT0, p, q, kVar);
    const std::string l2 = poseLine(kT0 + 10, p, q, kVar);
    const std::string head = "vtm-poses 1\n# t x y z qw qx qy qz var...\n";  // 2 lines
    const std::vector<PoseLogCase> cases = {
        {"empty", "", StatusCode::kCorruptData, "pose log: first line must be 'vtm-poses 1'", 1},
        {"magic", "vtm-pose 1\n", StatusCode::kCorruptData, "pose log: first line must be 'vtm-poses 1'", 1},
        {"version", "vtm-poses 3\n", StatusCode::kUnsupported, "pose log: version other than 1", 1},
        {"no pose", head, StatusCode::kNoData, "pose log: no pose line", 3},
        {"nan position", head + l1 + std::to_string(kT0 + 10) + " 0 nan 0 1 0 0 0 1 1 1 1 1 1\n",
         StatusCode::kCorruptData, "pose: position_m is not finite", 4},
        {"inf variance", head + std::to_string(kT0) + " 0 0 0 1 0 0 0 1 1 inf 1 1 1\n", StatusCode::kCorruptData,
         "pose: covariance is not finite", 3},
        {"non-unit quaternion", head + l1 + std::to_string(kT0 + 10) + " 0 0 0 0.9 0 0 0 1 1 1 1 1 1\n",
         StatusCode::kCorruptData, "pose: attitude_wxyz is not a unit quaternion", 4},
        {"negative variance", head + std::to_string(kT0) + " 0 0 0 1 0 0 0 1 1 1 1 -1 1\n", StatusCode::kCorruptData,
         "pose: covariance diagonal is negative", 3},
        {"13 fields", head + std::to_string(kT0) + " 0 0 0 1 0 0 0 1 1 1 1 1\n", StatusCode::kCorruptData,
         "pose log: a pose line needs 14 or 44 fields (timestamp_ns, x y z, qw qx qy qz, 6 variances or 36 "
         "covariances)",
         3},
        {"timestamp", head + "-5 0 0 0 1 0 0 0 1 1 1 1 1 1\n", StatusCode::kCorruptData,
         "pose log: timestamp_ns is not an integer 0..18446744073709551615", 3},
        {"value", head + std::to_string(kT0) + " 0 0 zero 1 0 0 0 1 1 1 1 1 1\n", StatusCode::kCorruptData,
         "pose log: pose value is not a number", 3},
        {"backwards", head + l1 + l2 + poseLine(kT0 + 5, p, q, kVar), StatusCode::kOutOfOrder,
         "pose log: timestamp_ns not greater than the previous pose's", 5},
        {"repeated", head + l1 + l1, StatusCode::kOutOfOrder, "pose log: timestamp_ns not greater than the previous pose's",
         4},
        {"line too long", head + "#" + std::string(3000, 'x') + "\n", StatusCode::kUnsupported,
         "pose log: line longer than kMaxLineChars (2047)", 3},
    };
    for (const PoseLogCase& c : cases) {
        EXPECT_TRUE(hasStatus(initWith(c.text), c.code, c.reason, c.line)) << c.name;
        PoseEstimate pose;
        EXPECT_EQ(odometry_->poseAt(kT0, pose).code(), StatusCode::kNotInitialized) << c.name;
    }
    FileOdometry::Config config;
    const std::string missing = dir_.file("missing.txt");
    config.pose_log_path = missing.c_str();
    EXPECT_TRUE(hasStatus(odometry_->init(config), StatusCode::kIoError, "pose log: cannot open file", ENOENT));
}

TEST_F(FileOdometryTest, PoseCapacityLimitNamesTheLine) {
    const double p[3] = {0.0, 0.0, 0.0};
    const double q[4] = {1.0, 0.0, 0.0, 0.0};
    std::string log = "vtm-poses 1\n";
    for (std::size_t i = 0; i < fl::kMaxPoses; ++i) {
        log += poseLine(kT0 + i, p, q, kVar);
    }
    ASSERT_TRUE(isOk(initWith(log)));
    EXPECT_EQ(odometry_->poseCount(), fl::kMaxPoses);
    log += poseLine(kT0 + fl::kMaxPoses, p, q, kVar);
    EXPECT_TRUE(hasStatus(initWith(log), StatusCode::kUnsupported, "pose log: more than kMaxPoses (4096) poses",
                          static_cast<std::int64_t>(fl::kMaxPoses + 2U)));
}

// The interpolated bits, folded into one number: compare it between targets (the
// determinism claim of docs/hal-file.md); printed, not asserted, as no value is golden.
TEST_F(FileOdometryTest, ReportsAHashOfInterpolatedBits) {
    // Inputs exact on every target: unit quaternions from integer quadruples
    // (a^2 + b^2 + c^2 + d^2 = n^2) and positions from + - * / only.
    const int quads[9][5] = {{1, 0, 0, 0, 1}, {3, 0, 0, 4, 5},  {2, 1, 2, 0, 3}, {5, 1, 1, 3, 6}, {6, 2, 4, 5, 9},
                             {6, 2, 3, 0, 7}, {-1, 1, 1, 1, 2}, {8, 4, 1, 0, 9}, {9, 2, 6, 0, 11}};
    std::string log = "vtm-poses 1\n";
    for (int k = 0; k <= 8; ++k) {
        const double p[3] = {0.1 * k, -0.37 * k * k, 1.0 / (k + 1)};
        const double n = quads[k][4];
        const double q[4] = {quads[k][0] / n, quads[k][1] / n, quads[k][2] / n, quads[k][3] / n};
        log += poseLine(kT0 + static_cast<std::uint64_t>(k) * 1000000007ULL, p, q, kVar);
    }
    ASSERT_TRUE(isOk(initWith(log)));
    std::uint64_t hash = 1469598103934665603ULL;
    for (std::uint64_t dt = 0; dt <= 8000000056ULL; dt += 12345677ULL) {
        PoseEstimate pose;
        ASSERT_TRUE(isOk(odometry_->poseAt(kT0 + dt, pose)));
        const double* fields[3] = {pose.position_m, pose.attitude_wxyz, pose.covariance};
        const int counts[3] = {3, 4, 36};
        for (int f = 0; f < 3; ++f) {
            for (int i = 0; i < counts[f]; ++i) {
                std::uint64_t bits = 0;
                std::memcpy(&bits, &fields[f][i], sizeof bits);
                hash = (hash ^ bits) * 1099511628211ULL;
            }
        }
    }
    std::printf("FileOdometry interpolation hash: %016llx\n", static_cast<unsigned long long>(hash));
}

// ==== the flight rule: no heap after init ====================================================

TEST_F(FileCameraTest, CaptureAndPoseAtTouchNoHeapAfterInit) {
    const int w = 16;
    const int h = 12;
    const Image a = pattern(w, h, 255, 21);
    Bytes rgb;
    for (const std::uint16_t v : a.px) {
        rgb.insert(rgb.end(), {static_cast<std::uint8_t>(v), static_cast<std::uint8_t>(255 - v), 7});
    }
    PngSpec pal{w, h, 8, 3};
    pal.plte = {0, 0, 0, 255, 255, 255, 10, 20, 30};
    writeBytes(dir_.file("a.pgm"), pgm(a, 255));
    writeBytes(dir_.file("a.png"), pngCompressed(w, h, 1, toBytes(a.px)));
    writeBytes(dir_.file("rgb.png"), pngCompressed(w, h, 3, rgb));
    writeBytes(dir_.file("pal.png"), pngStored(pal, pattern(w, h, 2, 22).px));
    writeBytes(dir_.file("bad.png"), Bytes{0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n', 0, 0});
    ASSERT_TRUE(isOk(initWith(header(w, h, 8) + frameLine(1, 10, 1, "a.pgm") + frameLine(2, 20, 1, "a.png") +
                              frameLine(3, 30, 1, "rgb.png") + frameLine(4, 40, 1, "pal.png") +
                              frameLine(5, 50, 1, "missing.png") + frameLine(6, 60, 1, "bad.png"))));

    static FileCamera camera16;
    const Image b = pattern(w, h, 4095, 23);
    writeBytes(dir_.file("b.pgm"), pgm(b, 4095));
    writeBytes(dir_.file("b.png"), pngStored({w, h, 16, 0}, b.px));
    const std::string manifest16 = dir_.file("frames16.txt");
    writeText(manifest16, header(w, h, 12) + frameLine(1, 10, 1, "b.pgm") + frameLine(2, 20, 1, "b.png"));
    FileCamera::Config config16;
    config16.manifest_path = manifest16.c_str();
    ASSERT_TRUE(isOk(camera16.init(config16)));

    static FileOdometry odometry;
    std::string log = "vtm-poses 1\n";
    for (int k = 0; k <= 5; ++k) {
        const double p[3] = {0.5 * k, 0.0, 0.0};
        const double q[4] = {std::cos(0.1 * k), 0.0, 0.0, std::sin(0.1 * k)};
        log += poseLine(kT0 + static_cast<std::uint64_t>(k) * 1000000000ULL, p, q, kVar);
    }
    const std::string log_path = dir_.file("poses.txt");
    writeText(log_path, log);
    FileOdometry::Config odo_config;
    odo_config.pose_log_path = log_path.c_str();
    ASSERT_TRUE(isOk(odometry.init(odo_config)));

    static std::uint8_t px8[16 * 12];
    static std::uint16_t px16[16 * 12];
    StatusCode codes[3][9] = {};
    std::uint64_t heap_calls = 0;
    {
        test::NoHeapScope guard;
        for (int round = 0; round < 3; ++round) {
            camera_->rewind();
            camera16.rewind();
            FrameInfo info;
            for (int i = 0; i < 7; ++i) {
                codes[round][i] = camera_->capture(ImageView<std::uint8_t>(px8, w, h), info).code();
            }
            codes[round][7] = camera16.capture16(ImageView<std::uint16_t>(px16, w, h), info).code();
            codes[round][8] = camera16.capture16(ImageView<std::uint16_t>(px16, w, h), info).code();
            PoseEstimate pose;
            for (std::uint64_t dt = 0; dt <= 5000000000ULL; dt += 99999999ULL) {
                if (!odometry.poseAt(kT0 + dt, pose).isOk()) {
                    codes[round][0] = StatusCode::kTimeout;  // marks a failure outside the guard
                }
            }
        }
        heap_calls = guard.heapCalls();
    }
    EXPECT_EQ(heap_calls, 0U);
    const StatusCode want[9] = {StatusCode::kOk,          StatusCode::kOk,      StatusCode::kOk,
                                StatusCode::kOk,          StatusCode::kIoError, StatusCode::kCorruptData,
                                StatusCode::kNoData,      StatusCode::kOk,      StatusCode::kOk};
    for (int round = 0; round < 3; ++round) {
        for (int i = 0; i < 9; ++i) {
            EXPECT_EQ(codes[round][i], want[i]) << "round " << round << " call " << i;
        }
    }
    EXPECT_EQ(std::vector<std::uint16_t>(px16, px16 + w * h), b.px);
}

}  // namespace
}  // namespace vtm::hal
