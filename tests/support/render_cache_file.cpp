// FileRenderCache (render_cache_file.hpp) and its installation from $VTM_RENDER_CACHE.
#include "render_cache_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include "vtm/core/crc32.hpp"

namespace vtm::test {

namespace {

constexpr char kMagic[8] = {'V', 'T', 'M', 'R', 'C', 'F', '0', '1'};
constexpr std::size_t kBufferBytes = 16384;
constexpr int kMaxViews = 5;

enum class Element { kU8, kU16, kF32 };

// One view's band rows: row y at base + y * stride_bytes, `count` elements.
struct Rows {
    Element element = Element::kU8;
    std::uint8_t* base = nullptr;
    std::size_t stride_bytes = 0U;
    std::int32_t count = 0;
};

template <typename T>
Rows rowsOf(const ImageView<T>& v, Element e) noexcept {
    Rows r;
    r.element = e;
    r.base = reinterpret_cast<std::uint8_t*>(v.data());
    r.stride_bytes = static_cast<std::size_t>(v.stride()) * sizeof(T);
    r.count = v.width();
    return r;
}

// The views renderFrame writes, in file order; returns how many.
int viewsOf(const sim::FrameOutput& out, std::uint32_t mask, Rows* rows) noexcept {
    int n = 0;
    rows[n++] = (mask & sim::kViewImage16) != 0U ? rowsOf(out.image16, Element::kU16) : rowsOf(out.image8, Element::kU8);
    const ImageView<float>* truth[] = {&out.truth.range_m, &out.truth.depth_m, &out.truth.point_site_m,
                                       &out.truth.normal_site};
    const std::uint32_t bits[] = {sim::kViewRange, sim::kViewDepth, sim::kViewPoint, sim::kViewNormal};
    for (int i = 0; i < 4; ++i) {
        if ((mask & bits[i]) != 0U) {
            rows[n++] = rowsOf(*truth[i], Element::kF32);
        }
    }
    return n;
}

// Buffered writer with a running CRC-32.
class Sink {
public:
    explicit Sink(int fd) noexcept : fd_(fd) {}
    void bytes(const std::uint8_t* p, std::size_t n) noexcept {
        for (std::size_t i = 0; i < n; ++i) {  // bound: n
            if (used_ == kBufferBytes) {
                flush();
            }
            buf_[used_++] = p[i];
        }
    }
    void u32(std::uint32_t v) noexcept {
        const std::uint8_t b[4] = {static_cast<std::uint8_t>(v), static_cast<std::uint8_t>(v >> 8U),
                                   static_cast<std::uint8_t>(v >> 16U), static_cast<std::uint8_t>(v >> 24U)};
        bytes(b, 4);
    }
    void u64(std::uint64_t v) noexcept {
        u32(static_cast<std::uint32_t>(v));
        u32(static_cast<std::uint32_t>(v >> 32U));
    }
    // Writes the CRC of everything so far, then the rest of the buffer.
    bool finish() noexcept {
        flush();
        u32(crc32Final(crc_));
        flush();
        return ok_;
    }

private:
    void flush() noexcept {
        crc_ = crc32Update(crc_, buf_, used_);
        std::size_t done = 0U;
        for (int tries = 0; done < used_ && tries < 1000 && ok_; ++tries) {  // bound: 1000 partial writes
            const ssize_t w = ::write(fd_, buf_ + done, used_ - done);
            if (w > 0) {
                done += static_cast<std::size_t>(w);
            } else if (w < 0 && errno != EINTR) {
                ok_ = false;
            }
        }
        ok_ = ok_ && done == used_;
        used_ = 0U;
    }

    int fd_;
    std::uint8_t buf_[kBufferBytes];
    std::size_t used_ = 0U;
    std::uint32_t crc_ = crc32Init();
    bool ok_ = true;
};

// Buffered reader with a running CRC-32 of the bytes taken.
class Source {
public:
    explicit Source(int fd) noexcept : fd_(fd) {}
    bool bytes(std::uint8_t* p, std::size_t n) noexcept {
        for (std::size_t i = 0; i < n; ++i) {  // bound: n
            if (pos_ == len_ && !refill()) {
                return false;
            }
            p[i] = buf_[pos_++];
        }
        return true;
    }
    bool u32(std::uint32_t& v) noexcept {
        std::uint8_t b[4];
        if (!bytes(b, 4)) {
            return false;
        }
        v = static_cast<std::uint32_t>(b[0]) | (static_cast<std::uint32_t>(b[1]) << 8U) |
            (static_cast<std::uint32_t>(b[2]) << 16U) | (static_cast<std::uint32_t>(b[3]) << 24U);
        return true;
    }
    bool u64(std::uint64_t& v) noexcept {
        std::uint32_t lo = 0U, hi = 0U;
        const bool ok = u32(lo) && u32(hi);
        v = static_cast<std::uint64_t>(lo) | (static_cast<std::uint64_t>(hi) << 32U);
        return ok;
    }
    // CRC of the bytes taken so far.
    [[nodiscard]] std::uint32_t crc() noexcept {
        crc_ = crc32Update(crc_, buf_ + crc_from_, pos_ - crc_from_);
        crc_from_ = pos_;
        return crc32Final(crc_);
    }

private:
    bool refill() noexcept {
        crc_ = crc32Update(crc_, buf_ + crc_from_, pos_ - crc_from_);
        pos_ = len_ = crc_from_ = 0U;
        for (int tries = 0; tries < 1000; ++tries) {  // bound: 1000 interrupted reads
            const ssize_t r = ::read(fd_, buf_, kBufferBytes);
            if (r > 0) {
                len_ = static_cast<std::size_t>(r);
                return true;
            }
            if (r == 0 || errno != EINTR) {
                return false;
            }
        }
        return false;
    }

    int fd_;
    std::uint8_t buf_[kBufferBytes];
    std::size_t pos_ = 0U;
    std::size_t len_ = 0U;
    std::size_t crc_from_ = 0U;
    std::uint32_t crc_ = crc32Init();
};

// The header fields after the magic: key, width, height, first row, rows, mask, 0.
struct Header {
    std::uint64_t key = 0U;
    std::uint32_t fields[6] = {};
};

Header headerOf(std::uint64_t key, const sim::FrameRequest& r, const sim::FrameOutput& out) noexcept {
    Header h;
    h.key = key;
    h.fields[0] = r.model.width_px;
    h.fields[1] = r.model.height_px;
    h.fields[2] = static_cast<std::uint32_t>(r.first_row);
    h.fields[3] = static_cast<std::uint32_t>(sim::bandRows(r));
    h.fields[4] = sim::renderedViews(r, out);
    return h;
}

void writeRow(Sink& s, const Rows& v, std::int32_t y) noexcept {
    const std::uint8_t* row = v.base + static_cast<std::size_t>(y) * v.stride_bytes;
    if (v.element == Element::kU8) {
        s.bytes(row, static_cast<std::size_t>(v.count));
        return;
    }
    for (std::int32_t x = 0; x < v.count; ++x) {  // bound: the row's width
        if (v.element == Element::kU16) {
            std::uint16_t e = 0U;
            std::memcpy(&e, row + 2 * x, 2);
            const std::uint8_t b[2] = {static_cast<std::uint8_t>(e), static_cast<std::uint8_t>(e >> 8U)};
            s.bytes(b, 2);
        } else {
            std::uint32_t e = 0U;
            std::memcpy(&e, row + 4 * x, 4);
            s.u32(e);
        }
    }
}

bool readRow(Source& s, const Rows& v, std::int32_t y) noexcept {
    std::uint8_t* row = v.base + static_cast<std::size_t>(y) * v.stride_bytes;
    if (v.element == Element::kU8) {
        return s.bytes(row, static_cast<std::size_t>(v.count));
    }
    for (std::int32_t x = 0; x < v.count; ++x) {  // bound: the row's width
        if (v.element == Element::kU16) {
            std::uint8_t b[2];
            if (!s.bytes(b, 2)) {
                return false;
            }
            const auto e = static_cast<std::uint16_t>(b[0] | (b[1] << 8U));
            std::memcpy(row + 2 * x, &e, 2);
        } else {
            std::uint32_t e = 0U;
            if (!s.u32(e)) {
                return false;
            }
            std::memcpy(row + 4 * x, &e, 4);
        }
    }
    return true;
}

void hexKey(std::uint64_t key, char* out) noexcept {
    const char* digits = "0123456789abcdef";
    for (int i = 0; i < 16; ++i) {  // bound: 16 digits
        out[i] = digits[(key >> (4 * (15 - i))) & 0xFU];
    }
}

// Appends src to dst (capacity bytes with the terminator); false if it does not fit.
bool append(char* dst, int capacity, const char* src) noexcept {
    const std::size_t have = std::strlen(dst);
    const std::size_t add = std::strlen(src);
    if (have + add + 1U > static_cast<std::size_t>(capacity)) {
        return false;
    }
    std::memcpy(dst + have, src, add + 1U);
    return true;
}

}  // namespace

FileRenderCache::FileRenderCache(const char* dir) noexcept {
    if (dir == nullptr || dir[0] == '\0' || std::strlen(dir) >= static_cast<std::size_t>(kMaxDirChars)) {
        return;
    }
    std::memcpy(dir_, dir, std::strlen(dir) + 1U);
    (void)::mkdir(dir_, 0755);  // EEXIST is fine; any other failure shows at the first store
    usable_ = true;
}

bool FileRenderCache::framePath(std::uint64_t key, char* path, int capacity) const noexcept {
    char name[24] = {'/'};
    hexKey(key, name + 1);
    std::memcpy(name + 17, ".frame", 7);
    path[0] = '\0';
    return append(path, capacity, dir_) && append(path, capacity, name);
}

bool FileRenderCache::load(std::uint64_t key, const sim::FrameRequest& request, const sim::FrameOutput& out,
                           sim::RenderStats& stats) noexcept {
    char path[kMaxDirChars + 32];
    const int fd = usable_ && framePath(key, path, sizeof path) ? ::open(path, O_RDONLY | O_CLOEXEC) : -1;
    if (fd < 0) {
        misses_.fetch_add(1U);
        return false;
    }
    Source s(fd);
    const Header want = headerOf(key, request, out);
    std::uint8_t magic[8] = {};
    Header got;
    bool ok = s.bytes(magic, 8) && std::memcmp(magic, kMagic, 8) == 0 && s.u64(got.key) && got.key == want.key;
    for (int i = 0; i < 6 && ok; ++i) {  // bound: 6 fields
        ok = s.u32(got.fields[i]) && got.fields[i] == want.fields[i];
    }
    std::uint64_t counters[5] = {};
    for (int i = 0; i < 5 && ok; ++i) {  // bound: 5 counters
        ok = s.u64(counters[i]);
    }
    Rows views[kMaxViews];
    const int n = viewsOf(out, want.fields[4], views);
    const std::int32_t end = request.first_row + sim::bandRows(request);
    for (int v = 0; v < n && ok; ++v) {  // bound: 5 views
        for (std::int32_t y = request.first_row; y < end && ok; ++y) {  // bound: the band's rows
            ok = readRow(s, views[v], y);
        }
    }
    const std::uint32_t computed = s.crc();
    std::uint32_t stored = 0U;
    ok = ok && s.u32(stored) && stored == computed;
    (void)::close(fd);
    if (!ok) {
        misses_.fetch_add(1U);
        return false;
    }
    stats.hit_pixels = static_cast<std::int64_t>(counters[0]);
    stats.sky_pixels = static_cast<std::int64_t>(counters[1]);
    stats.shadowed_pixels = static_cast<std::int64_t>(counters[2]);
    stats.saturated_pixels = static_cast<std::int64_t>(counters[3]);
    stats.bad_ray_pixels = static_cast<std::int64_t>(counters[4]);
    hits_.fetch_add(1U);
    return true;
}

void FileRenderCache::store(std::uint64_t key, const sim::FrameRequest& request, const sim::FrameOutput& out,
                            const sim::RenderStats& stats) noexcept {
    char path[kMaxDirChars + 32];
    char temp[kMaxDirChars + 80];
    char suffix[48] = ".tmp.";
    hexKey(static_cast<std::uint64_t>(::getpid()), suffix + 5);
    suffix[21] = '.';
    hexKey(temp_counter_.fetch_add(1U), suffix + 22);
    suffix[38] = '\0';
    if (!usable_ || !framePath(key, path, sizeof path)) {
        return;
    }
    temp[0] = '\0';
    if (!append(temp, sizeof temp, path) || !append(temp, sizeof temp, suffix)) {
        return;
    }
    const int fd = ::open(temp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0) {
        return;
    }
    Sink s(fd);
    const Header h = headerOf(key, request, out);
    s.bytes(reinterpret_cast<const std::uint8_t*>(kMagic), 8);
    s.u64(h.key);
    for (const std::uint32_t f : h.fields) {
        s.u32(f);
    }
    const std::int64_t counters[5] = {stats.hit_pixels, stats.sky_pixels, stats.shadowed_pixels,
                                      stats.saturated_pixels, stats.bad_ray_pixels};
    for (const std::int64_t c : counters) {
        s.u64(static_cast<std::uint64_t>(c));
    }
    Rows views[kMaxViews];
    const int n = viewsOf(out, h.fields[4], views);
    const std::int32_t end = request.first_row + sim::bandRows(request);
    for (int v = 0; v < n; ++v) {  // bound: 5 views
        for (std::int32_t y = request.first_row; y < end; ++y) {  // bound: the band's rows
            writeRow(s, views[v], y);
        }
    }
    const bool written = s.finish();
    const bool closed = ::close(fd) == 0;
    if (written && closed && ::rename(temp, path) == 0) {
        stores_.fetch_add(1U);
    } else {
        (void)::unlink(temp);
    }
}

}  // namespace vtm::test
