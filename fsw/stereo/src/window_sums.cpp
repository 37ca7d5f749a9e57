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

#include <cstddef>

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
        takeIndex(disparities - 1 - slotOfPosition(q), v);
    }
    // The kLanes sums of the word at position q (a multiple of kLanes): its lanes hold
    // every other slot from slotOfPosition(q).
    void takeWord(std::int32_t disparities, std::int32_t q, const std::uint16_t* lanes) noexcept {
        const std::int32_t j0 = disparities - 1 - slotOfPosition(q);
        for (std::int32_t i = 0; i < kLanes; ++i) {
            takeIndex(j0 - 2 * i, lanes[i]);
        }
    }
    void takeIndex(std::int32_t j, std::int32_t v) noexcept {
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
    // The least (sum << 16 | j) over the lanes: the least sum, ties to the lowest j
    // (j <= 1023). A lane that saw only padding holds 0xFFFF: never the least.
    [[nodiscard]] Best finish() const noexcept {
        std::uint32_t least = ~0U;
        for (std::int32_t i = 0; i < kLanes; ++i) {
            const std::int32_t j = disparities_ - 1 - slotOfPosition(word_[i] + i);
            const std::uint32_t key = (static_cast<std::uint32_t>(cost_[i]) << 16U) |
                                      (static_cast<std::uint32_t>(j) & 0xFFFFU);
            least = key < least ? key : least;
        }
        return Best{static_cast<std::int32_t>(least >> 16U), static_cast<std::int32_t>(least & 0xFFFFU)};
    }

private:
    std::int32_t disparities_;
    SumWord cost_ = ~SumWord{};
    SumWord word_{};
};
#else
// A stored word of the pixel's sums (positions q .. q + kLanes - 1) against the best so
// far; its lanes are read back from `sums` only when one may be at most the best (marked
// unlikely, so that the hot loop carries no per-lane disparity indices).
class BestTracker {
public:
    explicit BestTracker(std::int32_t disparities) noexcept : disparities_(disparities) {}
    void consider(const std::uint16_t* sums, std::int32_t q, SumWord w) noexcept {
        if (__builtin_expect(static_cast<long>(anyLaneAtMost(w, threshold_)), 0L) == 0L) {
            return;
        }
        best_.takeWord(disparities_, q, sums + q);
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

// The buffers and constants of one row's pass.
struct RowPass {
    const Plan& p;
    std::int32_t words;     // cost words per pixel
    std::int32_t tail;      // first sum position of the last word group when it has padding, else all
    SumWord pad[2];         // paddingMasks() of that group
    std::uint8_t* ring;     // this row's ring slot
    std::uint16_t* colSums;
    const SearchRow* out;   // nullptr: push only
};

std::uint16_t* colOf(const RowPass& r, std::int32_t paddedColumn) noexcept {
    return r.colSums + at(paddedColumn, r.p.slotStride);
}

// Pushes image column x: ring slot and column sums (costs: its D costs, nullptr: zero).
void pushColumn(const RowPass& r, std::int32_t x, const std::uint8_t* costs) noexcept {
    std::uint8_t* slot = r.ring + at(x, r.p.slotStride);
    std::uint16_t* col = colOf(r, x + r.p.half);
    for (std::int32_t g = 0; g < r.words; ++g) {
        const auto o = static_cast<std::ptrdiff_t>(g) * kWordBytes;
        const SumWord n = costs != nullptr ? loadWord(costs + o) : SumWord{};
        updateColumn(col + o, loadWord(slot + o), n);
        storeWord(slot + o, n);
    }
}

void finishPixel(const RowPass& r, std::int32_t e, const BestTracker& tracker) noexcept {
    const Best b = tracker.finish();
    r.out->best[e] = b.cost;
    r.out->bestIndex[e] = static_cast<std::int16_t>(b.index);
}

// Pixel 0's window sums, column by column (its columns are pushed).
void firstWindow(const RowPass& r) noexcept {
    const std::int32_t positions = 2 * r.words * kLanes;
    std::uint16_t* sums = r.out->winSums;
    BestTracker tracker(r.p.disparities);
    for (std::int32_t q = 0; q < positions; q += kLanes) {
        SumWord s{};
        for (std::int32_t i = 0; i <= 2 * r.p.half; ++i) {
            s += loadWord(colOf(r, i) + q);
        }
        storeWord(sums + q, s);
        tracker.consider(sums, q, q < r.tail ? s : s | r.pad[(q - r.tail) / kLanes]);
    }
    finishPixel(r, 0, tracker);
}

// Pixel e >= 1: pixel e - 1's window sums, less the column that leaves, plus the one that
// enters (already pushed: columns right of the image, which are zero).
void slideWindow(const RowPass& r, std::int32_t e) noexcept {
    const std::int32_t positions = 2 * r.words * kLanes;
    std::uint16_t* sums = r.out->winSums + at(e, r.p.slotStride);
    const std::uint16_t* prev = sums - r.p.slotStride;
    const std::uint16_t* leaving = colOf(r, e - 1);
    const std::uint16_t* entering = colOf(r, e + 2 * r.p.half);
    BestTracker tracker(r.p.disparities);
    for (std::int32_t q = 0; q < positions; q += kLanes) {
        const SumWord s = loadWord(prev + q) - loadWord(leaving + q) + loadWord(entering + q);
        storeWord(sums + q, s);
        tracker.consider(sums, q, q < r.tail ? s : s | r.pad[(q - r.tail) / kLanes]);
    }
    finishPixel(r, e, tracker);
}

// One cost word of pushColumnAndSlide: the new column sums go straight into the window
// sums of pixel e (its entering column).
inline void pushAndSlideWord(std::uint8_t* slot, std::uint16_t* col, const std::uint16_t* prev,
                             const std::uint16_t* leaving, std::uint16_t* sums, std::int32_t q, SumWord n,
                             SumWord pad0, SumWord pad1, BestTracker& tracker) noexcept {
    const SumWord o = loadWord(slot);
    storeWord(slot, n);
    const SumWord even = loadWord(col) - evenBytes(o) + evenBytes(n);
    const SumWord odd = loadWord(col + kLanes) - oddBytes(o) + oddBytes(n);
    storeWord(col, even);
    storeWord(col + kLanes, odd);
    const SumWord s0 = loadWord(prev + q) - loadWord(leaving + q) + even;
    const SumWord s1 = loadWord(prev + q + kLanes) - loadWord(leaving + q + kLanes) + odd;
    storeWord(sums + q, s0);
    storeWord(sums + q + kLanes, s1);
    tracker.consider(sums, q, s0 | pad0);
    tracker.consider(sums, q + kLanes, s1 | pad1);
}

// Pushes image column x = e + half and slides pixel e >= 1's window onto it (kZero: a
// row of zero cost, costs unused).
template <bool kZero>
void pushColumnAndSlide(const RowPass& r, std::int32_t x, const std::uint8_t* costs) noexcept {
    const std::int32_t e = x - r.p.half;
    std::uint8_t* slot = r.ring + at(x, r.p.slotStride);
    std::uint16_t* col = colOf(r, x + r.p.half);
    std::uint16_t* sums = r.out->winSums + at(e, r.p.slotStride);
    const std::uint16_t* prev = sums - r.p.slotStride;
    const std::uint16_t* leaving = colOf(r, e - 1);
    BestTracker tracker(r.p.disparities);
    const std::int32_t full = r.tail / kWordBytes;  // words without padding
    for (std::int32_t g = 0; g < full; ++g) {
        const auto o = static_cast<std::ptrdiff_t>(g) * kWordBytes;
        const SumWord n = kZero ? SumWord{} : loadWord(costs + o);
        pushAndSlideWord(slot + o, col + o, prev, leaving, sums, g * kWordBytes, n, SumWord{}, SumWord{}, tracker);
    }
    for (std::int32_t g = full; g < r.words; ++g) {  // the last word, when it has padding
        const auto o = static_cast<std::ptrdiff_t>(g) * kWordBytes;
        const SumWord n = kZero ? SumWord{} : loadWord(costs + o);
        pushAndSlideWord(slot + o, col + o, prev, leaving, sums, g * kWordBytes, n, r.pad[0], r.pad[1], tracker);
    }
    finishPixel(r, e, tracker);
}

}  // namespace

// ring and colSums are written through RowPass.
void pushCostRow(const Plan& p, std::int32_t width, const std::uint8_t* dtRow, const std::int32_t* costs,
                 std::uint8_t* ring,       // NOLINT(readability-non-const-parameter)
                 std::uint16_t* colSums,   // NOLINT(readability-non-const-parameter)
                 const SearchRow* out) noexcept {
    RowPass r{p, costWords(p), 0, {}, ring, colSums, out};
    const std::int32_t positions = 2 * r.words * kLanes;
    r.tail = p.disparities % kWordBytes == 0 ? positions : positions - 2 * kLanes;
    paddingMasks(p, r.tail, r.pad);
    const auto costsOf = [&](std::int32_t x) { return costs != nullptr ? dtRow + costs[x] : nullptr; };
    // Pixel e = x - half is complete once column x is pushed.
    for (std::int32_t x = 0; x < width; ++x) {
        if (out != nullptr && x - p.half >= 1) {
            if (costs != nullptr) {
                pushColumnAndSlide<false>(r, x, dtRow + costs[x]);
            } else {
                pushColumnAndSlide<true>(r, x, nullptr);
            }
            continue;
        }
        pushColumn(r, x, costsOf(x));
        if (out != nullptr && x == p.half) {
            firstWindow(r);
        }
    }
    if (out == nullptr) {
        return;
    }
    if (width <= p.half) {
        firstWindow(r);
    }
    for (std::int32_t e = (width - p.half > 1 ? width - p.half : 1); e < width; ++e) {
        slideWindow(r, e);
    }
}

}  // namespace vtm::stereo::detail
