// `vtm-sim serve <scenario> --tcp HOST:PORT | --unix PATH [--frames N] [--rate HZ]
//  [--chunk BYTES] [--fault KIND:N]... [--camera ID] [--soak SEED [--fault-rate PERMILLE]
//  [--stall-ms MS] [--hang-ms MS]] [--fault-log FILE]`: the ground side of the HIL link. Waits for one
// flight-side receiver to connect, then streams the scenario's camera description and,
// per frame, the odometry pose and the rendered frame in the framed protocol of
// docs/icd-hil-link.md, then an end-of-stream message. Fault flags damage the stream on
// purpose for tests: crc:N (a payload byte of every Nth message flipped after its CRC
// was computed), truncate:N (every Nth message cut to half), replay:N (every Nth message
// sent twice), garbage:N (37 bytes of noise before every Nth message); one fault per
// message. --soak SEED draws faults at random instead, of every kind including drops,
// stalls, hangs and disconnects (after which the next connection is accepted and the
// stream goes on with the next frame); --fault-log FILE writes what was injected.
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
    int camera_id = -1;             // only this camera's frames (-1: every camera of the main size)
    long long soak_seed = -1;       // >= 0: random faults of every kind (serve_writer.hpp)
    int fault_rate_permille = 20;   // --soak: messages hit per 1000
    int stall_ms = 100;             // --soak: a stall's pause
    int hang_ms = 0;                // --soak: a hang's pause (0: none)
    std::string fault_log;          // what was injected (serve_writer.hpp, LinkWriter::log)
};

// Registers the subcommand on `app`. When it is parsed the server runs from the
// subcommand's callback; a failure prints one line on stderr and exits with 1 (input
// error) or 2 (usage error).
CLI::App* addServeCommand(CLI::App& app);

// Runs the server; returns the exit code (0 ok, 1 input/IO error, 2 usage error).
int runServe(const ServeOptions& options);

}  // namespace vtm::simtool
