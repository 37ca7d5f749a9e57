#include <algorithm>
#include <cstring>

#include "hal/link/link_session.hpp"

namespace vtm::hal::link {
namespace {

// Copies whole pixels [offset, offset + data.size()) of the packed frame into the sink,
// row segment by row segment. 16-bit samples are big-endian on the wire.
Status copyPixels(const detail::FrameSink& sink, std::uint32_t bytes_per_pixel, std::uint32_t offset_bytes,
                  Span<const std::uint8_t> data) noexcept {
    if ((bytes_per_pixel == 1U) ? sink.px8 == nullptr : sink.px16 == nullptr) {
        // The 8-bit / 16-bit path check in captureFrame() rules this out.
        return Status(StatusCode::kUnsupported, "link: frame's pixel size does not match the capture path",
                      bytes_per_pixel);
    }
    std::size_t pixel = offset_bytes / bytes_per_pixel;
    std::size_t left = data.size() / bytes_per_pixel;
    const std::uint8_t* src = data.data();
    const auto width = static_cast<std::size_t>(sink.width_px);
    // bound: one pass per image row the chunk touches (at most its pixel count).
    while (left > 0U) {
        const std::size_t y = pixel / width;
        const std::size_t x = pixel % width;
        const std::size_t run = std::min(left, width - x);
        const std::size_t row_start = y * static_cast<std::size_t>(sink.stride_px) + x;
        if (bytes_per_pixel == 1U) {
            std::memcpy(sink.px8 + row_start, src, run);
        } else {
            for (std::size_t i = 0U; i < run; ++i) {
                const auto v = static_cast<std::uint16_t>((static_cast<std::uint32_t>(src[2U * i]) << 8U) |
                                                          src[2U * i + 1U]);
                if (v > sink.max_sample) {
                    return Status(StatusCode::kCorruptData, "link: 16-bit sample above the camera's bit depth", v);
                }
                sink.px16[row_start + i] = v;
            }
        }
        src += run * bytes_per_pixel;
        pixel += run;
        left -= run;
    }
    return Status::ok();
}

template <typename Pixel>
detail::FrameSink makeSink(const ImageView<Pixel>& out) noexcept {
    detail::FrameSink sink;
    sink.width_px = out.width();
    sink.height_px = out.height();
    sink.stride_px = out.stride();
    return sink;
}

}  // namespace

Status LinkSession::startFrame(const FrameBegin& begin, detail::FrameAssembly& frame) noexcept {
    frame = detail::FrameAssembly{};
    if (begin.info.width_px != description_.width_px || begin.info.height_px != description_.height_px ||
        begin.info.bit_depth != description_.bit_depth) {
        return fault(LinkFault::kFrameSize, StatusCode::kSizeMismatch,
                     "link: frame size or bit depth differs from the camera description", begin.info.width_px);
    }
    frame.active = true;
    frame.begin = begin;
    return Status::ok();
}

Status LinkSession::addChunk(const FrameChunk& chunk, const detail::FrameSink& sink,
                             detail::FrameAssembly& frame) noexcept {
    const std::uint32_t bpp = frame.begin.bytes_per_pixel;
    if (chunk.offset_bytes != frame.received_bytes) {
        frame.active = false;
        return fault(LinkFault::kFrameIncomplete, StatusCode::kCorruptData,
                     "link: frame chunk missing or out of place (offset_bytes)", chunk.offset_bytes);
    }
    if (chunk.data.size() > frame.begin.pixel_bytes - frame.received_bytes || chunk.data.size() % bpp != 0U) {
        frame.active = false;
        return fault(LinkFault::kBadLength, StatusCode::kCorruptData,
                     "link: frame chunk not whole pixels or past the frame's pixel_bytes",
                     static_cast<std::int64_t>(chunk.data.size()));
    }
    const Status s = copyPixels(sink, bpp, chunk.offset_bytes, chunk.data);
    if (!s.isOk()) {
        frame.active = false;
        decoder_.counters().add(LinkFault::kBadLength);
        return s;
    }
    frame.received_bytes += static_cast<std::uint32_t>(chunk.data.size());
    return Status::ok();
}

// A message during capture; done = the frame is complete.
Status LinkSession::onFrameMessage(const Message& message, const detail::FrameSink& sink,
                                   detail::FrameAssembly& frame, bool& done) noexcept {
    done = false;
    if (message.header.type == MessageType::kFrameBegin) {
        FrameBegin begin;
        const Status s = decodeFrameBegin(message.payload, begin);
        if (!s.isOk()) {
            frame.active = false;
            decoder_.counters().add(LinkFault::kBadLength);
            return s;
        }
        if (frame.active) {
            // The frame in assembly was cut short; the new one is the next capture's.
            frame.active = false;
            pending_frame_ = begin;
            has_pending_frame_ = true;
            return fault(LinkFault::kFrameIncomplete, StatusCode::kCorruptData,
                         "link: frame cut short (the next frame began)", frame.received_bytes);
        }
        return startFrame(begin, frame);
    }
    if (message.header.type == MessageType::kFrameChunk) {
        FrameChunk chunk;
        VTM_RETURN_IF_ERROR(decodeFrameChunk(message.payload, chunk));
        if (!frame.active || chunk.frame_sequence != frame.begin.info.sequence) {
            ++decoder_.counters().orphan_chunks;
            return Status::ok();
        }
        VTM_RETURN_IF_ERROR(addChunk(chunk, sink, frame));
        done = frame.received_bytes == frame.begin.pixel_bytes;
        return Status::ok();
    }
    if (message.header.type == MessageType::kEndOfStream && frame.active) {
        end_of_stream_ = true;
        frame.active = false;
        return fault(LinkFault::kFrameIncomplete, StatusCode::kCorruptData,
                     "link: frame cut short (end of stream)", frame.received_bytes);
    }
    return applyControl(message);
}

Status LinkSession::captureFrame(const detail::FrameSink& sink, bool wide, FrameInfo& info) noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "link: capture before init()");
    }
    const std::uint64_t deadline = deadlineNs();
    VTM_RETURN_IF_ERROR(pumpControlUntilDescription(deadline));
    if (!have_description_) {
        return Status(StatusCode::kNoData, "link: no camera description before the first frame or end of stream");
    }
    if (sink.width_px != description_.width_px || sink.height_px != description_.height_px) {
        return Status(StatusCode::kSizeMismatch, "link: output buffer size differs from the camera's", sink.width_px);
    }
    if (wide != (description_.bit_depth > 8U)) {
        return Status(StatusCode::kUnsupported,
                      wide ? "link: 8-bit camera: use capture()" : "link: camera has more than 8 bits: use capture16()",
                      description_.bit_depth);
    }
    detail::FrameAssembly frame;
    if (has_pending_frame_) {
        has_pending_frame_ = false;
        VTM_RETURN_IF_ERROR(startFrame(pending_frame_, frame));
    }
    // Every message either completes the frame, fails, or is consumed.
    // bound: nextMessage() returns kTimeout at the deadline
    for (;;) {
        if (end_of_stream_ && !frame.active) {
            return Status(StatusCode::kNoData, "link: end of stream");
        }
        VTM_RETURN_IF_ERROR(nextMessage(deadline));
        bool done = false;
        VTM_RETURN_IF_ERROR(onFrameMessage(decoder_.message(), sink, frame, done));
        if (done) {
            info = frame.begin.info;
            ++decoder_.counters().frames_ok;
            return Status::ok();
        }
    }
}

Status LinkCamera::describe(CameraDescription& out) const noexcept { return session_->describe(out); }

Status LinkCamera::capture(const ImageView<std::uint8_t>& out, FrameInfo& info) noexcept {
    if (!out.valid()) {
        return Status(StatusCode::kSizeMismatch, "link: output image is empty or malformed");
    }
    detail::FrameSink sink = makeSink(out);
    sink.px8 = out.data();
    return session_->captureFrame(sink, false, info);
}

Status LinkCamera::capture16(const ImageView<std::uint16_t>& out, FrameInfo& info) noexcept {
    if (!out.valid()) {
        return Status(StatusCode::kSizeMismatch, "link: output image is empty or malformed");
    }
    CameraDescription d;
    VTM_RETURN_IF_ERROR(session_->describe(d));
    detail::FrameSink sink = makeSink(out);
    sink.px16 = out.data();
    sink.max_sample = (1U << d.bit_depth) - 1U;
    return session_->captureFrame(sink, true, info);
}

}  // namespace vtm::hal::link
