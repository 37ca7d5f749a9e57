// Whole-file reads and writes with error messages that name the file and the
// operating system's reason (errno).
#pragma once

#include <string>
#include <vector>

#include "vtm/ground/image.hpp"

namespace vtm::ground::detail {

using Bytes = std::vector<unsigned char>;

Result<Bytes> readFileBytes(const std::string& path);
Outcome writeFileBytes(const std::string& path, const Bytes& bytes);

}  // namespace vtm::ground::detail
