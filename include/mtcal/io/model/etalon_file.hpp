// Reading an Etalon exchange file (vendor variant, as the ISG/Beckhoff TF5280 reads it) as a parameter file.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "mtcal/model/machine.hpp"

namespace mtcal {

// One block of the file: a position error ("C0B", VALUE = v) or a component error ("EXY",
// Gridpoints = { argument value ... }), with the line of its [NAME].
struct EtalonBlock {
  std::string name;
  int line = 0;
  bool table = false;
  double value = 0.0;                   // position error: mm or rad
  std::vector<double> argument, error;  // component error: argument mm or deg, error mm or rad
};

// Parses the format (TF5280 manual, "Etalon Exchange Format"): '//' starts a comment anywhere on
// a line; "[NAME]" starts a block; keys VALUE and Gridpoints (any case) with '='; Gridpoints rows
// of exactly two numbers between '{' and '}', arguments strictly increasing, at least two rows.
// Anything else (text before the first block, an unknown key, a block given twice, a block without
// its key, a non-numeric cell, a row of one or three numbers, a missing '}') is refused with one
// InputError naming the file (source), the line and the block.
std::vector<EtalonBlock> parse_etalon(std::string_view text, const std::string& source);

// Whether text looks like an Etalon file rather than YAML: its first line that is neither blank
// nor a '//' comment starts with '['.
bool looks_like_etalon(std::string_view text);

// Applies the blocks to m, all or nothing: [<d>0<axis>] sets the location error E<d>0<axis>;
// [E<d><axis>] replaces that motion error by a table (one for both directions; arguments of a
// rotary axis in deg). A block that names no ISO 230-1 error of m (e.g. [EXU], [GENERAL]) is
// refused: a parameter file whose blocks were skipped would leave errors silently uncompensated.
void apply_etalon(Machine& m, std::string_view text, const std::string& source);

}  // namespace mtcal
