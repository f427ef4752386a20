// How many significant digits the numbers mtcal writes carry: 10 by default, up to 17.
#pragma once

#include <string>

namespace mtcal {

// Significant digits of written numbers (CSV cells, printed figures that are not rounded for
// reading): 10 unless set. 17 makes every double round-trip bit for bit (IEEE 754 binary64 needs
// at most 17 significant decimal digits, IEEE 754-2008 5.12.2).
int significant_digits();
// 1 to 17; InputError (located in "precision") otherwise. Process-wide: set once, before writing.
void set_significant_digits(int digits);

// v with significant_digits() digits, shortest form ("%g"); at least min_digits digits.
std::string format_number(double v, int min_digits = 0);

}  // namespace mtcal
