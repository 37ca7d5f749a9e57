// The shared real data (README "Data"; ../shared/data beside the repository, one folder per
// set: middlebury/, msl_navcam/, strecha/, srif/, mer_opportunity/): one rule for every test
// that reads it.
//  - Root: $VTM_DATA when set and not empty, else the build's VTM_TEST_DATA_DIR (CMake cache
//    variable, default ../shared/data; tests/CMakeLists.txt vtm_use_test_data()).
//  - A set that is not there: the test skips, naming the folder it looked in and VTM_DATA;
//    with VTM_REQUIRE_DATA=1 in the environment (CI: tools/test.sh) it fails instead, so a
//    run that is meant to have the data cannot pass without it.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <string>

namespace vtm::test {

inline std::string testDataRoot() {
    const char* env = std::getenv("VTM_DATA");
    if (env != nullptr && env[0] != '\0') return env;
#ifdef VTM_TEST_DATA_DIR
    return VTM_TEST_DATA_DIR;
#else
    return "";
#endif
}

// The folder of one set, with a trailing '/': testDataRoot() + "/" + set + "/".
inline std::string testDataSet(const std::string& set) { return testDataRoot() + "/" + set + "/"; }

inline bool testDataRequired() {
    const char* env = std::getenv("VTM_REQUIRE_DATA");
    return env != nullptr && std::string(env) == "1";
}

// Why `path` (a set's folder or one of its files) is missing, "" when it is there.
inline std::string missingTestData(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::exists(path, ec)) return "";
    const char* env = std::getenv("VTM_DATA");
    const bool from_env = env != nullptr && env[0] != '\0';
    return "real data not found: '" + path + "' (data root " + testDataRoot() +
           (from_env ? " from $VTM_DATA" : ", the build's VTM_TEST_DATA_DIR; set VTM_DATA to use another") +
           "; README \"Data\")";
}

}  // namespace vtm::test

// In a test body: skip (fail under VTM_REQUIRE_DATA=1) when `path` is not there.
#define VTM_REQUIRE_TEST_DATA(path)                                             \
    do {                                                                        \
        const std::string vtm_missing_ = ::vtm::test::missingTestData(path);    \
        if (!vtm_missing_.empty()) {                                            \
            if (::vtm::test::testDataRequired()) FAIL() << vtm_missing_;        \
            GTEST_SKIP() << vtm_missing_;                                       \
        }                                                                       \
    } while (false)
