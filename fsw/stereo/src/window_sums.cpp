// Column sums, window sums and the best disparity, a word of packed 16-bit sums at a time.
//
// Why packed words give the lane-by-lane results: word arithmetic is modulo 2^(16 L)
// (L lanes), and a word is sum_i lane_i 2^(16 i). So a chain of word adds and subtracts
// yields exactly the packed lane results whenever every lane's final result lies in
// 0..65535, whatever the order of the operations (the compiler may reassociate, and
// intermediate lanes may wrap). Every final lane here is such a sum of costs 0..maxCost:
// - a column sum: the `window` costs of its column and disparity in the ring, at most
//   31 * 255 = 7905 (window <= 31, maxCost <= 255).
// - a window sum: `window` column sums, at most window^2 * maxCost <= 65535, because
//   maxCost = min(255, 65535 / window^2) (plan.cpp).
// - slots past D in a pixel's last word (padding) read real DT bytes (the DT row has
//   kSlotGroup bytes of padding on the right), also 0..maxCost: the same bounds; their
//   sums are never a result (consider() skips them).
#include "window_sums.hpp"

namespace vtm::stereo::detail {
namespace {

constexpr std::int32_t kInfCost = 0x7FFFFFFF;

std::int32_t costWords(const Plan& p) noexcept { return (p.disparities + kWordBytes - 1) / kWordBytes; }

std::size_t at(std::int32_t x, std::int32_t stride) noexcept {
    return static_cast<std::size_t>(x) * static_cast<std::size_t>(stride);
}

// col = (col - old) + new, for the even and the odd cost bytes of one word.
inline void updateColumn(std::uint16_t* col, SumWord oldCosts, SumWord newCosts) noexcept {
    storeWord(col, loadWord(col) - evenBytes(oldCosts) + evenBytes(newCosts));
    storeWord(col + kLanes, loadWord(col + kLanes) - oddBytes(oldCosts) + oddBytes(newCosts));
}

// The least sum and its disparity index (ties: the lowest index) among those taken.
struct Best {
    std::int32_t cost = kInfCost;
    std::int32_t index = 0;
    // Pixel sum position q with value v; padding slots (j < 0) are never taken.
    void take(std::int32_t disparities, std::int32_t q, std::int32_t v) noexcept {
        const std::int32_t j = disparities - 1 - slotOfPosition(q);
        if (j >= 0 && (v < cost || (v == cost && j < index))) {
            cost = v;
            index = j;
        }
    }
};

#if VTM_STEREO_VECTOR_SUMS
// Branch-free per lane: the least sum so far and the position of the word it came from;
// <= keeps the later word on ties, whose slot is the higher one (slots grow with the word
// in every lane): the lower disparity index. Padding lanes come in as 0xFFFF (above every
// real sum, which is at most 65534: window^2 never divides 65535 = 3 5 17 257), so they
// never hide a real one; finish() then picks among the lanes.
class BestTracker {
public:
    explicit BestTracker(std::int32_t disparities) noexcept : disparities_(disparities) {}
    void consider(const std::uint16_t* /*sums*/, std::int32_t q, SumWord w) noexcept {
        const auto less = w <= cost_;
        cost_ = less ? w : cost_;
        word_ = less ? SumWord{} + static_cast<std::uint16_t>(q) : word_;
    }
    [[nodiscard]] Best finish() const noexcept {
        Best b;
        for (std::int32_t i = 0; i < kLanes; ++i) {
            b.take(disparities_, word_[i] + i, cost_[i]);
        }
        return b;
    }

private:
    std::int32_t disparities_;
    SumWord cost_ = ~SumWord{};
    SumWord word_{};
};
#else
// A stored word of the pixel's sums (positions q .. q + kLanes - 1) against the best so
// far; its lanes are read back from `sums` only when one may be at most the best.
class BestTracker {
public:
    explicit BestTracker(std::int32_t disparities) noexcept : disparities_(disparities) {}
    void consider(const std::uint16_t* sums, std::int32_t q, SumWord w) noexcept {
        if (!anyLaneAtMost(w, threshold_)) {
            return;
        }
        for (std::int32_t i = 0; i < kLanes; ++i) {
            best_.take(disparities_, q + i, sums[q + i]);
        }
        threshold_ = atMostThreshold(best_.cost);
    }
    [[nodiscard]] Best finish() const noexcept { return best_; }

private:
    std::int32_t disparities_;
    Best best_{};
    SumWord threshold_ = ~SumWord{0};
};
#endif

// 0xFFFF in the lanes of padding slots of the pixel's last word group (two sum words from
// position `tail`), 0 elsewhere: or-ed into what the tracker sees.
void paddingMasks(const Plan& p, std::int32_t tail, SumWord* masks) noexcept {
    std::uint16_t lanes[2 * kLanes] = {};
    for (std::int32_t i = 0; i < 2 * kLanes; ++i) {
        lanes[i] = slotOfPosition(tail + i) >= p.disparities ? std::uint16_t{0xFFFF} : std::uint16_t{0};
    }
    masks[0] = loadWord(lanes);
    masks[1] = loadWord(lanes + kLanes);
}

}  // namespace

void pushCostRow(const Plan& p, std::int32_t width, const std::uint8_t* dtRow, const std::int32_t* costs,
                 std::uint8_t* ring, std::uint16_t* colSums) noexcept {
    const std::int32_t words = costWords(p);
    for (std::int32_t x = 0; x < width; ++x) {
        std::uint8_t* slot = ring + at(x, p.slotStride);
        std::uint16_t* col = colSums + at(x + p.half, p.slotStride);
        if (costs == nullptr) {
            for (std::int32_t g = 0; g < words; ++g) {
                updateColumn(col + g * kWordBytes, loadWord(slot + g * kWordBytes), SumWord{0});
                storeWord(slot + g * kWordBytes, SumWord{0});
            }
            continue;
        }
        const std::uint8_t* src = dtRow + costs[x];
        for (std::int32_t g = 0; g < words; ++g) {
            const SumWord n = loadWord(src + g * kWordBytes);
            updateColumn(col + g * kWordBytes, loadWord(slot + g * kWordBytes), n);
            storeWord(slot + g * kWordBytes, n);
        }
    }
}

void windowSumsAndBest(const Plan& p, std::int32_t width, const std::uint16_t* colSums, std::uint16_t* winSums,
                       std::int32_t* best, std::int16_t* bestIndex) noexcept {
    const std::int32_t positions = 2 * costWords(p) * kLanes;
    const std::int32_t tail = p.disparities % kWordBytes == 0 ? positions : positions - 2 * kLanes;
    SumWord pad[2] = {};
    paddingMasks(p, tail, pad);
    const std::int32_t span = 2 * p.half;
    const auto stride = static_cast<std::ptrdiff_t>(p.slotStride);
    for (std::int32_t x = 0; x < width; ++x) {
        std::uint16_t* sums = winSums + at(x, p.slotStride);
        BestTracker tracker(p.disparities);
        if (x == 0) {  // the first window, column by column
            for (std::int32_t q = 0; q < positions; q += kLanes) {
                SumWord s{};
                for (std::int32_t i = 0; i <= span; ++i) {
                    s += loadWord(colSums + at(i, p.slotStride) + q);
                }
                storeWord(sums + q, s);
                tracker.consider(sums, q, q < tail ? s : s | pad[(q - tail) / kLanes]);
            }
        } else {  // the previous window, less the column that leaves, plus the one that enters
            const std::uint16_t* prev = sums - stride;
            const std::uint16_t* leaving = colSums + at(x - 1, p.slotStride);
            const std::uint16_t* entering = leaving + (span + 1) * stride;
            for (std::int32_t q = 0; q < tail; q += kLanes) {
                const SumWord s = loadWord(prev + q) - loadWord(leaving + q) + loadWord(entering + q);
                storeWord(sums + q, s);
                tracker.consider(sums, q, s);
            }
            for (std::int32_t q = tail; q < positions; q += kLanes) {
                const SumWord s = loadWord(prev + q) - loadWord(leaving + q) + loadWord(entering + q);
                storeWord(sums + q, s);
                tracker.consider(sums, q, s | pad[(q - tail) / kLanes]);
            }
        }
        const Best b = tracker.finish();
        best[x] = b.cost;
        bestIndex[x] = static_cast<std::int16_t>(b.index);
    }
}

}  // namespace vtm::stereo::detail
