// Strict parsing of text written by people: numbers (decimal, optional sign and exponent,
// finite) and cells with surrounding blanks.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace mtcal {

// "12", "-0.5", "+3e-6" -> value; nullopt for anything else (spaces, hex, "inf", "nan", trailing
// characters, an empty string).
std::optional<double> parse_number(std::string_view text);

// The text without leading and trailing spaces, tabs and carriage returns.
std::string trim(std::string_view text);

// The text in ASCII lower / upper case (file keywords, unit names, axis letters; not locale-aware).
std::string to_lower(std::string_view text);
std::string to_upper(std::string_view text);

}  // namespace mtcal
