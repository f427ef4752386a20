#include "mtcal/util/errors.hpp"

#include <cmath>
#include <cstdio>

#include <fmt/format.h>

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
  std::string s = file.empty() ? std::string("<input>") : printable(file, 160);
  if (line > 0) s += ":" + std::to_string(line);
  if (!field.empty()) s += ": field '" + printable(field) + "'";
  return s;
}

InputError::InputError(SourceLocation where, const std::string& what_happened)
    : Error(where.describe() + ": " + what_happened), where_(std::move(where)) {}

std::string format_bytes(double bytes) {
  static const char* const units[] = {"bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  int u = 0;
  while (bytes >= 1024 && u < 6) bytes /= 1024, ++u;
  return u == 0 ? fmt::format("{:.0f} bytes", bytes) : fmt::format("{:.3g} {}", bytes, units[u]);
}

std::string format_seconds(double s) {
  if (!std::isfinite(s)) return "forever";
  if (s < 120) return fmt::format("{:.2g} s", s);
  if (s < 7200) return fmt::format("{:.3g} min", s / 60);
  if (s < 2 * 86400) return fmt::format("{:.3g} h", s / 3600);
  if (s < 2 * 365.25 * 86400) return fmt::format("{:.3g} days", s / 86400);
  return fmt::format("{:.3g} years", s / (365.25 * 86400));
}

}  // namespace mtcal
