#include "mtcal/util/units.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "mtcal/util/parse.hpp"

namespace mtcal {
namespace {

struct Entry {
  std::string_view name;
  std::string_view canonical;
  Dimension dimension;
  double factor;
};

constexpr std::array<Entry, 19> kUnits{{
    {"mm", "mm", Dimension::Length, 1.0},
    {"um", "um", Dimension::Length, 1e-3},
    {"\xC2\xB5m", "um", Dimension::Length, 1e-3},  // micro sign
    {"\xCE\xBCm", "um", Dimension::Length, 1e-3},  // Greek mu
    {"nm", "nm", Dimension::Length, 1e-6},
    {"m", "m", Dimension::Length, 1e3},
    {"in", "in", Dimension::Length, 25.4},
    {"rad", "rad", Dimension::Angle, 1.0},
    {"mrad", "mrad", Dimension::Angle, 1e-3},
    {"urad", "urad", Dimension::Angle, 1e-6},
    {"\xC2\xB5rad", "urad", Dimension::Angle, 1e-6},
    {"\xCE\xBCrad", "urad", Dimension::Angle, 1e-6},
    {"deg", "deg", Dimension::Angle, kRadPerDeg},
    {"arcsec", "arcsec", Dimension::Angle, kRadPerDeg / 3600.0},
    // A slope in length per length is an angle (small-angle reading of squareness and tilt).
    {"um/m", "um/m", Dimension::Angle, 1e-6},
    {"\xC2\xB5m/m", "um/m", Dimension::Angle, 1e-6},
    {"\xCE\xBCm/m", "um/m", Dimension::Angle, 1e-6},
    {"mm/m", "mm/m", Dimension::Angle, 1e-3},
    {"ppm", "ppm", Dimension::Angle, 1e-6},  // parts per million: um/m
}};

bool is_ratio(std::string_view canonical) {
  return canonical.find('/') != std::string_view::npos || canonical == "ppm";
}

// The power of ten that factor is (1e-3 -> -3: the double nearest to it, as the table and a
// reader of "1e-3" have it), or nullopt (25.4, pi/180).
std::optional<int> power_of_ten(double factor) {
  static const std::array<double, 49> powers = [] {
    std::array<double, 49> p{};
    for (int k = -24; k <= 24; ++k) p[static_cast<std::size_t>(k + 24)] = *parse_number("1e" + std::to_string(k));
    return p;
  }();
  for (int k = -24; k <= 24; ++k)
    if (factor == powers[static_cast<std::size_t>(k + 24)]) return k;
  return std::nullopt;
}

}  // namespace

std::optional<double> convert_number(std::string_view number, double from_factor, double to_factor) {
  const auto v = parse_number(number);
  if (!v) return std::nullopt;
  const auto from = power_of_ten(from_factor), to = power_of_ten(to_factor);
  if (from && to) {
    // "20" urad -> "20e-6" rad: the decimal the user wrote, scaled exactly, then rounded once.
    std::string digits(number);
    long long exponent = 0;
    bool exact = true;
    if (const auto e = digits.find_first_of("eE"); e != std::string::npos) {
      std::string_view ex = std::string_view(digits).substr(e + 1);
      if (!ex.empty() && ex.front() == '+') ex.remove_prefix(1);
      const auto [end, ec] = std::from_chars(ex.data(), ex.data() + ex.size(), exponent);
      exact = ec == std::errc() && end == ex.data() + ex.size() && std::abs(exponent) < (1LL << 40);  // "0e99...9"
      digits.resize(e);
    }
    // Beyond a double's range (parse_number refuses infinity, and a result that rounds to 0
    // from_chars reports out of range) the multiplication below gives the answer.
    if (exact)
      if (const auto out = parse_number(digits + "e" + std::to_string(exponent + *from - *to))) return out;
  }
  const double out = *v * from_factor / to_factor;
  if (!std::isfinite(out)) return std::nullopt;
  return out;
}

std::optional<Unit> find_unit(std::string_view name) {
  for (const auto& e : kUnits)
    if (e.name == name) return Unit{std::string(e.canonical), e.dimension, e.factor, is_ratio(e.canonical)};
  return std::nullopt;
}

std::string accepted_units(Dimension d, bool with_ratios) {
  std::string out;
  for (const auto& e : kUnits) {
    if (e.dimension != d || e.name != e.canonical) continue;
    if (!with_ratios && is_ratio(e.canonical)) continue;
    if (!out.empty()) out += ", ";
    out += e.name;
  }
  return out;
}

TypedValue parse_typed_value(std::string_view text, Dimension d, const SourceLocation& where) {
  const std::string t = trim(text);
  // The longest number prefix whose rest is empty or a unit: "1e-5" is a number, "5m" 5 metres.
  for (std::size_t k = t.size(); k > 0; --k) {
    const auto v = parse_number(std::string_view(t).substr(0, k));
    if (!v) continue;
    const std::string rest = trim(std::string_view(t).substr(k));
    if (rest.empty()) return {*v, std::nullopt, t.substr(0, k)};
    if (const auto u = find_unit(rest)) return {*v, u, t.substr(0, k)};
    throw InputError(where,
                     fmt::format("unknown unit '{}' in '{}' (expected {} unit: {})", printable(rest), printable(t),
                                 d == Dimension::Length ? "a length" : "an angle", accepted_units(d)));
  }
  throw InputError(where, fmt::format("expected a number with an optional unit, found '{}'", printable(t)));
}

double parse_quantity(std::string_view text, Dimension d, double bare_factor, bool slopes,
                      const SourceLocation& where) {
  const TypedValue v = parse_typed_value(text, d, where);
  if (!v.unit) return v.number * bare_factor;
  const char* kind = d == Dimension::Length ? "a length" : "an angle";
  if (v.unit->dimension != d || (v.unit->ratio && !slopes))
    throw InputError(where, fmt::format("'{}' is {}; expected {} unit: {}", v.unit->name,
                                        v.unit->ratio                            ? "a slope"
                                        : v.unit->dimension == Dimension::Length ? "a length"
                                                                                 : "an angle",
                                        kind, accepted_units(d, slopes)));
  const auto out = convert_number(v.text, v.unit->to_internal);
  if (!out) throw InputError(where, fmt::format("'{}' is beyond the range of a number", printable(text)));
  return *out;
}

double parse_in_unit(std::string_view text, std::string_view internal_unit, const SourceLocation& where) {
  if (internal_unit == "mm") return parse_quantity(text, Dimension::Length, 1.0, false, where);
  if (internal_unit == "rad") return parse_quantity(text, Dimension::Angle, 1.0, true, where);
  const std::string t = trim(text);
  const bool slope = internal_unit == "mm/mm" || internal_unit == "rad/rad";
  // Its own unit as suffix: "2e-9 rad/mm^2".
  if (t.size() > internal_unit.size() && t.ends_with(internal_unit)) {
    const auto v = parse_number(trim(std::string_view(t).substr(0, t.size() - internal_unit.size())));
    if (v) return *v;
  }
  if (slope) {
    const TypedValue v = parse_typed_value(t, Dimension::Angle, where);
    if (!v.unit) return v.number;
    if (!v.unit->ratio)
      throw InputError(where, fmt::format("'{}' does not fit a value in {}; expected a bare number or a slope: {}",
                                          v.unit->name, internal_unit, "um/m, ppm, mm/m"));
    const auto out = convert_number(v.text, v.unit->to_internal);
    if (!out) throw InputError(where, fmt::format("'{}' is beyond the range of a number", printable(t)));
    return *out;
  }
  const auto v = parse_number(t);
  if (!v)
    throw InputError(where, fmt::format("expected a number in {} (no other unit fits this coefficient), found '{}'",
                                        internal_unit, printable(t)));
  return *v;
}

std::string implausible_parameter(std::string_view name, std::string_view internal_unit, double value) {
  const double a = std::abs(value);
  if (internal_unit == "rad" && a > 1e-2)
    return fmt::format(
        "{} = {:g} rad ({:g} urad) is far beyond any machine's angular error (at most about "
        "10 mrad); was it meant in urad? Write 20urad, 20um/m or 2e-5",
        name, value, value * 1e6);
  if (internal_unit == "mm" && a > 5.0)
    return fmt::format(
        "{} = {:g} mm is far beyond any machine's error (at most a few mm); was it meant in um? "
        "Write 20um or 0.02",
        name, value);
  if ((internal_unit == "mm/mm" || internal_unit == "rad/rad") && a > 1e-2)
    return fmt::format(
        "{} = {:g} {} ({:g} um/m) is far beyond any machine's scale error; was it meant in um/m? "
        "Write 20um/m, 20ppm or 2e-5",
        name, value, internal_unit, value * 1e6);
  return {};
}

}  // namespace mtcal
