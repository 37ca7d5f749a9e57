#include "vtm/core/status.hpp"

namespace vtm {

const char* statusCodeName(StatusCode code) noexcept {
    switch (code) {
        case StatusCode::kOk: return "ok";
        case StatusCode::kInvalidArgument: return "invalid_argument";
        case StatusCode::kInvalidConfig: return "invalid_config";
        case StatusCode::kOutOfMemory: return "out_of_memory";
        case StatusCode::kSizeMismatch: return "size_mismatch";
        case StatusCode::kNoData: return "no_data";
        case StatusCode::kTimeout: return "timeout";
        case StatusCode::kCorruptData: return "corrupt_data";
        case StatusCode::kNotInitialized: return "not_initialized";
        case StatusCode::kDegenerate: return "degenerate";
        case StatusCode::kUnsupported: return "unsupported";
        case StatusCode::kIoError: return "io_error";
        case StatusCode::kOutOfOrder: return "out_of_order";
    }
    return "unknown";
}

}  // namespace vtm
