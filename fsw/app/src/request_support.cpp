#include "request_support.hpp"

#include <cmath>

#include "vtm/core/math.hpp"

namespace vtm::app::detail {

void toGrey8(const ImageView<const std::uint16_t>& in, std::uint8_t bit_depth,
             const ImageView<std::uint8_t>& out) noexcept {
    const std::uint32_t shift = bit_depth > 8U ? static_cast<std::uint32_t>(bit_depth) - 8U : 0U;
    for (std::int32_t y = 0; y < in.height(); ++y) {
        const std::uint16_t* src = in.row(y);
        std::uint8_t* dst = out.row(y);
        for (std::int32_t x = 0; x < in.width(); ++x) {
            const std::uint32_t v = static_cast<std::uint32_t>(src[x]) >> shift;
            dst[x] = static_cast<std::uint8_t>(v > 255U ? 255U : v);
        }
    }
}

namespace {

constexpr std::uint32_t kUnitGainQ16 = 65536U;

// Median grey level of the pixels above 0, or 0 when there is none.
std::uint32_t medianWithContent(const ImageView<const std::uint8_t>& image) noexcept {
    std::uint32_t histogram[256] = {};
    for (std::int32_t y = 0; y < image.height(); ++y) {
        const std::uint8_t* row = image.row(y);
        for (std::int32_t x = 0; x < image.width(); ++x) {
            ++histogram[row[x]];
        }
    }
    std::uint64_t count = 0U;
    for (std::uint32_t v = 1U; v < 256U; ++v) {
        count += histogram[v];
    }
    std::uint64_t seen = 0U;
    for (std::uint32_t v = 1U; v < 256U; ++v) {
        seen += histogram[v];
        if (2U * seen >= count && count > 0U) {
            return v;
        }
    }
    return 0U;
}

}  // namespace

std::uint32_t equalizeExposure(const ImageView<const std::uint8_t>& reference, const ImageView<std::uint8_t>& image,
                               std::int32_t tolerance_percent) noexcept {
    const std::uint32_t m_ref = medianWithContent(reference);
    const std::uint32_t m_img = medianWithContent(ImageView<const std::uint8_t>(image));
    if (m_ref == 0U || m_img == 0U) {
        return kUnitGainQ16;
    }
    const std::uint32_t gain = (m_ref * kUnitGainQ16 + m_img / 2U) / m_img;  // <= 255 * 65536 + 127: fits
    const std::uint32_t off = gain > kUnitGainQ16 ? gain - kUnitGainQ16 : kUnitGainQ16 - gain;
    if (static_cast<std::uint64_t>(off) * 100U <= static_cast<std::uint64_t>(tolerance_percent) * kUnitGainQ16) {
        return kUnitGainQ16;
    }
    for (std::int32_t y = 0; y < image.height(); ++y) {
        std::uint8_t* row = image.row(y);
        for (std::int32_t x = 0; x < image.width(); ++x) {
            const std::uint64_t v = (static_cast<std::uint64_t>(row[x]) * gain + kUnitGainQ16 / 2U) >> 16U;
            row[x] = static_cast<std::uint8_t>(v > 255U ? 255U : v);
        }
    }
    return gain;
}

std::int64_t positionSigmaMm(const hal::PoseEstimate& pose) noexcept {
    const double trace = pose.covariance[0] + pose.covariance[7] + pose.covariance[14];
    return static_cast<std::int64_t>(std::floor(1000.0 * math::sqrt(trace > 0.0 ? trace : 0.0) + 0.5));
}

double relativeRotationSigmaRad(const hal::PoseEstimate& a, const hal::PoseEstimate& b) noexcept {
    // Rows and columns 3..5 of the 6x6 row-major covariance: the rotation block's diagonal.
    const double variance = a.covariance[21] + a.covariance[28] + a.covariance[35] + b.covariance[21] +
                            b.covariance[28] + b.covariance[35];
    return variance > 0.0 && math::isFinite(variance) ? math::sqrt(variance) : 0.0;
}

bool refinementIsCertainEnough(double refined_sigma_rad, double odometry_sigma_rad, double max_ratio) noexcept {
    if (!(max_ratio > 0.0) || !(odometry_sigma_rad > 0.0)) {
        return true;  // off, or the odometry states no rotation uncertainty to compare with
    }
    return refined_sigma_rad <= max_ratio * odometry_sigma_rad;  // false for NaN too
}

Status poseStage(hal::Odometry& odometry, StageLog& log, hal::EventLog& events, const hal::Clock& clock,
                 Stage stage, const hal::FrameInfo& frame, hal::PoseEstimate& pose) noexcept {
    const std::uint64_t t0 = clock.monotonicNs();
    const Status st = odometry.poseAt(frame.timestamp_ns, pose);
    return recordStage(log, events, clock, stage, st, st.isOk() ? positionSigmaMm(pose) : 0, t0);
}

Status recordStage(StageLog& log, hal::EventLog& events, const hal::Clock& clock, Stage stage,
                   const Status& status, std::int64_t quality, std::uint64_t t0_ns) noexcept {
    const std::uint64_t now = clock.monotonicNs();
    StageRecord r;
    r.stage = stage;
    r.status = status;
    r.quality = quality;
    r.duration_ns = now >= t0_ns ? now - t0_ns : 0U;
    log.add(r);
    hal::Event e;
    e.timestamp_ns = now;
    e.id = static_cast<std::uint16_t>(kEventStageBase + static_cast<std::uint16_t>(stage));
    e.severity = status.isOk() ? hal::Severity::kInfo : hal::Severity::kError;
    e.args[0] = static_cast<std::int64_t>(status.code());
    e.args[1] = status.detail();
    e.args[2] = quality;
    e.args[3] = static_cast<std::int64_t>(r.duration_ns / 1000U);
    events.record(e);
    return status;
}

}  // namespace vtm::app::detail
