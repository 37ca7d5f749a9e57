// Local-entropy image: running column histograms and a tabulated n log2 n (local_entropy.hpp).
#include "vtm/core/config_check.hpp"
#include "vtm/entropy/local_entropy.hpp"

#include <cmath>

#include "vtm/core/math.hpp"

namespace vtm::entropy {
namespace {

bool isPowerOfTwo(std::int32_t v) noexcept { return v > 0 && (v & (v - 1)) == 0; }

std::int32_t log2Of(std::int32_t powerOfTwo) noexcept {
    std::int32_t k = 0;
    for (std::int32_t v = powerOfTwo; v > 1 && k < 31; v >>= 1) {
        ++k;
    }
    return k;
}

std::int32_t clampIndex(std::int32_t i, std::int32_t n) noexcept { return i < 0 ? 0 : (i >= n ? n - 1 : i); }

// First count of column x's histogram.
std::size_t columnOffset(std::int32_t x, std::int32_t bins) noexcept {
    return static_cast<std::size_t>(x) * static_cast<std::size_t>(bins);
}

}  // namespace

Status EntropyConfig::validate() const noexcept {
    if (max_width < 8 || max_width > 8192) {
        return invalidConfig("entropy.max_width: must be 8..8192 px", max_width);
    }
    if (max_height < 8 || max_height > 8192) {
        return invalidConfig("entropy.max_height: must be 8..8192 px", max_height);
    }
    if (window < 3 || window > kMaxWindow || (window % 2) != 1) {
        return invalidConfig("entropy.window: must be odd, 3..31 px", window);
    }
    if (!isPowerOfTwo(bins) || bins < 2 || bins > kMaxBins) {
        return invalidConfig("entropy.bins: must be a power of two, 2..64", bins);
    }
    if (input_bits < 8 || input_bits > 16) {
        return invalidConfig("entropy.input_bits: must be 8..16", input_bits);
    }
    return Status::ok();
}

std::size_t LocalEntropy::workspaceBytes(const EntropyConfig& config) noexcept {
    if (!config.validate().isOk()) {
        return 0U;
    }
    const auto samples = static_cast<std::size_t>(config.window) * static_cast<std::size_t>(config.window);
    return Arena::arrayBytes<std::uint32_t>(samples + 1U)  // n log2 n table
           + Arena::arrayBytes<std::uint16_t>(static_cast<std::size_t>(config.max_width) *
                                              static_cast<std::size_t>(config.bins));  // column histograms
}

Status LocalEntropy::init(const EntropyConfig& config, Arena& arena) noexcept {
    initialized_ = false;
    VTM_RETURN_IF_ERROR(config.validate());
    const std::int32_t samples = config.window * config.window;
    table_ = arena.allocateArray<std::uint32_t>(static_cast<std::size_t>(samples) + 1U);
    columns_ = arena.allocateArray<std::uint16_t>(static_cast<std::size_t>(config.max_width) *
                                                  static_cast<std::size_t>(config.bins));
    if (table_.empty() || columns_.empty()) {
        return Status(StatusCode::kOutOfMemory, "LocalEntropy::init: arena smaller than workspaceBytes(config)",
                      static_cast<std::int64_t>(workspaceBytes(config)));
    }
    // n log2 n in units of 2^-16 bit, rounded; log2 n = ln n / ln 2 with the project's log.
    const double scale = static_cast<double>(1U << static_cast<unsigned>(kTableFractionBits)) / math::log(2.0);
    table_[0] = 0U;
    for (std::int32_t n = 1; n <= samples; ++n) {
        const double v = static_cast<double>(n) * math::log(static_cast<double>(n)) * scale;
        table_[static_cast<std::size_t>(n)] = static_cast<std::uint32_t>(std::floor(v + 0.5));
    }
    config_ = config;
    radius_ = config.window / 2;
    samples_ = samples;
    binsLog2_ = log2Of(config.bins);
    denominator_ = static_cast<std::int64_t>(samples) * binsLog2_ * (std::int64_t{1} << kTableFractionBits);
    initialized_ = true;
    return Status::ok();
}

std::uint32_t LocalEntropy::nLog2n(std::int32_t n) const noexcept {
    return (initialized_ && n >= 0 && n <= samples_) ? table_[static_cast<std::size_t>(n)] : 0U;
}

std::uint8_t LocalEntropy::quantise(std::int64_t sumTable) const noexcept {
    // H * N in table units = T[N] - sum T[c]; out = round(255 H / log2 bins).
    const std::int64_t hn = static_cast<std::int64_t>(table_[static_cast<std::size_t>(samples_)]) - sumTable;
    if (hn <= 0) {
        return 0U;
    }
    const std::int64_t q = (hn * 255 + denominator_ / 2) / denominator_;
    return static_cast<std::uint8_t>(q > 255 ? 255 : q);
}

std::uint8_t LocalEntropy::outputOf(const std::int32_t* counts) const noexcept {
    if (!initialized_ || counts == nullptr) {
        return 0U;
    }
    std::int64_t total = 0;
    std::int64_t sum = 0;
    for (std::int32_t b = 0; b < config_.bins; ++b) {
        if (counts[b] < 0 || counts[b] > samples_) {
            return 0U;
        }
        total += counts[b];
        sum += table_[static_cast<std::size_t>(counts[b])];
    }
    return total == samples_ ? quantise(sum) : 0U;
}

// Column histograms over rows y - r .. y + r (clamped): built whole for row 0, then moved
// down by one sample out and one in per column.
template <typename T>
void LocalEntropy::columnsForRow(const ImageView<const T>& src, std::int32_t y, std::int32_t shift) noexcept {
    const std::int32_t width = src.width();
    const std::int32_t height = src.height();
    const auto bins = static_cast<std::size_t>(config_.bins);
    if (y == 0) {
        for (std::size_t i = 0; i < static_cast<std::size_t>(width) * bins; ++i) {
            columns_[i] = 0U;
        }
        for (std::int32_t dy = -radius_; dy <= radius_; ++dy) {
            const T* row = src.row(clampIndex(dy, height));
            for (std::int32_t x = 0; x < width; ++x) {
                ++columns_[static_cast<std::size_t>(x) * bins + static_cast<std::size_t>(row[x] >> shift)];
            }
        }
        return;
    }
    const T* out = src.row(clampIndex(y - 1 - radius_, height));
    const T* in = src.row(clampIndex(y + radius_, height));
    for (std::int32_t x = 0; x < width; ++x) {
        std::uint16_t* column = &columns_[static_cast<std::size_t>(x) * bins];
        --column[static_cast<std::size_t>(out[x] >> shift)];
        ++column[static_cast<std::size_t>(in[x] >> shift)];
    }
}

// One output row from the column histograms: the window's histogram slides right.
void LocalEntropy::entropyRow(std::uint8_t* out, std::int32_t width) noexcept {
    const std::int32_t bins = config_.bins;
    for (std::int32_t b = 0; b < bins; ++b) {
        window_[b] = 0;
    }
    for (std::int32_t dx = -radius_; dx <= radius_; ++dx) {
        const std::uint16_t* column = &columns_[columnOffset(clampIndex(dx, width), bins)];
        for (std::int32_t b = 0; b < bins; ++b) {
            window_[b] += column[b];
        }
    }
    for (std::int32_t x = 0; x < width; ++x) {
        if (x > 0) {
            const std::int32_t leaving = clampIndex(x - 1 - radius_, width);
            const std::int32_t entering = clampIndex(x + radius_, width);
            const std::uint16_t* a = &columns_[columnOffset(entering, bins)];
            const std::uint16_t* d = &columns_[columnOffset(leaving, bins)];
            for (std::int32_t b = 0; b < bins; ++b) {
                window_[b] += static_cast<std::int32_t>(a[b]) - static_cast<std::int32_t>(d[b]);
            }
        }
        std::int64_t sum = 0;
        for (std::int32_t b = 0; b < bins; ++b) {
            sum += table_[static_cast<std::size_t>(window_[b])];
        }
        out[x] = quantise(sum);
    }
}

template <typename T>
Status LocalEntropy::run(const ImageView<const T>& src, const ImageView<std::uint8_t>& dst,
                         std::int32_t shift) noexcept {
    if (!initialized_) {
        return Status(StatusCode::kNotInitialized, "LocalEntropy::compute: init() has not succeeded");
    }
    if (!src.valid() || !dst.valid()) {
        return Status(StatusCode::kInvalidArgument, "LocalEntropy::compute: empty or malformed image view");
    }
    if (src.width() > config_.max_width || src.height() > config_.max_height) {
        return Status(StatusCode::kSizeMismatch, "LocalEntropy::compute: image larger than max_width x max_height",
                      src.width() > config_.max_width ? src.width() : src.height());
    }
    if (!dst.sameSize(src.width(), src.height())) {
        return Status(StatusCode::kSizeMismatch, "LocalEntropy::compute: output size differs from the image",
                      dst.width());
    }
    const std::uint32_t limit = static_cast<std::uint32_t>(config_.bins) << static_cast<unsigned>(shift);
    for (std::int32_t y = 0; y < src.height(); ++y) {
        const T* row = src.row(y);
        for (std::int32_t x = 0; x < src.width(); ++x) {
            if (static_cast<std::uint32_t>(row[x]) >= limit) {
                return Status(StatusCode::kInvalidArgument,
                              "LocalEntropy::compute: grey level at or above 2^input_bits", row[x]);
            }
        }
    }
    for (std::int32_t y = 0; y < src.height(); ++y) {
        columnsForRow(src, y, shift);
        entropyRow(dst.row(y), src.width());
    }
    return Status::ok();
}

Status LocalEntropy::compute(const ImageView<const std::uint8_t>& src, const ImageView<std::uint8_t>& dst) noexcept {
    return run(src, dst, 8 - binsLog2_);
}

Status LocalEntropy::compute(const ImageView<const std::uint16_t>& src,
                             const ImageView<std::uint8_t>& dst) noexcept {
    return run(src, dst, config_.input_bits - binsLog2_);
}

}  // namespace vtm::entropy
