// Unit names accepted in files and on the command line, and their factors to mm and rad.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace mtcal {

enum class Dimension { Length, Angle };

struct Unit {
  std::string name;  // canonical spelling, e.g. "um", "urad"
  Dimension dimension;
  double to_internal;  // multiply a value in this unit to get mm (Length) or rad (Angle)
  bool ratio = false;  // a slope such as um/m: an angle for errors, not for joint positions
};

// Looks a unit up by name ("mm", "um", "µm", "nm", "m", "in", "rad", "mrad", "urad", "µrad",
// "deg", "arcsec", and the ratios "um/m", "µm/m", "mm/m" which are angles). nullopt if unknown.
std::optional<Unit> find_unit(std::string_view name);

// Comma-separated list of every accepted unit name of one dimension, for error messages;
// with_ratios false leaves out the slopes (um/m ...), which are no units for positions.
std::string accepted_units(Dimension d, bool with_ratios = true);

}  // namespace mtcal
