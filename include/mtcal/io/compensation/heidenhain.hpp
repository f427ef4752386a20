// HEIDENHAIN TNC files for a compensation: *.COM axis-error tables and the *.CMA table that assigns them.
#pragma once

#include "mtcal/compensation/heidenhain.hpp"
#include "mtcal/io/compensation/output.hpp"

namespace mtcal {

// Per table "<axis>.COM" in the TNC table syntax: "BEGIN <name> MM", a header line of column names
// (NR, AXISPOS, one per compensated axis) in fixed-width columns, one line per compensation point,
// "[END]"; "config.cma" with one active line (ACTIVE "*") naming each table under its argument
// axis; README.txt with how to load them and what must be checked on the control.
TargetOutput heidenhain_output(const HeidenhainCompensation& c);

}  // namespace mtcal
