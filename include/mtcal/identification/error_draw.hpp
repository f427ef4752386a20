// A seeded random "truth" for a virtual machine: realistic geometric errors drawn on a nominal machine (issue 33).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "mtcal/model/machine.hpp"

namespace mtcal {

// What to draw and how large. Sizes are magnitudes (the sign is drawn too), uniform in [lo, hi]:
// a length error's largest |value| over its axis' travel in mm, an angle's in rad.
struct ErrorDrawOptions {
  std::uint64_t seed = 1;
  // Errors ("EX0C", "EXX": every coefficient) or parameters ("EXX.1") to draw. Empty: every
  // location error of every axis (ISO 230-1 / ISO 230-7 position and orientation errors) and
  // the tables below. Mounting and motion errors are drawn only when named here or in tables.
  std::vector<std::string> only;
  // Motion errors drawn as tables (e.g. ECC, EXX): a smooth curve sampled at table_points
  // positions evenly over the axis' travel (the machine's own positions if the error already is a
  // table), zero at the axis' zero (its constant part is the location error's), linearly
  // interpolated between positions. Drawn whether or not `only` names them.
  std::vector<std::string> tables;
  std::size_t table_points = 13;
  double length_lo = 5e-3, length_hi = 50e-3;    // mm: 5 .. 50 um
  double angle_lo = 10e-6, angle_hi = 100e-6;    // rad: 10 .. 100 urad
  // Where the names and sizes came from (a file, a command-line option), for messages.
  std::string only_source = "errors to draw", tables_source = "tables to draw", size_source = "draw sizes";
};

// One drawn error: its name, its size (the largest |value| over the travel: mm or rad) and the
// parameters that were given values.
struct DrawnError {
  ErrorName error;
  double size = 0.0;
  bool rotational = false;  // an angle (size in rad) rather than a length (mm)
  bool table = false;       // drawn as a table
  std::vector<std::string> parameters;
};

struct ErrorDraw {
  // The nominal machine (every error zero; the forms kept, drawn tables as tables) with the drawn
  // values: the truth. The machine given is never changed.
  Machine truth;
  // The same machine with every error zero: what a calibration of the truth starts from (the
  // drawn tables' positions included, so that the truth is within the model's reach).
  Machine nominal;
  std::vector<DrawnError> drawn;  // in the order of Machine::parameters()
  std::uint64_t seed = 0;
};

// Draws the errors: the same seed and options give the same values on every platform (the
// generator is std::mt19937_64, whose output the standard fixes, and the uniform and sign draws
// are computed here from its bits). Every parameter of a selected error is drawn: location and
// mounting errors a value, a polynomial motion error's coefficients of degree 1 and up (each
// alone reaching its size at the travel's far end; the constant and the reversal stay zero), a
// Fourier series its terms, a table its curve. Throws InputError (located in the options'
// sources) for an unknown name, a table of an error that is not a motion error or of an axis
// without a travel, fewer than 2 table points, or sizes that are not 0 <= lo <= hi.
ErrorDraw draw_errors(const Machine& nominal, const ErrorDrawOptions& options);

}  // namespace mtcal
