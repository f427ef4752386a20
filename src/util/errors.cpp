#include "mtcal/util/errors.hpp"

#include <cstdio>

namespace mtcal {

std::string printable(std::string_view text, std::size_t max) {
  std::string out;
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    char piece[5] = {ch, '\0'};
    if (c < 0x20 || c >= 0x7f) std::snprintf(piece, sizeof piece, "\\x%02x", c);
    if (out.size() + std::char_traits<char>::length(piece) > max) return out + "\u2026";
    out += piece;
  }
  return out;
}

std::string SourceLocation::describe() const {
  std::string s = file.empty() ? std::string("<input>") : file;
  if (line > 0) s += ":" + std::to_string(line);
  if (!field.empty()) s += ": field '" + printable(field) + "'";
  return s;
}

InputError::InputError(SourceLocation where, const std::string& what_happened)
    : Error(where.describe() + ": " + what_happened), where_(std::move(where)) {}

}  // namespace mtcal
