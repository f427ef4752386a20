// SHA-256 (FIPS 180-4) of bytes and of files: input identities in reports and the history store.
#pragma once

#include <string>
#include <string_view>

namespace mtcal {

// Lowercase hex digest of bytes.
std::string sha256_hex(std::string_view bytes);
// Lowercase hex digest of a file's content, read in blocks (InputError when it cannot be read).
std::string sha256_file(const std::string& path);

}  // namespace mtcal
