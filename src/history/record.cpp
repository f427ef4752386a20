// Calibration history records: event kinds and the ISO 8601 check.
#include "mtcal/history/record.hpp"

#include <array>
#include <cctype>

namespace mtcal {

namespace {
constexpr std::array<std::pair<EventKind, std::string_view>, 4> kKinds{
    {{EventKind::CompensationLoaded, "compensation-loaded"},
     {EventKind::Crash, "crash"},
     {EventKind::Repair, "repair"},
     {EventKind::Other, "other"}}};

bool digits(std::string_view s, std::size_t at, std::size_t n) {
  if (at + n > s.size()) return false;
  for (std::size_t i = at; i < at + n; ++i)
    if (!std::isdigit(static_cast<unsigned char>(s[i]))) return false;
  return true;
}

int number(std::string_view s, std::size_t at, std::size_t n) {
  int v = 0;
  for (std::size_t i = at; i < at + n; ++i) v = v * 10 + (s[i] - '0');
  return v;
}
}  // namespace

std::string_view to_string(EventKind k) {
  for (const auto& [kind, name] : kKinds)
    if (kind == k) return name;
  return "other";
}

std::optional<EventKind> parse_event_kind(std::string_view name) {
  for (const auto& [kind, n] : kKinds)
    if (n == name) return kind;
  return std::nullopt;
}

// ISO 8601-1:2019 extended format, the calendar date (5.2.2.1) optionally followed by a time of
// day (5.3.1.2) and a UTC designator or offset (5.3.4).
bool is_iso8601(std::string_view s) {
  if (!digits(s, 0, 4) || s.size() < 10 || s[4] != '-' || !digits(s, 5, 2) || s[7] != '-' || !digits(s, 8, 2))
    return false;
  const int month = number(s, 5, 2), day = number(s, 8, 2), year = number(s, 0, 4);
  static constexpr int kDays[] = {31, 29, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  if (month < 1 || month > 12 || day < 1 || day > kDays[month - 1]) return false;
  const bool leap = (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
  if (month == 2 && day == 29 && !leap) return false;
  if (s.size() == 10) return true;
  if (s[10] != 'T' || !digits(s, 11, 2) || s.size() < 16 || s[13] != ':' || !digits(s, 14, 2)) return false;
  if (number(s, 11, 2) > 23 || number(s, 14, 2) > 59) return false;
  std::size_t i = 16;
  if (i < s.size() && s[i] == ':') {
    if (!digits(s, i + 1, 2) || number(s, i + 1, 2) > 60) return false;  // 60: a leap second
    i += 3;
    if (i < s.size() && (s[i] == '.' || s[i] == ',')) {
      ++i;
      const std::size_t start = i;
      while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) ++i;
      if (i == start) return false;
    }
  }
  if (i == s.size()) return true;
  if (s[i] == 'Z') return i + 1 == s.size();
  if (s[i] != '+' && s[i] != '-') return false;
  return s.size() == i + 6 && digits(s, i + 1, 2) && s[i + 3] == ':' && digits(s, i + 4, 2) &&
         number(s, i + 1, 2) <= 14 && number(s, i + 4, 2) <= 59;
}

}  // namespace mtcal
