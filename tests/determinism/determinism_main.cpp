// vtm_determinism: prints the determinism suite's hash per section, and optionally
// writes it to a file (the host reference) or compares it with one (a cross target,
// another optimisation level). Exit 0 when equal / written, 1 on any difference.
//
//   vtm_determinism --write FILE      host: record the reference
//   vtm_determinism --expect FILE     any build: compare with the reference
#include <cinttypes>
#include <cstdio>
#include <cstring>

#include "determinism_suite.hpp"

namespace {

using vtm::determinism::Section;

int usage() {
    std::fprintf(stderr, "usage: vtm_determinism [--write FILE | --expect FILE]\n");
    return 2;
}

void format(char* out, std::size_t size) {
    std::size_t used = 0;
    for (int i = 0; i < vtm::determinism::kSectionCount; ++i) {
        const auto s = static_cast<Section>(i);
        const int n = std::snprintf(out + used, size - used, "%s 0x%016" PRIx64 "\n",
                                    vtm::determinism::sectionName(s), vtm::determinism::sectionHash(s));
        used += static_cast<std::size_t>(n > 0 ? n : 0);
    }
}

}  // namespace

int main(int argc, char** argv) {
    static char mine[1024];
    format(mine, sizeof mine);
    std::fputs(mine, stdout);
    if (argc == 1) {
        return 0;
    }
    if (argc != 3) {
        return usage();
    }
    if (std::strcmp(argv[1], "--write") == 0) {
        std::FILE* f = std::fopen(argv[2], "w");
        if (f == nullptr || std::fputs(mine, f) < 0 || std::fclose(f) != 0) {
            std::fprintf(stderr, "vtm_determinism: cannot write %s\n", argv[2]);
            return 1;
        }
        return 0;
    }
    if (std::strcmp(argv[1], "--expect") != 0) {
        return usage();
    }
    static char reference[1024];
    std::FILE* f = std::fopen(argv[2], "r");
    if (f == nullptr) {
        std::fprintf(stderr, "vtm_determinism: reference %s is missing (run the host tests first)\n", argv[2]);
        return 1;
    }
    const std::size_t n = std::fread(reference, 1, sizeof reference - 1, f);
    std::fclose(f);
    reference[n] = '\0';
    if (std::strcmp(reference, mine) != 0) {
        std::fprintf(stderr, "vtm_determinism: MISMATCH with %s\nreference:\n%s", argv[2], reference);
        return 1;
    }
    std::printf("identical to %s\n", argv[2]);
    return 0;
}
