// Values typed with units (util/units.hpp) and "did you mean" (util/suggest.hpp): every suffix
// against its definition (1 in = 25.4 mm exactly, NIST SP 811 B.8; 1 deg = pi/180 rad), refused
// suffixes with the accepted ones named, the plausibility warnings, and name suggestions.
#include <gtest/gtest.h>

#include <cstdlib>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "mtcal/util/errors.hpp"
#include "mtcal/util/suggest.hpp"
#include "mtcal/util/units.hpp"
#include "examples.hpp"

namespace mtcal {
namespace {

using mtcal::testing::kDeg;

double length(const std::string& s) { return parse_quantity(s, Dimension::Length, 1.0, false, {"test", 0, ""}); }
double angle(const std::string& s, bool slopes = true) {
  return parse_quantity(s, Dimension::Angle, 1.0, slopes, {"test", 0, ""});
}
std::string units_error_of(auto&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(TypedValue, EveryLengthSuffix) {
  EXPECT_DOUBLE_EQ(length("12.5mm"), 12.5);
  EXPECT_DOUBLE_EQ(length("20um"), 0.020);
  EXPECT_DOUBLE_EQ(length("20\xC2\xB5m"), 0.020);  // micro sign
  EXPECT_DOUBLE_EQ(length("20\xCE\xBCm"), 0.020);  // Greek mu
  EXPECT_DOUBLE_EQ(length("0.4m"), 400.0);
  EXPECT_DOUBLE_EQ(length("2in"), 50.8);
  EXPECT_DOUBLE_EQ(length("7nm"), 7e-6);
  EXPECT_DOUBLE_EQ(length("-3e-3"), -3e-3);  // bare: the caller's unit (mm here)
  EXPECT_DOUBLE_EQ(length("1e3 um"), 1.0);   // the exponent is the number's, blanks before the unit
  EXPECT_DOUBLE_EQ(length(" 5 mm "), 5.0);
}

TEST(TypedValue, EveryAngleSuffix) {
  EXPECT_DOUBLE_EQ(angle("90deg"), 90 * kDeg);
  EXPECT_DOUBLE_EQ(angle("0.5rad"), 0.5);
  EXPECT_DOUBLE_EQ(angle("3mrad"), 3e-3);
  EXPECT_DOUBLE_EQ(angle("20urad"), 20e-6);
  EXPECT_DOUBLE_EQ(angle("20\xC2\xB5rad"), 20e-6);
  EXPECT_DOUBLE_EQ(angle("20um/m"), 20e-6);
  EXPECT_DOUBLE_EQ(angle("20ppm"), 20e-6);
  EXPECT_DOUBLE_EQ(angle("0.02mm/m"), 20e-6);
  EXPECT_DOUBLE_EQ(angle("36arcsec"), 0.01 * kDeg);
  // A bare number in the caller's unit: degrees for joint positions.
  EXPECT_DOUBLE_EQ(parse_quantity("30", Dimension::Angle, kDeg, false, {}), 30 * kDeg);
}

TEST(TypedValue, BadSuffixesNameTheAcceptedUnits) {
  const auto e = units_error_of([] { length("5 furlong"); });
  EXPECT_NE(e.find("test: unknown unit 'furlong' in '5 furlong'"), std::string::npos) << e;
  EXPECT_NE(e.find("mm, um, nm, m, in"), std::string::npos) << e;
  EXPECT_NE(units_error_of([] { length("5deg"); }).find("'deg' is an angle; expected a length unit"), std::string::npos);
  EXPECT_NE(units_error_of([] { angle("5mm"); }).find("'mm' is a length; expected an angle unit"), std::string::npos);
  // A slope is no position.
  EXPECT_NE(units_error_of([] { angle("5um/m", false); }).find("'um/m' is a slope"), std::string::npos);
  EXPECT_NE(units_error_of([] { length("mm"); }).find("expected a number with an optional unit, found 'mm'"),
            std::string::npos);
  EXPECT_NE(units_error_of([] { length(""); }).find("expected a number"), std::string::npos);
  EXPECT_NE(units_error_of([] { length("5 mm mm"); }).find("unknown unit 'mm mm'"), std::string::npos);
  EXPECT_NE(units_error_of([] { length("1e308m"); }).find("beyond the range"), std::string::npos);
  EXPECT_NE(units_error_of([] { length("nan mm"); }).find("expected a number"), std::string::npos);
}

TEST(TypedValue, ParameterUnits) {
  auto in = [](const std::string& s, const std::string& unit) { return parse_in_unit(s, unit, {"--set", 0, "P"}); };
  EXPECT_DOUBLE_EQ(in("20urad", "rad"), 20e-6);
  EXPECT_DOUBLE_EQ(in("20um/m", "rad"), 20e-6);  // squareness as a slope
  EXPECT_DOUBLE_EQ(in("2e-5", "rad"), 2e-5);     // bare: the internal unit
  EXPECT_DOUBLE_EQ(in("3um", "mm"), 3e-3);
  EXPECT_DOUBLE_EQ(in("5ppm", "mm/mm"), 5e-6);  // a scale error
  EXPECT_DOUBLE_EQ(in("5um/m", "mm/mm"), 5e-6);
  EXPECT_DOUBLE_EQ(in("5e-6", "mm/mm"), 5e-6);
  EXPECT_DOUBLE_EQ(in("2e-9 rad/mm^2", "rad/mm^2"), 2e-9);  // its own unit as suffix
  EXPECT_DOUBLE_EQ(in("2e-9", "rad/mm^2"), 2e-9);
  EXPECT_NE(units_error_of([&] { in("3um", "rad"); }).find("--set: field 'P': 'um' is a length"), std::string::npos);
  EXPECT_NE(units_error_of([&] { in("3urad", "mm"); }).find("'urad' is an angle"), std::string::npos);
  EXPECT_NE(units_error_of([&] { in("3mm", "mm/mm"); }).find("does not fit a value in mm/mm"), std::string::npos);
  EXPECT_NE(units_error_of([&] { in("3um", "rad/mm^2"); }).find("expected a number in rad/mm^2"), std::string::npos);
}

// Issue 29, item 3: a decimal unit converts the number as written, rounded once, so the value is
// the double of the same number written in the internal unit, bit for bit (EXPECT_EQ).
TEST(TypedValue, DecimalUnitsReadExactly) {
  auto in = [](const std::string& s, const std::string& unit) { return parse_in_unit(s, unit, {"--set", 0, "P"}); };
  ASSERT_NE(20 * 1e-6, 2e-5);  // the product read before: 1.9999999999999998e-05
  EXPECT_EQ(in("20urad", "rad"), 2e-5);
  EXPECT_EQ(in("20um/m", "rad"), 2e-5);
  EXPECT_EQ(in("20ppm", "mm/mm"), 2e-5);
  EXPECT_EQ(in("0.02mm/m", "rad"), 2e-5);
  EXPECT_EQ(in("3um", "mm"), 0.003);
  EXPECT_EQ(length("7nm"), 7e-6);
  EXPECT_EQ(length("0.4m"), 400.0);
  EXPECT_EQ(length("+1.5e+2um"), 0.15);
  EXPECT_EQ(length("-.5um"), -0.0005);
  EXPECT_EQ(length("5.um"), 0.005);
  EXPECT_EQ(angle("3mrad"), 0.003);
  // Between two decimal units (an option in um given in mm) and back.
  EXPECT_EQ(convert_number("0.02", 1.0, 1e-3), 20.0);
  EXPECT_EQ(convert_number("20", 1e-3, 1.0), 0.02);
  // At the ends of the range: what the shift cannot give is the product (or refused).
  EXPECT_EQ(convert_number("1e-320", 1e-6), 1e-320 * 1e-6);
  EXPECT_FALSE(convert_number("1e308", 1e3).has_value());
  // The other factors are one rounding more: the number read times the factor (docs/conventions.md).
  EXPECT_EQ(length("6in"), 6 * 25.4);
  EXPECT_EQ(angle("90deg"), 90 * kDeg);
  EXPECT_EQ(angle("36arcsec"), 36 * (kDeg / 3600));
}

// The same property over random numbers: every decimal unit gives, for the number as written,
// what the C library's strtod (correctly rounded, independent of the reader's from_chars) gives
// for the number with the unit's exponent added to its own.
TEST(TypedValue, DecimalUnitsMatchStrtodWithTheShiftedExponent) {
  std::mt19937_64 rng(29);
  const std::vector<std::pair<std::string, int>> units{
      {"um", -3}, {"nm", -6}, {"m", 3}, {"mm", 0}};
  const std::vector<std::pair<std::string, int>> angles{{"mrad", -3}, {"urad", -6}, {"um/m", -6}, {"mm/m", -3},
                                                        {"ppm", -6},  {"rad", 0}};
  int checked = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    // 1..19 significant digits, a decimal point somewhere or none, an exponent or none.
    std::string digits = std::to_string(rng() % 9 + 1);
    const int n = static_cast<int>(rng() % 19);
    for (int k = 0; k < n; ++k) digits += static_cast<char>('0' + rng() % 10);
    const std::size_t point = rng() % (digits.size() + 1);
    std::string mantissa = digits;
    if (point < digits.size()) mantissa.insert(point, ".");
    if (rng() % 2) mantissa = "-" + mantissa;
    const int exponent = static_cast<int>(rng() % 41) - 20;
    const bool with_exponent = rng() % 2;
    const std::string number = with_exponent ? mantissa + "e" + std::to_string(exponent) : mantissa;
    const int e0 = with_exponent ? exponent : 0;
    for (const bool is_angle : {false, true})
      for (const auto& [unit, shift] : is_angle ? angles : units) {
        const std::string reference = mantissa + "e" + std::to_string(e0 + shift);
        const double expected = std::strtod(reference.c_str(), nullptr);
        const double got = is_angle ? angle(number + unit) : length(number + unit);
        ASSERT_EQ(got, expected) << number << unit << " against " << reference;
        ++checked;
      }
  }
  EXPECT_EQ(checked, 4000 * 10);
}

TEST(TypedValue, PlausibilityWarnings) {
  EXPECT_NE(implausible_parameter("EC0Y", "rad", 20).find("EC0Y = 20 rad"), std::string::npos);
  EXPECT_NE(implausible_parameter("EC0Y", "rad", 20).find("urad"), std::string::npos);
  EXPECT_NE(implausible_parameter("EX0C", "mm", 1000).find("EX0C = 1000 mm"), std::string::npos);  // 1 m
  EXPECT_NE(implausible_parameter("EXX.1", "mm/mm", 20).find("um/m"), std::string::npos);
  EXPECT_EQ(implausible_parameter("EC0Y", "rad", 2e-5), "");
  EXPECT_EQ(implausible_parameter("EC0Y", "rad", -5e-3), "");  // 5 mm/m: bad, but a machine
  EXPECT_EQ(implausible_parameter("EX0C", "mm", 0.5), "");
  EXPECT_EQ(implausible_parameter("EXX.1", "mm/mm", 50e-6), "");
  EXPECT_EQ(implausible_parameter("EXX.2", "mm/mm^2", 1.0), "");  // no rule for higher orders
}

TEST(Suggest, EditDistance) {
  EXPECT_EQ(edit_distance("ec0y", "EC0Y"), 0u);
  EXPECT_EQ(edit_distance("EC0U", "EC0Y"), 1u);
  EXPECT_EQ(edit_distance("E0CY", "EC0Y"), 1u);  // adjacent transposition
  EXPECT_EQ(edit_distance("EY0C", "EC0Y"), 2u);
  EXPECT_EQ(edit_distance("", "abc"), 3u);
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);  // Levenshtein's classic
}

TEST(Suggest, ClosestName) {
  const std::vector<std::string> names{"EC0Y", "EB0Z", "EA0Z", "EXX", "EXX.1", "--grid", "--points"};
  EXPECT_EQ(closest_name("ec0y", names), "EC0Y");
  EXPECT_EQ(closest_name("EXX.l", names), "EXX.1");
  // Equally many edits: look-alikes, then neighbouring keys decide.
  const std::vector<std::string> close{"EXX.0", "EXX.1", "EC0X", "EC0Y", "EXC", "EX0C"};
  EXPECT_EQ(closest_name("EXX.l", close), "EXX.1");
  EXPECT_EQ(closest_name("EC0U", close), "EC0Y");
  EXPECT_EQ(closest_name("EXOC", close), "EX0C");
  EXPECT_EQ(closest_name("--grdi", names), "--grid");
  EXPECT_EQ(closest_name("EC0Y", names), std::nullopt);  // itself
  EXPECT_EQ(closest_name("QQQQ", names), std::nullopt);  // nothing close
  EXPECT_EQ(did_you_mean("eb0z", names), " (did you mean 'EB0Z'?)");
  EXPECT_EQ(did_you_mean("zzz", names), "");
}

}  // namespace
}  // namespace mtcal
