// The stations file (panorama_stations.hpp, docs/panorama-cli.md).
#include "vtm/ground/panorama_stations.hpp"
#include "vtm/ground/number_text.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "vtm/ground/sim_output.hpp"

namespace vtm::ground {
namespace {

using Fields = std::vector<std::string>;

Fields split(const std::string& line) {
    Fields f;
    std::string cur;
    for (const char c : line) {
        if (c == ' ' || c == '\t' || c == '\r') {
            if (!cur.empty()) f.push_back(cur);
            cur.clear();
        } else {
            cur += c;
        }
    }
    if (!cur.empty()) f.push_back(cur);
    return f;
}

// A finite number in the "C" form strtod reads, the whole field.
bool toNumber(const std::string& s, double& v) {
    if (s.empty() || s.size() > 63U) return false;
    errno = 0;
    char* end = nullptr;
    v = std::strtod(s.c_str(), &end);
    return end == s.c_str() + s.size() && std::isfinite(v);
}

bool toInt(const std::string& s, int lo, int hi, int& v) {
    double d = 0.0;
    if (!toNumber(s, d) || d != std::floor(d) || d < lo || d > hi) return false;
    v = static_cast<int>(d);
    return true;
}

// `count` finite numbers after the key.
bool numbers(const Fields& f, std::size_t count, double* out) {
    if (f.size() != count + 1U) return false;
    for (std::size_t i = 0; i < count; ++i) {
        if (!toNumber(f[i + 1U], out[i])) return false;
    }
    return true;
}

// x y z qw qx qy qz -> RigidPose through the one conversion of docs/cli-poses.md.
std::string poseOf(const Fields& f, RigidPose& pose) {
    double v[7] = {};
    if (!numbers(f, 7U, v)) return f[0] + ": expected 7 finite numbers x y z qw qx qy qz";
    const double n2 = v[3] * v[3] + v[4] * v[4] + v[5] * v[5] + v[6] * v[6];
    if (std::fabs(n2 - 1.0) > 2e-6) return f[0] + ": the attitude is not a unit quaternion";
    SimCameraPose record;
    for (int i = 0; i < 3; ++i) record.position_m[i] = v[i];
    for (int i = 0; i < 4; ++i) record.attitude_wxyz[i] = v[3 + i];
    pose = siteFromCam(record);
    return "";
}

std::string poseText(const char* key, const RigidPose& pose) {
    SimCameraPose record;
    setSiteFromCam(record, pose);
    std::string t = key;
    for (const double v : record.position_m) t += " " + exactNumber(v);
    for (const double v : record.attitude_wxyz) t += " " + exactNumber(v);
    return t + "\n";
}

struct Seen {  // the keys of the current station
    bool images = false, approx = false, truth = false, prior = false;
};

struct Parser {
    PanoramaStationsFile file;
    int announced = -1;  // the "stations" line's count
    bool camera_l = false, camera_r = false, rig = false, depth = false;
    Seen seen;
    std::string error;

    bool fail(std::size_t line, const std::string& reason) {
        error = "line " + std::to_string(line) + ": " + reason;
        return false;
    }

    bool stationHeader(const Fields& f, std::size_t line);
    bool stationsLine(const Fields& f, std::size_t line);
    bool global(const Fields& f, std::size_t line);
    bool stationKey(const Fields& f, std::size_t line);
    bool stationComplete(std::size_t line);
    bool line(const Fields& f, std::size_t line);
};

bool Parser::stationsLine(const Fields& f, std::size_t line) {
    if (announced >= 0) return fail(line, "stations given twice");
    if (f.size() < 2U || f.size() % 2U != 0U) return fail(line, "expected 'stations N [tiers T] [columns C]'");
    int n = 0;
    if (!toInt(f[1], 2, 1 << 20, n)) return fail(line, "stations: '" + f[1] + "' is not a count >= 2");
    if (n > kMaxPanoramaFileStations) {
        return fail(line, "stations: " + f[1] + " stations; at most " + std::to_string(kMaxPanoramaFileStations) +
                              " (the bundle adjustment's capacity)");
    }
    for (std::size_t i = 2; i < f.size(); i += 2U) {
        int* target = f[i] == "tiers" ? &file.tiers : f[i] == "columns" ? &file.columns : nullptr;
        if (target == nullptr || *target != 0) return fail(line, "stations: unknown or repeated field '" + f[i] + "'");
        if (!toInt(f[i + 1U], 1, n, *target)) return fail(line, f[i] + ": '" + f[i + 1U] + "' is not 1.." + f[1]);
    }
    if (file.tiers > 0 && file.columns > 0 && file.tiers * file.columns != n) {
        return fail(line, "stations: tiers x columns is not the station count");
    }
    announced = n;
    file.stations.reserve(static_cast<std::size_t>(n));
    return true;
}

bool Parser::global(const Fields& f, std::size_t line) {
    const std::string& key = f[0];
    if (key == "stations") return stationsLine(f, line);
    if (key == "left_camera" || key == "right_camera") {
        bool& seen_camera = key == "left_camera" ? camera_l : camera_r;
        if (seen_camera) return fail(line, key + " given twice");
        if (f.size() != 2U) return fail(line, key + ": expected one file name (no blanks)");
        (key == "left_camera" ? file.left_camera : file.right_camera) = f[1];
        seen_camera = true;
        return true;
    }
    if (key == "right_from_left") {
        if (rig) return fail(line, "right_from_left given twice");
        const std::string e = poseOf(f, file.right_from_left);
        rig = true;
        return e.empty() || fail(line, e);
    }
    if (key == "bit_depth") {
        if (depth) return fail(line, "bit_depth given twice");
        if (f.size() != 2U || !toInt(f[1], 8, 16, file.bit_depth)) return fail(line, "bit_depth: expected 8..16");
        depth = true;
        return true;
    }
    return fail(line, "unknown key '" + key + "'");
}

bool Parser::stationHeader(const Fields& f, std::size_t line) {
    if (announced < 0) return fail(line, "station before the 'stations' line");
    if (!camera_l || !camera_r || !rig) {
        return fail(line, "left_camera, right_camera and right_from_left must come before the first station");
    }
    if (!file.stations.empty() && !stationComplete(line)) return false;
    const int k = static_cast<int>(file.stations.size());
    int index = -1;
    if (f.size() < 2U || f.size() % 2U != 0U || !toInt(f[1], 0, 1 << 20, index)) {
        return fail(line, "expected 'station K [tier T] [column C] [pan_deg P] [tilt_deg D]'");
    }
    if (index != k) return fail(line, "station " + f[1] + " where station " + std::to_string(k) + " is due");
    if (k >= announced) return fail(line, "more stations than the 'stations' line announced");
    PanoramaStationRecord s;
    for (std::size_t i = 2; i < f.size(); i += 2U) {
        const std::string& key = f[i];
        double v = 0.0;
        if (!toNumber(f[i + 1U], v)) return fail(line, key + ": '" + f[i + 1U] + "' is not a finite number");
        if (key == "tier" || key == "column") {
            int& target = key == "tier" ? s.tier : s.column;
            if (target >= 0 || !toInt(f[i + 1U], 0, 1 << 20, target)) return fail(line, key + ": repeated or not >= 0");
        } else if (key == "pan_deg") {
            s.pan_deg = v;
        } else if (key == "tilt_deg") {
            s.tilt_deg = v;
        } else {
            return fail(line, "station: unknown field '" + key + "'");
        }
    }
    file.stations.push_back(s);
    seen = Seen{};
    return true;
}

bool Parser::stationKey(const Fields& f, std::size_t line) {
    PanoramaStationRecord& s = file.stations.back();
    const std::string& key = f[0];
    const std::string where = "station " + std::to_string(file.stations.size() - 1U) + ": ";
    if (key == "images") {
        if (seen.images) return fail(line, where + "images given twice");
        if (f.size() != 3U) return fail(line, where + "expected 'images LEFT_FILE RIGHT_FILE' (no blanks in names)");
        s.left_image = f[1];
        s.right_image = f[2];
        s.images_line = line;
        seen.images = true;
        return true;
    }
    if (key == "approx" || key == "true") {
        bool& once = key == "approx" ? seen.approx : seen.truth;
        if (once) return fail(line, where + key + " given twice");
        once = true;
        s.has_truth = s.has_truth || key == "true";
        const std::string e = poseOf(f, key == "approx" ? s.approx : s.truth);
        return e.empty() || fail(line, where + e);
    }
    if (key == "prior" || key == "sigma") {
        if (seen.prior) return fail(line, where + "the prior given twice (prior or sigma, once)");
        seen.prior = true;
        double v[36] = {};
        if (key == "prior") {
            if (!numbers(f, 36U, v)) return fail(line, where + "prior: expected 36 finite numbers (6x6, row-major)");
            for (int i = 0; i < 36; ++i) s.prior(i / 6, i % 6) = v[i];
        } else {
            if (!numbers(f, 6U, v)) return fail(line, where + "sigma: expected 6 finite numbers (3 rad, 3 m)");
            for (int i = 0; i < 6; ++i) {
                if (v[i] < 0.0) return fail(line, where + "sigma: a negative sigma");
                s.prior(i, i) = v[i] * v[i];
            }
        }
        const std::string e = checkPointingPrior(s.prior);
        return e.empty() || fail(line, where + key + ": " + e);
    }
    return fail(line, "unknown key '" + key + "'");
}

bool Parser::stationComplete(std::size_t line) {
    const std::string where = "station " + std::to_string(file.stations.size() - 1U) + " has no ";
    if (!seen.images) return fail(line, where + "'images' line");
    if (!seen.approx) return fail(line, where + "'approx' pose");
    if (!seen.prior) return fail(line, where + "'prior' or 'sigma'");
    return true;
}

bool Parser::line(const Fields& f, std::size_t line) {
    if (f[0] == "station") return stationHeader(f, line);
    return file.stations.empty() ? global(f, line) : stationKey(f, line);
}

}  // namespace

std::string checkPointingPrior(const Mat6& prior) {
    for (int i = 0; i < 6; ++i) {
        for (int j = 0; j < 6; ++j) {
            const double a = prior(i, j), b = prior(j, i);
            if (!std::isfinite(a)) return "not finite";
            if (std::fabs(a - b) > 1e-12 * std::max(std::fabs(a), std::fabs(b))) return "not symmetric";
        }
    }
    Mat6 free = prior;
    for (int i = 0; i < 6; ++i) {
        if (prior(i, i) < 0.0) return "a negative variance on the diagonal";
        if (prior(i, i) > 0.0) continue;
        for (int j = 0; j < 6; ++j) {
            if (prior(i, j) != 0.0) return "a fixed parameter (zero variance) with a non-zero covariance";
        }
        free(i, i) = 1.0;  // a fixed parameter: out of the test below
    }
    const Eigen::LLT<Mat6> llt(free);
    if (llt.info() != Eigen::Success) return "not positive definite on its free parameters";
    return "";
}

Result<PanoramaStationsFile> parsePanoramaStations(const std::string& text) {
    using R = Result<PanoramaStationsFile>;
    std::istringstream in(text);
    std::string raw;
    std::size_t n = 0;
    Parser p;
    while (std::getline(in, raw)) {
        ++n;
        const Fields f = split(raw);
        if (n == 1U) {
            if (f.size() != 2U || f[0] != "vtm-panorama-stations" || f[1] != "1") {
                return R::failure("line 1: first line must be 'vtm-panorama-stations 1'");
            }
            continue;
        }
        if (f.empty() || f[0][0] == '#') continue;
        if (!p.line(f, n)) return R::failure(p.error);
    }
    if (n == 0U) return R::failure("line 1: empty file; first line must be 'vtm-panorama-stations 1'");
    if (p.announced < 0) return R::failure("line 0: no 'stations' line");
    if (static_cast<int>(p.file.stations.size()) != p.announced) {
        return R::failure("line 0: " + std::to_string(p.file.stations.size()) + " stations of the " +
                          std::to_string(p.announced) + " announced");
    }
    if (!p.stationComplete(n)) return R::failure(p.error);
    return R::success(std::move(p.file));
}

Result<PanoramaStationsFile> readPanoramaStationsFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return Result<PanoramaStationsFile>::failure(path + ": cannot open");
    std::ostringstream text;
    text << in.rdbuf();
    Result<PanoramaStationsFile> r = parsePanoramaStations(text.str());
    if (!r.ok) r.error = path + ": " + r.error;
    return r;
}

std::string formatPanoramaStations(const PanoramaStationsFile& file, const std::vector<std::string>& comments) {
    std::string t = "vtm-panorama-stations 1\n";
    for (const std::string& c : comments) t += "# " + c + "\n";
    t += "left_camera " + file.left_camera + "\nright_camera " + file.right_camera + "\n";
    t += poseText("right_from_left", file.right_from_left);
    t += "bit_depth " + std::to_string(file.bit_depth) + "\n";
    t += "stations " + std::to_string(file.stations.size());
    if (file.tiers > 0) t += " tiers " + std::to_string(file.tiers);
    if (file.columns > 0) t += " columns " + std::to_string(file.columns);
    t += "\n";
    for (std::size_t k = 0; k < file.stations.size(); ++k) {
        const PanoramaStationRecord& s = file.stations[k];
        t += "station " + std::to_string(k);
        if (s.tier >= 0) t += " tier " + std::to_string(s.tier);
        if (s.column >= 0) t += " column " + std::to_string(s.column);
        t += " pan_deg " + exactNumber(s.pan_deg) + " tilt_deg " + exactNumber(s.tilt_deg) + "\n";
        t += "images " + s.left_image + " " + s.right_image + "\n";
        if (s.has_truth) t += poseText("true", s.truth);
        t += poseText("approx", s.approx);
        t += "prior";
        for (int i = 0; i < 36; ++i) t += " " + exactNumber(s.prior(i / 6, i % 6));
        t += "\n";
    }
    return t;
}

}  // namespace vtm::ground
