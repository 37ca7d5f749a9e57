// `vtm-sim serve <scenario> --tcp HOST:PORT | --unix PATH [--frames N] [--rate HZ]
//  [--chunk BYTES] [--fault KIND:N]...`: the ground side of the HIL link. Waits for one
// flight-side receiver to connect, then streams the scenario's camera description and,
// per frame, the odometry pose and the rendered frame in the framed protocol of
// docs/icd-hil-link.md, then an end-of-stream message. Fault flags damage the stream on
// purpose for tests: crc:N (a payload byte of every Nth message flipped after its CRC
// was computed), truncate:N (every Nth message cut to half), replay:N (every Nth message
// sent twice), garbage:N (37 bytes of noise before every Nth message).
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>
#include <vector>

namespace vtm::simtool {

struct ServeOptions {
    std::string scenario;           // scenario text file (sim/scenarios/*.scn)
    std::string tcp;                // "127.0.0.1:PORT" (listen address)
    std::string unix_path;          // Unix-domain socket path (created, removed at exit)
    int frames = -1;                // frames to stream (-1: all of the scenario)
    double rate_hz = 0.0;           // frame rate; 0: as fast as the receiver reads
    int chunk_bytes = 65536;        // pixel bytes per chunk message (whole pixels)
    int accept_timeout_s = 30;      // give up when nobody connects
    std::vector<std::string> faults;  // "crc:N", "truncate:N", "replay:N", "garbage:N"
};

// Registers the subcommand on `app`. When it is parsed the server runs from the
// subcommand's callback; a failure prints one line on stderr and exits with 1 (input
// error) or 2 (usage error).
CLI::App* addServeCommand(CLI::App& app);

// Runs the server; returns the exit code (0 ok, 1 input/IO error, 2 usage error).
int runServe(const ServeOptions& options);

}  // namespace vtm::simtool
