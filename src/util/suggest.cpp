#include "mtcal/util/suggest.hpp"

#include <algorithm>
#include <cctype>
#include <vector>

namespace mtcal {

std::size_t edit_distance(std::string_view a, std::string_view b) {
  auto same = [](char x, char y) {
    return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
  };
  // Three rows of the dynamic programme (Damerau 1964's transposition, restricted form).
  const std::size_t n = b.size();
  std::vector<std::size_t> prev2(n + 1), prev(n + 1), cur(n + 1);
  for (std::size_t j = 0; j <= n; ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= n; ++j) {
      const std::size_t cost = same(a[i - 1], b[j - 1]) ? 0 : 1;
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + cost});
      if (i > 1 && j > 1 && same(a[i - 1], b[j - 2]) && same(a[i - 2], b[j - 1]))
        cur[j] = std::min(cur[j], prev2[j - 2] + 1);
    }
    std::swap(prev2, prev);
    std::swap(prev, cur);
  }
  return prev[n];
}

namespace {

char lower(char c) { return static_cast<char>(std::tolower(static_cast<unsigned char>(c))); }

// Letters that look alike in a name typed from a printout: O/0 and l/I/1.
bool look_alike(char x, char y) {
  auto cls = [](char c) { return c == 'o' || c == '0' ? 1 : c == 'l' || c == 'i' || c == '1' ? 2 : 0; };
  return cls(lower(x)) != 0 && cls(lower(x)) == cls(lower(y));
}

// Neighbours on a QWERTY keyboard (same row), the commonest slip of a finger.
bool adjacent_keys(char x, char y) {
  static const char* rows[] = {"1234567890", "qwertyuiop", "asdfghjkl", "zxcvbnm"};
  for (const char* r : rows)
    for (std::size_t i = 0; r[i + 1]; ++i)
      if ((r[i] == lower(x) && r[i + 1] == lower(y)) || (r[i] == lower(y) && r[i + 1] == lower(x))) return true;
  return false;
}

// The same distance in quarter edits, a substitution of look-alikes costing 1 and of
// neighbouring keys 2: it ranks candidates that are equally many edits away.
std::size_t weighted_distance(std::string_view a, std::string_view b) {
  const std::size_t n = b.size();
  std::vector<std::size_t> prev2(n + 1), prev(n + 1), cur(n + 1);
  for (std::size_t j = 0; j <= n; ++j) prev[j] = 4 * j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = 4 * i;
    for (std::size_t j = 1; j <= n; ++j) {
      const char x = a[i - 1], y = b[j - 1];
      const std::size_t cost = lower(x) == lower(y) ? 0 : look_alike(x, y) ? 1 : adjacent_keys(x, y) ? 2 : 4;
      cur[j] = std::min({prev[j] + 4, cur[j - 1] + 4, prev[j - 1] + cost});
      if (i > 1 && j > 1 && lower(x) == lower(b[j - 2]) && lower(a[i - 2]) == lower(y))
        cur[j] = std::min(cur[j], prev2[j - 2] + 4);
    }
    std::swap(prev2, prev);
    std::swap(prev, cur);
  }
  return prev[n];
}

}  // namespace

std::optional<std::string> closest_name(std::string_view typed, std::span<const std::string> candidates) {
  if (typed.empty()) return std::nullopt;
  const std::size_t limit = typed.size() <= 4 ? 1 : typed.size() <= 8 ? 2 : 3;
  std::optional<std::string> best;
  std::pair<std::size_t, std::size_t> best_d{limit + 1, 0};
  for (const auto& c : candidates) {
    if (c == typed) return std::nullopt;
    const std::pair<std::size_t, std::size_t> d{edit_distance(typed, c), weighted_distance(typed, c)};
    if (d.first <= limit && d < best_d) best_d = d, best = c;
  }
  return best;
}

std::string did_you_mean(std::string_view typed, std::span<const std::string> candidates) {
  const auto c = closest_name(typed, candidates);
  return c ? " (did you mean '" + *c + "'?)" : std::string();
}

}  // namespace mtcal
