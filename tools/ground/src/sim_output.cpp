// Files of `vtm-sim render` (sim_output.hpp).
#include "vtm/ground/sim_output.hpp"
#include "vtm/ground/number_text.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <utility>

#include "file_bytes.hpp"
#include "vtm/core/crc32.hpp"
#include "vtm/core/eigen.hpp"

namespace vtm::ground {
namespace {

using detail::Bytes;

void putU32(Bytes& out, std::uint32_t v) {
    out.push_back(static_cast<unsigned char>(v >> 24U));
    out.push_back(static_cast<unsigned char>(v >> 16U));
    out.push_back(static_cast<unsigned char>(v >> 8U));
    out.push_back(static_cast<unsigned char>(v));
}

void putChunk(Bytes& png, const char* type, const Bytes& data) {
    putU32(png, static_cast<std::uint32_t>(data.size()));
    Bytes body(type, type + 4);
    body.insert(body.end(), data.begin(), data.end());
    png.insert(png.end(), body.begin(), body.end());
    putU32(png, vtm::crc32(body.data(), body.size()));
}

// zlib stream (RFC 1950) of stored deflate blocks (RFC 1951 BTYPE 00), at most 65535 bytes each.
Bytes storedZlib(const Bytes& raw) {
    Bytes z = {0x78, 0x01};
    std::size_t pos = 0;
    do {
        const std::size_t n = std::min<std::size_t>(65535U, raw.size() - pos);
        const bool last = pos + n == raw.size();
        z.push_back(last ? 1U : 0U);
        z.push_back(static_cast<unsigned char>(n & 0xFFU));
        z.push_back(static_cast<unsigned char>(n >> 8U));
        z.push_back(static_cast<unsigned char>(~n & 0xFFU));
        z.push_back(static_cast<unsigned char>((~n >> 8U) & 0xFFU));
        z.insert(z.end(), raw.begin() + static_cast<std::ptrdiff_t>(pos),
                 raw.begin() + static_cast<std::ptrdiff_t>(pos + n));
        pos += n;
    } while (pos < raw.size());
    std::uint32_t a = 1U;
    std::uint32_t b = 0U;
    for (const unsigned char c : raw) {
        a = (a + c) % 65521U;
        b = (b + a) % 65521U;
    }
    putU32(z, (b << 16U) | a);
    return z;
}

bool allOffDiagonalZero(const SimPose& p) {
    for (int i = 0; i < 36; ++i) {
        if (i % 7 != 0 && p.covariance[i] != 0.0) {
            return false;
        }
    }
    return true;
}

// Data lines of a text file (comments and blank lines skipped) with their line numbers.
Result<std::vector<std::pair<int, std::vector<std::string>>>> dataLines(const std::string& path,
                                                                        const std::string& header) {
    using Lines = std::vector<std::pair<int, std::vector<std::string>>>;
    std::ifstream in(path);
    if (!in) {
        return Result<Lines>::failure(path + ": cannot open");
    }
    Lines lines;
    std::string line;
    int number_of_line = 0;
    bool seen_header = false;
    while (std::getline(in, line)) {
        ++number_of_line;
        std::istringstream fields(line);
        std::vector<std::string> tokens;
        std::string t;
        while (fields >> t) {
            tokens.push_back(t);
        }
        if (tokens.empty() || tokens[0][0] == '#') {
            continue;
        }
        if (!seen_header) {
            if (tokens.size() != 2 || tokens[0] + " " + tokens[1] != header) {
                return Result<Lines>::failure(path + ": line " + std::to_string(number_of_line) +
                                              ": first line must be '" + header + "'");
            }
            seen_header = true;
            continue;
        }
        lines.emplace_back(number_of_line, tokens);
    }
    if (!seen_header) {
        return Result<Lines>::failure(path + ": empty file (no '" + header + "' line)");
    }
    return Result<Lines>::success(lines);
}

bool toDouble(const std::string& s, double& v) {
    char* end = nullptr;
    v = std::strtod(s.c_str(), &end);
    return end == s.c_str() + s.size() && std::isfinite(v);
}

bool toU64(const std::string& s, std::uint64_t& v) {
    if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos || s.size() > 20) {
        return false;
    }
    char* end = nullptr;
    v = std::strtoull(s.c_str(), &end, 10);
    return end == s.c_str() + s.size();
}

}  // namespace

Outcome writePng16(const std::string& path, const Grey16Image& image) {
    if (image.empty() || image.channels != 1) {
        return Outcome::failure(path + ": a 16-bit PNG needs a non-empty one-channel image");
    }
    Bytes raw;
    raw.reserve(static_cast<std::size_t>(image.height) * (1U + 2U * static_cast<std::size_t>(image.width)));
    for (std::int32_t y = 0; y < image.height; ++y) {
        raw.push_back(0U);  // filter type None
        for (std::int32_t x = 0; x < image.width; ++x) {
            const std::uint16_t v = image.at(x, y);
            raw.push_back(static_cast<unsigned char>(v >> 8U));
            raw.push_back(static_cast<unsigned char>(v & 0xFFU));
        }
    }
    Bytes png = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
    Bytes ihdr;
    putU32(ihdr, static_cast<std::uint32_t>(image.width));
    putU32(ihdr, static_cast<std::uint32_t>(image.height));
    ihdr.insert(ihdr.end(), {16U, 0U, 0U, 0U, 0U});  // 16-bit grey, deflate, no filter, no interlace
    putChunk(png, "IHDR", ihdr);
    putChunk(png, "IDAT", storedZlib(raw));
    putChunk(png, "IEND", Bytes());
    return detail::writeFileBytes(path, png);
}

Outcome writePgm8(const std::string& path, const GreyImage& image) {
    if (image.empty() || image.channels != 1) {
        return Outcome::failure(path + ": a PGM needs a non-empty one-channel image");
    }
    const std::string header = "P5\n" + std::to_string(image.width) + " " + std::to_string(image.height) + "\n255\n";
    Bytes bytes(header.begin(), header.end());
    bytes.insert(bytes.end(), image.pixels.begin(), image.pixels.end());
    return detail::writeFileBytes(path, bytes);
}

Outcome writePgm16(const std::string& path, const Grey16Image& image, int maxval) {
    if (image.empty() || image.channels != 1 || maxval < 256 || maxval > 65535) {
        return Outcome::failure(path + ": a 16-bit PGM needs a one-channel image and maxval 256..65535");
    }
    const std::string header = "P5\n" + std::to_string(image.width) + " " + std::to_string(image.height) + "\n" +
                               std::to_string(maxval) + "\n";
    Bytes bytes(header.begin(), header.end());
    for (const std::uint16_t v : image.pixels) {
        bytes.push_back(static_cast<unsigned char>(v >> 8U));
        bytes.push_back(static_cast<unsigned char>(v & 0xFFU));
    }
    return detail::writeFileBytes(path, bytes);
}

std::string formatPoseLog(const std::vector<SimPose>& poses, const std::string& comment) {
    std::string out = "vtm-poses 1\n# " + comment +
                      "\n# timestamp_ns x y z [m, site: north east down] qw qx qy qz (T_site_from_vehicle) covariance\n";
    for (const SimPose& p : poses) {
        out += std::to_string(p.timestamp_ns);
        for (const double v : p.position_m) out += " " + exactNumber(v);
        for (const double v : p.attitude_wxyz) out += " " + exactNumber(v);
        const bool diagonal = allOffDiagonalZero(p);
        for (int i = 0; i < 36; ++i) {
            if (!diagonal || i % 7 == 0) out += " " + exactNumber(p.covariance[i]);
        }
        out += "\n";
    }
    return out;
}

Result<std::vector<SimPose>> readPoseLog(const std::string& path) {
    auto lines = dataLines(path, "vtm-poses 1");
    if (!lines.ok) {
        return Result<std::vector<SimPose>>::failure(lines.error);
    }
    std::vector<SimPose> poses;
    for (const auto& [line, t] : lines.value) {
        const std::string where = path + ": line " + std::to_string(line) + ": ";
        SimPose p;
        double v[43] = {};
        bool ok = (t.size() == 14 || t.size() == 44) && toU64(t[0], p.timestamp_ns);
        for (std::size_t i = 1; ok && i < t.size(); ++i) ok = toDouble(t[i], v[i - 1]);
        if (!ok) {
            return Result<std::vector<SimPose>>::failure(where + "a pose needs timestamp_ns and 13 or 43 numbers");
        }
        for (int i = 0; i < 3; ++i) p.position_m[i] = v[i];
        for (int i = 0; i < 4; ++i) p.attitude_wxyz[i] = v[3 + i];
        for (int i = 0; i < 36; ++i) {
            if (t.size() == 44) p.covariance[i] = v[7 + i];
            else if (i % 7 == 0) p.covariance[i] = v[7 + i / 7];
        }
        poses.push_back(p);
    }
    return Result<std::vector<SimPose>>::success(poses);
}

RigidPose siteFromCam(const SimCameraPose& p) {
    const Quat q(p.attitude_wxyz[0], p.attitude_wxyz[1], p.attitude_wxyz[2], p.attitude_wxyz[3]);
    RigidPose site_from_cam;
    site_from_cam.R = q.normalized().toRotationMatrix();
    site_from_cam.t_m = Vec3(p.position_m[0], p.position_m[1], p.position_m[2]);
    return site_from_cam;
}

void setSiteFromCam(SimCameraPose& p, const RigidPose& site_from_cam) {
    const Quat q(site_from_cam.R);
    for (int i = 0; i < 3; ++i) p.position_m[i] = site_from_cam.t_m[i];
    p.attitude_wxyz[0] = q.w();
    p.attitude_wxyz[1] = q.x();
    p.attitude_wxyz[2] = q.y();
    p.attitude_wxyz[3] = q.z();
}

std::string formatCameraPoses(const std::vector<SimCameraPose>& poses) {
    std::string out = "vtm-camera-poses 1\n# frame camera timestamp_ns x y z [m, site: north east down] "
                      "qw qx qy qz (T_site_from_camera_reference_frame)\n";
    for (const SimCameraPose& p : poses) {
        out += std::to_string(p.frame_index) + " " + p.camera + " " + std::to_string(p.timestamp_ns);
        for (const double v : p.position_m) out += " " + exactNumber(v);
        for (const double v : p.attitude_wxyz) out += " " + exactNumber(v);
        out += "\n";
    }
    return out;
}

Result<std::vector<SimCameraPose>> readCameraPoses(const std::string& path) {
    auto lines = dataLines(path, "vtm-camera-poses 1");
    if (!lines.ok) {
        return Result<std::vector<SimCameraPose>>::failure(lines.error);
    }
    std::vector<SimCameraPose> poses;
    for (const auto& [line, t] : lines.value) {
        SimCameraPose p;
        std::uint64_t frame = 0;
        bool ok = t.size() == 10 && toU64(t[0], frame) && frame <= 0xFFFFFFFFULL && toU64(t[2], p.timestamp_ns);
        for (int i = 0; ok && i < 3; ++i) ok = toDouble(t[3 + static_cast<std::size_t>(i)], p.position_m[i]);
        for (int i = 0; ok && i < 4; ++i) ok = toDouble(t[6 + static_cast<std::size_t>(i)], p.attitude_wxyz[i]);
        if (!ok) {
            return Result<std::vector<SimCameraPose>>::failure(
                path + ": line " + std::to_string(line) + ": needs frame camera timestamp_ns x y z qw qx qy qz");
        }
        p.frame_index = static_cast<std::uint32_t>(frame);
        p.camera = t[1];
        poses.push_back(p);
    }
    return Result<std::vector<SimCameraPose>>::success(poses);
}

Result<SimCameraPose> readCameraPoseSpec(const std::string& spec) {
    std::string path = spec;
    bool indexed = false;
    std::uint64_t index = 0;
    const std::size_t colon = spec.rfind(':');
    if (colon != std::string::npos && colon + 1 < spec.size() &&
        spec.find_first_not_of("0123456789", colon + 1) == std::string::npos) {
        indexed = toU64(spec.substr(colon + 1), index);
        if (indexed) path = spec.substr(0, colon);
    }
    auto poses = readCameraPoses(path);
    if (!poses.ok) return Result<SimCameraPose>::failure(poses.error);
    const SimCameraPose* chosen = nullptr;
    if (!indexed) {
        if (poses.value.size() != 1U) {
            return Result<SimCameraPose>::failure(path + ": holds " + std::to_string(poses.value.size()) +
                                                  " poses; name one as " + path + ":INDEX");
        }
        chosen = &poses.value.front();
    } else {
        for (const SimCameraPose& p : poses.value) {
            if (p.frame_index == index) chosen = &p;
        }
        if (chosen == nullptr) {
            return Result<SimCameraPose>::failure(path + ": no pose with frame index " + std::to_string(index));
        }
    }
    const double* q = chosen->attitude_wxyz;
    const double n2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    if (!std::isfinite(n2) || std::fabs(n2 - 1.0) > 2e-6) {
        return Result<SimCameraPose>::failure(spec + ": attitude is not a unit quaternion");
    }
    return Result<SimCameraPose>::success(*chosen);
}

}  // namespace vtm::ground
