// Acceptance tolerances: each evaluated quantity against its permitted value, and the verdict.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace mtcal {

struct PositioningEvaluation;
struct BallbarEvaluation;

// Permitted values of one test's quantities (e.g. ISO 230-2 "A", "E", "M", "R", "B"; ISO 230-4
// "G", "F", "H"; volumetric "VA"), every one in µm.
struct Tolerances {
  std::vector<std::pair<std::string, double>> limits;  // quantity, permitted value (µm)
  bool empty() const { return limits.empty(); }
  // Sets or replaces one limit.
  void set(const std::string& quantity, double limit_um);
};

struct ToleranceCheck {
  std::string quantity;
  double value = 0, limit = 0;  // µm
  bool pass = false;            // value <= limit
};

// Per-quantity checks in the order of the limits; an empty verdict checked nothing.
struct ToleranceVerdict {
  std::vector<ToleranceCheck> checks;
  bool empty() const { return checks.empty(); }
  // Every check passed (false when nothing was checked).
  bool pass() const;
};

// Every quantity of these acceptance tests is a range or a magnitude (ISO 230-2:2014 clause 2,
// ISO 230-4:2005 clause 3, volumetric accuracy after Mohammed 2019), so a quantity passes when
// its value is at most its permitted value, as ISO 230-2's acceptance tables read. values:
// quantity -> value (µm). Throws InputError (located in `where`) for a limit on a quantity the
// test does not give, naming those it gives.
ToleranceVerdict check_tolerances(const std::vector<std::pair<std::string, double>>& values, const Tolerances& t,
                                  const std::string& where = "tolerances");

// Micrometres in one unit of length named as measurement files name it (mm, um, µm, micron, nm,
// m, in, inch); nullopt for a name it does not know. 1 in = 25.4 mm exactly (NIST SP 811 B.8).
std::optional<double> micrometres_per(std::string_view unit);

// The quantities an acceptance test is judged by, in µm, for check_tolerances:
// ISO 230-2 A, E, M, R, B (clause 2) converted from the evaluation's unit (InputError, located at
// the unit, when that unit is not a length micrometres_per knows);
// ISO 230-4 G (G(b) when both directions were run, else the one direction's G), F (the larger
// magnitude of F max and F min) and H (hysteresis, both directions).
std::vector<std::pair<std::string, double>> tolerance_values(const PositioningEvaluation& e);
std::vector<std::pair<std::string, double>> tolerance_values(const BallbarEvaluation& e);

}  // namespace mtcal
