// Unit names accepted in files and on the command line, and their factors to mm and rad.
#pragma once

#include <numbers>
#include <optional>
#include <string>
#include <string_view>

#include "mtcal/util/errors.hpp"

namespace mtcal {

// Exact factors: one inch in mm (the 1959 international inch), one degree in rad.
inline constexpr double kMmPerInch = 25.4;
inline constexpr double kRadPerDeg = std::numbers::pi / 180.0;

enum class Dimension { Length, Angle };

struct Unit {
  std::string name;  // canonical spelling, e.g. "um", "urad"
  Dimension dimension;
  double to_internal;  // multiply a value in this unit to get mm (Length) or rad (Angle)
  bool ratio = false;  // a slope such as um/m: an angle for errors, not for joint positions
};

// Looks a unit up by name ("mm", "um", "µm", "nm", "m", "in", "rad", "mrad", "urad", "µrad",
// "deg", "arcsec", and the ratios "um/m", "µm/m", "mm/m", "ppm" which are angles or, for a scale
// error, slopes). nullopt if unknown.
std::optional<Unit> find_unit(std::string_view name);

// Comma-separated list of every accepted unit name of one dimension, for error messages;
// with_ratios false leaves out the slopes (um/m ...), which are no units for positions.
std::string accepted_units(Dimension d, bool with_ratios = true);

// A value typed by a person, "20urad", "20 µrad", "0.5mm", "-3e-3": a number (parse_number) and
// an optional unit suffix, blanks allowed between them.
struct TypedValue {
  double number = 0.0;
  std::optional<Unit> unit;  // nullopt: no suffix
  std::string text;          // the number as written ("20", "-1.5e-3"), for convert_number
};
// Throws InputError located at `where` for text that is no number with a known unit after it
// (the message lists the units of `d`).
TypedValue parse_typed_value(std::string_view text, Dimension d, const SourceLocation& where);

// A number as written (parse_number's syntax) in a unit whose factor to mm or rad is from_factor,
// in the unit whose factor is to_factor (1: mm or rad). Where both factors are powers of ten
// (mm, um, nm, m, rad, mrad, urad, um/m, mm/m, ppm) the decimal exponent of the number as written
// is shifted and the result read once, correctly rounded: "20" urad is the double "2e-5" rad is,
// bit for bit. Other factors (in, deg, arcsec) multiply the number read: one more rounding
// (docs/conventions.md, "Units"). nullopt for text that is not a number or a result beyond the
// range of a double.
std::optional<double> convert_number(std::string_view number, double from_factor, double to_factor = 1.0);

// A length or angle typed by a person in internal units (mm, rad): a bare number is in the unit
// whose factor to mm/rad is bare_factor (1 for mm, pi/180 for deg); a suffix must be of dimension
// d, and a slope (um/m, ppm ...) only where slopes is true. InputError located at `where`.
double parse_quantity(std::string_view text, Dimension d, double bare_factor, bool slopes, const SourceLocation& where);

// A parameter value typed by a person, converted to the parameter's internal unit (as
// ErrorParameter::unit names it): "mm" takes lengths, "rad" angles and slopes (20 um/m = 20
// urad), "mm/mm" and "rad/rad" (scale-like first-order coefficients) slopes (um/m, ppm, mm/m);
// any unit takes a bare number in itself or its own name as suffix ("2e-9 rad/mm^2").
double parse_in_unit(std::string_view text, std::string_view internal_unit, const SourceLocation& where);

// A warning for a parameter value no machine has (a squareness of 20 rad, an offset of 1 m):
// |value| above 10 mrad for a rotational error, 5 mm for a translational one, 10000 ppm for a
// slope; "" when plausible. name: the parameter's name for the message.
std::string implausible_parameter(std::string_view name, std::string_view internal_unit, double value);

}  // namespace mtcal
