// vtm_determinism: prints the determinism suite's hash per section, and optionally
// writes it to a file (the host reference) or compares it with one (a cross target,
// another optimisation level). Exit 0 when equal / written, 1 on any difference.
//
//   vtm_determinism [--sections a,b,...] --write FILE    host: record the reference
//   vtm_determinism [--sections a,b,...] --expect FILE   any build: compare with the reference
//
// --sections computes only the named sections (names as printed), and --expect compares
// them with the reference's lines of the same names (every named line must be there).
// Without it, every section, and the whole reference must match.
#include <cinttypes>
#include <cstdio>
#include <cstring>

#include "determinism_suite.hpp"

namespace {

using vtm::determinism::Section;
constexpr int kCount = vtm::determinism::kSectionCount;

int usage() {
    std::fprintf(stderr, "usage: vtm_determinism [--sections NAME,NAME,...] [--write FILE | --expect FILE]\n");
    return 2;
}

// Marks the sections named in a comma-separated list; false (with a message) on a name
// that is not a section.
bool selectSections(const char* list, bool (&chosen)[kCount]) {
    for (bool& c : chosen) c = false;
    const char* p = list;
    while (*p != '\0') {
        const char* end = std::strchr(p, ',');
        const std::size_t len = end != nullptr ? static_cast<std::size_t>(end - p) : std::strlen(p);
        bool found = false;
        for (int i = 0; i < kCount; ++i) {
            const char* name = vtm::determinism::sectionName(static_cast<Section>(i));
            if (std::strlen(name) == len && std::strncmp(name, p, len) == 0) {
                chosen[i] = true;
                found = true;
            }
        }
        if (!found) {
            std::fprintf(stderr, "vtm_determinism: --sections: '%.*s' is not a section\n", static_cast<int>(len), p);
            return false;
        }
        p += len;
        if (*p == ',') ++p;
    }
    return true;
}

void format(const bool (&chosen)[kCount], char* out, std::size_t size) {
    std::size_t used = 0;
    out[0] = '\0';
    for (int i = 0; i < kCount; ++i) {
        if (!chosen[i]) continue;
        const auto s = static_cast<Section>(i);
        const int n = std::snprintf(out + used, size - used, "%s 0x%016" PRIx64 "\n",
                                    vtm::determinism::sectionName(s), vtm::determinism::sectionHash(s));
        used += static_cast<std::size_t>(n > 0 ? n : 0);
    }
}

// Each line of `mine` must be a whole line of `reference`.
bool linesInReference(const char* mine, const char* reference) {
    const std::size_t ref_len = std::strlen(reference);
    for (const char* line = mine; *line != '\0';) {
        const char* nl = std::strchr(line, '\n');
        const std::size_t len = nl != nullptr ? static_cast<std::size_t>(nl - line) + 1 : std::strlen(line);
        bool found = false;
        for (const char* r = reference; r + len <= reference + ref_len; r = std::strchr(r, '\n') + 1) {
            if (std::strncmp(r, line, len) == 0) {
                found = true;
                break;
            }
            if (std::strchr(r, '\n') == nullptr) break;
        }
        if (!found) return false;
        line += len;
    }
    return true;
}

}  // namespace

int main(int argc, char** argv) {
    bool chosen[kCount];
    for (bool& c : chosen) c = true;
    bool subset = false;
    int arg = 1;
    if (argc >= 3 && std::strcmp(argv[1], "--sections") == 0) {
        if (!selectSections(argv[2], chosen)) return usage();
        subset = true;
        arg = 3;
    }
    static char mine[1024];
    format(chosen, mine, sizeof mine);
    std::fputs(mine, stdout);
    if (argc == arg) {
        return 0;
    }
    if (argc != arg + 2) {
        return usage();
    }
    const char* mode = argv[arg];
    const char* file = argv[arg + 1];
    if (std::strcmp(mode, "--write") == 0) {
        std::FILE* f = std::fopen(file, "w");
        if (f == nullptr || std::fputs(mine, f) < 0 || std::fclose(f) != 0) {
            std::fprintf(stderr, "vtm_determinism: cannot write %s\n", file);
            return 1;
        }
        return 0;
    }
    if (std::strcmp(mode, "--expect") != 0) {
        return usage();
    }
    static char reference[1024];
    std::FILE* f = std::fopen(file, "r");
    if (f == nullptr) {
        std::fprintf(stderr, "vtm_determinism: reference %s is missing (run the host tests first)\n", file);
        return 1;
    }
    const std::size_t n = std::fread(reference, 1, sizeof reference - 1, f);
    std::fclose(f);
    reference[n] = '\0';
    const bool same = subset ? linesInReference(mine, reference) : std::strcmp(reference, mine) == 0;
    if (!same) {
        std::fprintf(stderr, "vtm_determinism: MISMATCH with %s\nreference:\n%s", file, reference);
        return 1;
    }
    std::printf("identical to %s%s\n", file, subset ? " (the sections above)" : "");
    return 0;
}
