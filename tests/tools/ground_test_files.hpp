// Files for the ground-tool tests, written by hand (not by the code under test): a
// fresh temporary directory per test, raw bytes, PGM/PPM images and the location of the
// shared Middlebury data.
#pragma once

#include "test_data.hpp"

#include <gtest/gtest.h>

#include <stdlib.h>    // mkdtemp
#include <sys/wait.h>  // WIFEXITED

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace vtm::ground::test {

// The shared real data (tests/support/test_data.hpp), under the names this folder uses.
using vtm::test::testDataRoot;
using vtm::test::testDataSet;

// mkdtemp: parallel ctest runs share /tmp. Removed with its contents afterwards.
class TempDir {
public:
    TempDir() {
        std::string pattern = (std::filesystem::path(::testing::TempDir()) / "vtm_ground_XXXXXX").string();
        std::vector<char> buffer(pattern.begin(), pattern.end());
        buffer.push_back('\0');
        const char* made = mkdtemp(buffer.data());
        EXPECT_NE(made, nullptr);
        path_ = (made != nullptr) ? made : ::testing::TempDir();
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    [[nodiscard]] std::string file(const std::string& name) const { return (path_ / name).string(); }

private:
    std::filesystem::path path_;
};

using Bytes = std::vector<unsigned char>;

inline void writeBytes(const std::string& path, const Bytes& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    ASSERT_TRUE(out.good()) << path;
}

inline Bytes textBytes(const std::string& s) { return Bytes(s.begin(), s.end()); }

// P5 (grey) with maxval 255 or 65535 (16-bit samples big endian, as Netpbm specifies).
inline Bytes pgmBytes(int width, int height, const std::vector<std::uint16_t>& levels, int maxval = 255) {
    Bytes b = textBytes("P5\n" + std::to_string(width) + " " + std::to_string(height) + "\n" +
                        std::to_string(maxval) + "\n");
    for (std::uint16_t v : levels) {
        if (maxval > 255) {
            b.push_back(static_cast<unsigned char>(v >> 8));
        }
        b.push_back(static_cast<unsigned char>(v & 0xFF));
    }
    return b;
}

// P6 (RGB, 8-bit), rgb = r, g, b per pixel.
inline Bytes ppmBytes(int width, int height, const std::vector<std::uint8_t>& rgb) {
    Bytes b = textBytes("P6\n" + std::to_string(width) + " " + std::to_string(height) + "\n255\n");
    b.insert(b.end(), rgb.begin(), rgb.end());
    return b;
}

// The whole of a file's bytes ("" when it cannot be read).
inline std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// A command as a user runs it: exit code, stdout, stderr.
struct CommandRun {
    int exit_code = -1;
    std::string out;
    std::string err;
};

// Runs `'EXE' ARGS` through the shell with stdout and stderr captured into files of `dir`;
// `in_dir`: from inside `dir` (relative paths in ARGS are its files).
inline CommandRun runCommand(const TempDir& dir, const std::string& exe, const std::string& args, bool in_dir = false) {
    const std::string out = dir.file("stdout.txt");
    const std::string err = dir.file("stderr.txt");
    const std::string cd = in_dir ? "cd '" + dir.file("") + "' && " : std::string();
    const std::string cmd = cd + "'" + exe + "' " + args + " >'" + out + "' 2>'" + err + "'";
    const int status = std::system(cmd.c_str());
    CommandRun r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = slurp(out);
    r.err = slurp(err);
    return r;
}

}  // namespace vtm::ground::test
