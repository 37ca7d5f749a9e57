#include "serve_writer.hpp"

#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <sstream>
#include <thread>

namespace vtm::simtool {

namespace link = vtm::hal::link;

const char* faultName(Fault f) {
    static const char* const kNames[kFaultKinds] = {"none",   "drop",    "crc",   "truncate",  "replay",
                                                    "garbage", "stall", "hang", "disconnect"};
    const auto i = static_cast<int>(f);
    return i >= 0 && i < kFaultKinds ? kNames[i] : "unknown";
}

bool parseFaults(const std::vector<std::string>& specs, FaultPlan& plan) {
    for (const std::string& spec : specs) {
        const std::size_t colon = spec.find(':');
        if (colon == std::string::npos) {
            return false;
        }
        const std::string kind = spec.substr(0, colon);
        const int n = std::atoi(spec.c_str() + colon + 1);
        if (n < 1) {
            return false;
        }
        int* slot = kind == "crc"        ? &plan.crc_every
                    : kind == "truncate" ? &plan.truncate_every
                    : kind == "replay"   ? &plan.replay_every
                    : kind == "garbage"  ? &plan.garbage_every
                                         : nullptr;
        if (slot == nullptr) {
            return false;
        }
        *slot = n;
    }
    return true;
}

// One fault per message: at random in a soak; otherwise the first of crc, truncate,
// replay, garbage whose period divides the message count.
Fault LinkWriter::pick() {
    if (protected_ || (plan_.soak && count_ == 1U)) {  // a soak starts with an intact description
        return Fault::kNone;
    }
    if (plan_.soak) {
        if (static_cast<int>(random_() % 1000U) >= plan_.rate_permille) {
            return Fault::kNone;
        }
        const int kinds = plan_.hang_ms > 0 ? kFaultKinds - 1 : kFaultKinds - 2;  // without kHang when 0
        int k = 1 + static_cast<int>(random_() % static_cast<std::uint64_t>(kinds));
        if (plan_.hang_ms <= 0 && k >= static_cast<int>(Fault::kHang)) {
            ++k;  // skip kHang
        }
        return static_cast<Fault>(k);
    }
    return every(plan_.crc_every)        ? Fault::kCrc
           : every(plan_.truncate_every) ? Fault::kTruncate
           : every(plan_.replay_every)   ? Fault::kReplay
           : every(plan_.garbage_every)  ? Fault::kGarbage
                                         : Fault::kNone;
}

void LinkWriter::record(Fault f) {
    ++totals_[static_cast<int>(f)];
    if (f == Fault::kNone || frame_ < 0) {
        return;
    }
    // A disconnect on a frame's pose loses the whole frame too: the next connection goes
    // on with the next frame.
    const bool on_pose = is_pose_ && f != Fault::kDisconnect;
    std::string& line = frame_faults_[frame_];
    line += std::string(line.empty() ? "" : " ") + (on_pose ? "pose:" : "frame:") + faultName(f);
}

LinkWriter::Sent LinkWriter::send(link::MessageType type, const std::vector<std::uint8_t>& payload) {
    std::vector<std::uint8_t> msg(link::kHeaderBytes + payload.size());
    const std::size_t n = link::encodeMessage(type, sequence_++, Span<const std::uint8_t>(payload.data(), payload.size()),
                                              Span<std::uint8_t>(msg.data(), msg.size()));
    if (n == 0U) {
        return Sent::kPeerGone;  // cannot happen for the payloads the server builds
    }
    ++count_;
    const Fault f = pick();
    record(f);
    bool ok = true;
    switch (f) {
        case Fault::kDrop:
            return Sent::kOk;
        case Fault::kCrc:
            msg[msg.size() > link::kHeaderBytes ? msg.size() - 1U : link::kHeaderBytes - 1U] ^= 0x01U;
            return writeAll(msg.data(), msg.size()) ? Sent::kOk : Sent::kPeerGone;
        case Fault::kTruncate:
            return writeAll(msg.data(), msg.size() / 2U) ? Sent::kOk : Sent::kPeerGone;
        case Fault::kDisconnect:
            (void)writeAll(msg.data(), msg.size() / 2U);
            ::shutdown(fd_, SHUT_RDWR);
            ::close(fd_);
            fd_ = -1;
            return Sent::kDisconnected;
        case Fault::kReplay:
            ok = writeAll(msg.data(), msg.size());
            break;
        case Fault::kGarbage: {
            std::vector<std::uint8_t> noise(37U);
            for (std::size_t i = 0U; i < noise.size(); ++i) {
                noise[i] = static_cast<std::uint8_t>(count_ * 131U + i * 29U);
            }
            ok = writeAll(noise.data(), noise.size());
            break;
        }
        case Fault::kStall:
        case Fault::kHang:
            std::this_thread::sleep_for(std::chrono::milliseconds(f == Fault::kStall ? plan_.stall_ms : plan_.hang_ms));
            break;
        case Fault::kNone:
            break;
    }
    ok = ok && writeAll(msg.data(), msg.size());
    intact_ += ok ? 1U : 0U;
    return ok ? Sent::kOk : Sent::kPeerGone;
}

bool LinkWriter::writeAll(const std::uint8_t* data, std::size_t size) {
    std::size_t pos = 0U;
    while (pos < size) {  // bound: each pass writes >= 1 byte or fails
        const ssize_t w = ::send(fd_, data + pos, size - pos, MSG_NOSIGNAL);
        if (w <= 0) {
            return false;
        }
        pos += static_cast<std::size_t>(w);
    }
    bytes_ += size;
    return true;
}

std::string LinkWriter::log(std::uint64_t frames_sent) const {
    std::ostringstream out;
    out << "vtm-sim-faults 1\n";
    for (const auto& [frame, faults] : frame_faults_) {
        out << "frame " << frame << (faults.empty() ? "" : " ") << faults << '\n';
    }
    out << "total messages " << count_ << " intact " << intact_;
    for (int k = 1; k < kFaultKinds; ++k) {
        out << ' ' << faultName(static_cast<Fault>(k)) << ' ' << totals_[k];
    }
    out << " connections " << connections_ << " frames " << frames_sent << '\n';
    return out.str();
}

}  // namespace vtm::simtool
