// The image contents of the instruction probes (issue 22 item 5: a flight budget must hold
// for any image): "texture" (the probes' own, the default) and the adversarial ones,
// "noise" unsmoothed full-range noise, "flat" one grey level, "periodic" 4 px stripes,
// "saturated" the texture's levels times 4 clipped, "allbins" every level in turn.
// Test code.
#pragma once

#include <cstdio>
#include <string>

namespace vtm::bench {

inline const char* const kContents = "texture|noise|flat|periodic|saturated|allbins";

// True when `kind` is one of kContents; otherwise prints "PROBE: CONTENT must be ...".
inline bool knownContent(const std::string& kind, const char* probe) {
    if (("|" + std::string(kContents) + "|").find("|" + kind + "|") != std::string::npos) {
        return true;
    }
    std::fprintf(stderr, "%s: CONTENT must be one of %s\n", probe, kContents);
    return false;
}

// The grey levels a content uses on a sensor of `max` (255, 4095): flat, the stripes'
// two levels.
struct ContentLevels {
    int max;
    int flat;
    int stripe_dark;
    int stripe_bright;
};

// The grey level of pixel (x, y) of a `width`-wide image for `kind`, from the probe's
// texture t and its raw noise r there.
inline int contentValue(const std::string& kind, const ContentLevels& l, int x, int y, int width, int t, int r) {
    if (kind == "noise") return r;
    if (kind == "flat") return l.flat;
    if (kind == "periodic") return (x / 2) % 2 == 0 ? l.stripe_dark : l.stripe_bright;
    if (kind == "saturated") return t * 4 > l.max ? l.max : t * 4;
    if (kind == "allbins") return (x + y * width) % (l.max + 1);
    return t;
}

}  // namespace vtm::bench
