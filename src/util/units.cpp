#include "mtcal/util/units.hpp"

#include <array>
#include <numbers>

namespace mtcal {
namespace {

struct Entry {
  std::string_view name;
  std::string_view canonical;
  Dimension dimension;
  double factor;
};

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr std::array<Entry, 18> kUnits{{
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
    {"deg", "deg", Dimension::Angle, kDeg},
    {"arcsec", "arcsec", Dimension::Angle, kDeg / 3600.0},
    // A slope in length per length is an angle (small-angle reading of squareness and tilt).
    {"um/m", "um/m", Dimension::Angle, 1e-6},
    {"\xC2\xB5m/m", "um/m", Dimension::Angle, 1e-6},
    {"\xCE\xBCm/m", "um/m", Dimension::Angle, 1e-6},
    {"mm/m", "mm/m", Dimension::Angle, 1e-3},
}};

}  // namespace

std::optional<Unit> find_unit(std::string_view name) {
  for (const auto& e : kUnits)
    if (e.name == name)
      return Unit{std::string(e.canonical), e.dimension, e.factor, e.canonical.find('/') != std::string_view::npos};
  return std::nullopt;
}

std::string accepted_units(Dimension d, bool with_ratios) {
  std::string out;
  for (const auto& e : kUnits) {
    if (e.dimension != d || e.name != e.canonical) continue;
    if (!with_ratios && e.canonical.find('/') != std::string_view::npos) continue;
    if (!out.empty()) out += ", ";
    out += e.name;
  }
  return out;
}

}  // namespace mtcal
