// Probing plan and measurement CSV files (docs/identification.md): the formats of the domain's ProbingPlan.
#pragma once

#include <string>

#include "mtcal/identification/identification.hpp"
#include "mtcal/identification/probing_plan.hpp"
#include "mtcal/model/machine.hpp"

namespace mtcal {

// A plan or measurement CSV (docs/identification.md):
//   indexation,<rotary axis letters>,feature,kind,x,y,z,nx,ny,nz,dirX,dirY,dirZ[,X,Y,Z]
// kind is ball or facet; x y z the feature's nominal position (mm, workpiece frame); n its unit
// normal (facets; empty or 0 for balls); dir<axis> the linear axes' directions of motion at the
// contact (-1, 0, +1; empty = 0); X Y Z the readings (measurement files). A feature's geometry must
// be the same on every row. Rotary values in deg. Throws InputError with file, line and column.
ProbingPlan read_probing_csv(const Machine& m, const std::string& path);
ProbingPlan parse_probing_csv(const Machine& m, const std::string& text, const std::string& source);
// The same columns; readings (X Y Z ...) are written when plan.measured. A non-empty comment
// (one line) comes first as a '#' line, which the reader skips.
std::string probing_csv(const Machine& m, const ProbingPlan& plan, const std::string& comment = "");
// probing_csv written to path through an AtomicFile (complete or not at all).
void write_probing_csv(const std::string& path, const Machine& m, const ProbingPlan& plan,
                       const std::string& comment = "");

// A scale bar as text, "BALL:BALL:LENGTH" (mm): "1:2:304.8" -> {1, 2, 304.8}. where (a file, a
// command-line option) locates its messages and becomes the bar's source; throws InputError.
ScaleBar parse_scale_bar(const std::string& spec, const std::string& where);

}  // namespace mtcal
