#include "file_bytes.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

namespace vtm::ground::detail {
namespace {

struct FileCloser {
    void operator()(std::FILE* f) const { (void)std::fclose(f); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

std::string osError(const std::string& path, const char* what) {
    return path + ": " + what + ": " + std::strerror(errno);
}

}  // namespace

Result<Bytes> readFileBytes(const std::string& path) {
    errno = 0;
    File f(std::fopen(path.c_str(), "rb"));
    if (!f) {
        return Result<Bytes>::failure(osError(path, "cannot open"));
    }
    Bytes bytes;
    unsigned char chunk[65536];
    std::size_t n = 0;
    // Chunked reads rather than fseek/ftell: works for pipes and files of any size.
    while ((n = std::fread(chunk, 1, sizeof(chunk), f.get())) > 0) {
        bytes.insert(bytes.end(), chunk, chunk + n);
    }
    if (std::ferror(f.get()) != 0) {
        return Result<Bytes>::failure(osError(path, "read error"));
    }
    return Result<Bytes>::success(std::move(bytes));
}

Outcome writeFileBytes(const std::string& path, const Bytes& bytes) {
    errno = 0;
    File f(std::fopen(path.c_str(), "wb"));
    if (!f) {
        return Outcome::failure(osError(path, "cannot create"));
    }
    if (std::fwrite(bytes.data(), 1, bytes.size(), f.get()) != bytes.size()) {
        return Outcome::failure(osError(path, "write error"));
    }
    // fclose flushes: a full disk shows up here.
    if (std::fclose(f.release()) != 0) {
        return Outcome::failure(osError(path, "write error"));
    }
    return Outcome::success();
}

}  // namespace vtm::ground::detail
