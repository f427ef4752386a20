// fit-motion's inputs: measurement files ([ERROR=]FILE) read and each fitted to the motion error it measured.
#pragma once

#include <string>
#include <vector>

#include "mtcal/identification/machine_params.hpp"
#include "mtcal/identification/motion_fit.hpp"

namespace mtcal {

// How the files are read and fitted (the options of mtcal fit-motion, docs/fit-motion.md).
struct MotionFileOptions {
  MotionFitOptions fit;           // form, max_degree, coverage (quantity and rotary follow the name)
  std::string format = "auto";    // "auto", "csv", "dat" or "laser"
  std::string unit = "mm";        // a table's values unless its header says
  std::string target_unit;        // a table's targets (empty: the values' unit)
  double wrap = 0;                // > 0: targets this far apart are one position (rotary tests)
};

// Every file's estimated error and its fit, in the order of the files, and the readers' warnings.
struct MotionFileFits {
  std::vector<EstimatedError> errors;
  std::vector<MotionFit> fits;
  std::vector<std::string> warnings;
};

// "EYX=path" -> {"EYX", "path"}; a bare path -> {"", path} (the file names its error).
std::pair<std::string, std::string> split_motion_file_spec(const std::string& spec);

// Reads each [ERROR=]FILE (a Renishaw .rtl/.rta export names its error; an ISO 230-2 .dat or a
// table must be named), merges wrapped targets, fits it (estimate_motion_error) and refuses an
// error estimated twice (check_distinct). Throws InputError naming the file that does not say
// which error it measured.
MotionFileFits fit_motion_files(const std::vector<std::string>& specs, const MotionFileOptions& options);

}  // namespace mtcal
