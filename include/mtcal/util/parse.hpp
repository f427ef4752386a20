// Strict parsing of numbers written by people: decimal, optional sign and exponent, finite.
#pragma once

#include <optional>
#include <string_view>

namespace mtcal {

// "12", "-0.5", "+3e-6" -> value; nullopt for anything else (spaces, hex, "inf", "nan", trailing
// characters, an empty string).
std::optional<double> parse_number(std::string_view text);

}  // namespace mtcal
