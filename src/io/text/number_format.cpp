#include "mtcal/io/text/number_format.hpp"

#include <algorithm>
#include <atomic>

#include <fmt/format.h>

#include "mtcal/util/errors.hpp"

namespace mtcal {
namespace {
std::atomic<int> g_digits{10};
}

int significant_digits() { return g_digits.load(std::memory_order_relaxed); }

void set_significant_digits(int digits) {
  if (digits < 1 || digits > 17)
    throw InputError({"precision", 0, ""},
                     fmt::format("expected 1 to 17 significant digits (17: every double exact), found {}", digits));
  g_digits.store(digits, std::memory_order_relaxed);
}

std::string format_number(double v, int min_digits) {
  return fmt::format("{:.{}g}", v, std::max(significant_digits(), min_digits));
}

}  // namespace mtcal
