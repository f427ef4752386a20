// "Did you mean": the known name closest to a mistyped one (case-insensitive edit distance).
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace mtcal {

// Optimal-string-alignment distance (Levenshtein plus adjacent transpositions) between a and b,
// letters compared without case: "ec0y" and "EC0Y" are 0 apart, "EC0Y" and "EC0U" 1, "EY0C" and
// "EC0Y"... 2.
std::size_t edit_distance(std::string_view a, std::string_view b);

// The candidate closest to typed, if it is close enough to be what was meant: at most one edit
// for names up to 4 characters, two up to 8, three beyond (equal without case counts as 0 edits).
// Among equally close candidates, look-alike letters (O/0, l/I/1) and then neighbouring keys count
// less (EXOC -> EX0C, EXX.l -> EXX.1, EC0U -> EC0Y); then the earlier candidate. nullopt when none is
// close or typed is itself a candidate.
std::optional<std::string> closest_name(std::string_view typed, std::span<const std::string> candidates);

// " (did you mean 'EC0Y'?)" for the closest candidate, or "" when none is close.
std::string did_you_mean(std::string_view typed, std::span<const std::string> candidates);

}  // namespace mtcal
