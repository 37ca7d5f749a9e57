#!/usr/bin/env python3
"""policy_test: the include rules of tools/checks/policy.py on small trees written for each
case, and docs/flight-rules.md R12 quoting the policy's own layering texts.

    python3 tools/checks/policy_test.py        # ctest: policy.selftest (label checks)

Standard library only (unittest). Each case writes the files it needs into a temporary
repository root, runs `check_sources` on it and compares the findings' rules and lines.
"""

from __future__ import annotations

import sys
import tempfile
import unittest
from pathlib import Path

sys.dont_write_bytecode = True  # keep the source tree free of __pycache__
HERE = Path(__file__).resolve().parent
REPO = HERE.parent.parent
sys.path.insert(0, str(HERE))
import policy  # noqa: E402


class Tree:
    """A throw-away repository root with fsw/core and fsw/stereo present."""

    def __init__(self) -> None:
        self._dir = tempfile.TemporaryDirectory()
        self.root = Path(self._dir.name)
        for module in ("core", "app", "stereo", "rectify"):
            (self.root / "fsw" / module).mkdir(parents=True)

    def write(self, rel: str, text: str) -> None:
        path = self.root / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)

    def findings(self) -> list[str]:
        return policy.check_sources(self.root)

    def close(self) -> None:
        self._dir.cleanup()


def include(header: str) -> str:
    return f'#include "{header}"\n'


class PolicyTest(unittest.TestCase):
    def setUp(self) -> None:
        self.tree = Tree()

    def tearDown(self) -> None:
        self.tree.close()

    def rules(self) -> list[str]:
        """'file:line: rule' of every finding."""
        return [":".join(f.split(":")[:3]) for f in self.tree.findings()]

    # --- fsw/app: the executives ---------------------------------------------------------
    def test_app_may_include_hal_interfaces_core_app_and_modules(self) -> None:
        self.tree.write("fsw/app/src/mapper.cpp",
                        include("hal/camera.hpp") + include("hal/odometry.hpp") + include("vtm/core/pose.hpp") +
                        include("vtm/app/camera_mount.hpp") + include("vtm/stereo/ml_stereo.hpp") +
                        include("vtm/rectify/rectifier.hpp") + "#include <array>\n")
        self.assertEqual(self.rules(), [])

    def test_app_may_not_include_hal_drivers_sim_tools_ground_or_opencv(self) -> None:
        self.tree.write("fsw/app/src/mapper.cpp",
                        include("hal/file/file_camera.hpp") + include("sim/render.hpp") +
                        include("tools/vtm/exit_codes.hpp") + include("vtm/ground/image_io.hpp") +
                        "#include <opencv2/core.hpp>\n")
        self.assertEqual(self.rules(), [f"fsw/app/src/mapper.cpp:{n}: include-layer" for n in range(1, 6)])

    def test_gdal_is_refused_in_flight_code_and_in_the_simulator(self) -> None:
        self.tree.write("fsw/stereo/src/ml_stereo.cpp", "#include <gdal_priv.h>\n#include <ogr_spatialref.h>\n")
        self.tree.write("hal/file/src/reader.cpp", "#include <cpl_error.h>\n")
        self.tree.write("sim/src/world.cpp", "#include <gdal.h>\n")
        found = sorted(self.tree.findings())
        self.assertEqual([":".join(f.split(":")[:3]) for f in found],
                         ["fsw/stereo/src/ml_stereo.cpp:1: include-layer", "fsw/stereo/src/ml_stereo.cpp:2: include-layer",
                          "hal/file/src/reader.cpp:1: include-layer", "sim/src/world.cpp:1: include-layer"])
        self.assertTrue(all("tools/ground only" in f for f in found), found)

    # --- fsw/<module> ----------------------------------------------------------------------
    def test_module_may_include_core_and_itself(self) -> None:
        self.tree.write("fsw/stereo/src/ml_stereo.cpp",
                        include("vtm/core/eigen.hpp") + include("vtm/stereo/ml_stereo.hpp") +
                        include("local_helper.hpp") + "#include <cstdint>\n")
        self.tree.write("fsw/stereo/src/local_helper.hpp", "#pragma once\n")
        self.assertEqual(self.rules(), [])

    def test_module_may_not_include_another_module_app_or_hal(self) -> None:
        self.tree.write("fsw/stereo/src/ml_stereo.cpp",
                        include("vtm/rectify/rectifier.hpp") + include("vtm/app/camera_mount.hpp") +
                        include("hal/camera.hpp") + include("vtm/ground/pfm.hpp"))
        found = self.tree.findings()
        self.assertEqual([":".join(f.split(":")[:3]) for f in found],
                         [f"fsw/stereo/src/ml_stereo.cpp:{n}: include-layer" for n in range(1, 5)])
        self.assertIn("those of the modules its CMake target links", found[0])

    def test_module_may_include_the_modules_it_links_and_no_others(self) -> None:
        self.tree.write("fsw/terrain/CMakeLists.txt",
                        "target_link_libraries(vtm_terrain PUBLIC vtm_core vtm_rectify)\n")
        self.tree.write("fsw/rectify/CMakeLists.txt", "target_link_libraries(vtm_rectify PUBLIC vtm_core)\n")
        self.tree.write("fsw/terrain/src/geometry.cpp",
                        include("vtm/rectify/rectifier.hpp") + include("vtm/stereo/ml_stereo.hpp"))
        self.assertEqual(self.rules(), ["fsw/terrain/src/geometry.cpp:2: include-layer"])

    def test_a_cycle_of_module_links_is_refused(self) -> None:
        self.tree.write("fsw/terrain/CMakeLists.txt", "target_link_libraries(vtm_terrain PUBLIC vtm_rectify)\n")
        self.tree.write("fsw/rectify/CMakeLists.txt", "target_link_libraries(vtm_rectify PUBLIC vtm_terrain)\n")
        found = self.tree.findings()
        self.assertEqual(sorted(f.split(": ")[1] for f in found), ["module-cycle", "module-cycle"])

    def test_core_may_include_only_core(self) -> None:
        self.tree.write("fsw/core/src/arena.cpp", include("vtm/core/arena.hpp") + include("vtm/stereo/x.hpp"))
        self.assertEqual(self.rules(), ["fsw/core/src/arena.cpp:2: include-layer"])

    # --- relative includes and tools/ on tests/ --------------------------------------------
    def test_relative_include_is_refused_everywhere(self) -> None:
        self.tree.write("tools/sim/main.cpp", include("../vtm/exit_codes.hpp"))
        self.tree.write("tests/peer/descent_peer_test.cpp", include("../descent/descent_scene.hpp"))
        self.tree.write("fsw/stereo/src/a.cpp", include("../include/vtm/stereo/a.hpp"))
        # fsw/ also refuses it as a layer (the path names no allowed header).
        self.assertEqual(sorted(self.rules()), ["fsw/stereo/src/a.cpp:1: include-layer",
                                                "fsw/stereo/src/a.cpp:1: include-relative",
                                                "tests/peer/descent_peer_test.cpp:1: include-relative",
                                                "tools/sim/main.cpp:1: include-relative"])

    def test_tools_may_not_include_a_header_of_tests(self) -> None:
        self.tree.write("tests/peer/include/vtm/peer/peer_stereo.hpp", "#pragma once\n")
        self.tree.write("tools/bench/stereo_bench.cpp",
                        include("vtm/peer/peer_stereo.hpp") + include("tests/support/temp_dir.hpp"))
        self.assertEqual(self.rules(), ["tools/bench/stereo_bench.cpp:1: tools-tests",
                                        "tools/bench/stereo_bench.cpp:2: tools-tests"])

    def test_a_header_in_tools_may_be_shared_with_tests(self) -> None:
        self.tree.write("tools/peer/include/vtm/peer/peer_stereo.hpp", "#pragma once\n")
        self.tree.write("tools/bench/stereo_bench.cpp", include("vtm/peer/peer_stereo.hpp"))
        self.tree.write("tests/peer/peer_accuracy_test.cpp", include("vtm/peer/peer_stereo.hpp"))
        self.assertEqual(self.rules(), [])

    def test_tools_cmake_may_not_link_a_library_of_tests_or_name_a_tests_path(self) -> None:
        self.tree.write("tests/peer/CMakeLists.txt", "add_library(vtm_stereo_peers STATIC peer_stereo.cpp)\n")
        self.tree.write("tools/bench/CMakeLists.txt",
                        "# vtm_stereo_peers used to live in tests/peer (a comment is not a dependency)\n"
                        "target_link_libraries(vtm_bench_stereo PRIVATE vtm_stereo_peers)\n"
                        "target_include_directories(x PRIVATE ${PROJECT_SOURCE_DIR}/tests/support)\n"
                        "target_link_libraries(vtm_bench_stereo PRIVATE vtm_stereo_peers_extra)\n")
        self.assertEqual(self.rules(), ["tools/bench/CMakeLists.txt:2: tools-tests",
                                        "tools/bench/CMakeLists.txt:3: tools-tests"])

    # --- the document states the same rule ------------------------------------------------
    def test_flight_rules_r12_quotes_the_policy_layering(self) -> None:
        rows = [line for line in (REPO / "docs" / "flight-rules.md").read_text().splitlines()
                if line.startswith("| R12 |")]
        self.assertEqual(len(rows), 1)
        for prefix in ("fsw/app/", "fsw/"):
            zone = next(z for z in policy.ZONES if z.prefix == prefix)
            self.assertIn(f"`{zone.why}`", rows[0], prefix)

    def test_the_repository_itself_is_clean(self) -> None:
        self.assertEqual(policy.check_sources(REPO), [])


if __name__ == "__main__":
    unittest.main(verbosity=1)
