// The HIL server's message writer and its fault injection (vtm-sim serve, docs/hal-link.md).
// Faults come either every Nth message (--fault KIND:N, the link tests) or at random from a
// seed (--soak SEED, the soak: each message is hit with probability --fault-rate per mille,
// by one kind drawn uniformly from all of them). What was injected is kept per frame and in
// totals so that the receiver's accounting can be checked against it (--fault-log).
#pragma once

#include <cstdint>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "hal/link/protocol.hpp"

namespace vtm::simtool {

enum class Fault : std::uint8_t {
    kNone = 0,
    kDrop,        // the message is not sent (its sequence number is skipped)
    kCrc,         // a payload byte (or the header's last byte) flipped after the CRC
    kTruncate,    // only the first half of the message is sent
    kReplay,      // the message is sent twice
    kGarbage,     // 37 bytes of noise before the message
    kStall,       // a pause of stall_ms before the message (shorter than the receiver's timeout)
    kHang,        // a pause of hang_ms before the message (longer than the receiver's timeout)
    kDisconnect,  // half the message, then the connection is closed; the stream goes on
                  // on the next connection with the next frame
};
inline constexpr int kFaultKinds = 9;
[[nodiscard]] const char* faultName(Fault f);

struct FaultPlan {
    int crc_every = 0;  // --fault KIND:N
    int truncate_every = 0;
    int replay_every = 0;
    int garbage_every = 0;
    bool soak = false;           // --soak SEED: random faults of every kind
    std::uint64_t seed = 0U;
    int rate_permille = 20;      // --fault-rate
    int stall_ms = 100;          // --stall-ms
    int hang_ms = 0;             // --hang-ms (0: no hangs)
};

// Parses "crc:N", "truncate:N", "replay:N", "garbage:N" into plan; false on anything else.
[[nodiscard]] bool parseFaults(const std::vector<std::string>& specs, FaultPlan& plan);

// Encodes messages, applies the fault plan and writes them to the connected socket.
class LinkWriter {
public:
    enum class Sent : std::uint8_t { kOk, kDisconnected, kPeerGone };

    explicit LinkWriter(FaultPlan plan) : plan_(plan), random_(plan.seed) {}

    // A new connection: sequence numbers start again at 1.
    void attach(int fd) {
        fd_ = fd;
        sequence_ = 1U;
        ++connections_;
    }
    // The frame the next messages belong to (its sequence), or -1 for none (camera
    // description, end of stream). `is_pose`: the next message is the frame's pose.
    void setFrame(std::int64_t frame_sequence, bool is_pose) {
        frame_ = frame_sequence;
        is_pose_ = is_pose;
        if (frame_sequence >= 0) {
            (void)frame_faults_[frame_sequence];  // every frame sent is in the log
        }
    }
    // No fault on the following messages (the end of the stream).
    void protect() { protected_ = true; }

    // kDisconnected: the fault closed the connection (the caller accepts the next one);
    // kPeerGone: the receiver closed it.
    [[nodiscard]] Sent send(hal::link::MessageType type, const std::vector<std::uint8_t>& payload);

    int fd() const { return fd_; }  // -1 after a disconnect fault
    std::uint64_t bytesWritten() const { return bytes_; }
    std::uint64_t messages() const { return count_; }
    // The log: "vtm-sim-faults 1", one "frame SEQ [pose:KIND | frame:KIND]..." line per
    // frame sent, with the faults that hit its pose or its begin and chunks, and a
    // "total ..." line (docs/hal-link.md, "Soak").
    [[nodiscard]] std::string log(std::uint64_t frames_sent) const;

private:
    [[nodiscard]] Fault pick();
    [[nodiscard]] bool every(int n) const { return n > 0 && count_ % static_cast<std::uint64_t>(n) == 0U; }
    [[nodiscard]] bool writeAll(const std::uint8_t* data, std::size_t size);
    void record(Fault f);

    int fd_ = -1;
    FaultPlan plan_;
    std::mt19937_64 random_;
    bool protected_ = false;
    std::uint32_t sequence_ = 1U;
    std::uint64_t count_ = 0U;
    std::uint64_t bytes_ = 0U;
    std::uint64_t intact_ = 0U;  // messages that reached the socket whole and unchanged, once
    std::uint64_t totals_[kFaultKinds] = {};
    std::uint64_t connections_ = 0U;
    std::int64_t frame_ = -1;
    bool is_pose_ = false;
    std::map<std::int64_t, std::string> frame_faults_;  // frame sequence -> "frame:crc pose:drop ..."
};

}  // namespace vtm::simtool
