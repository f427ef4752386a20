// HTML report of an identification (mtcal identify --report): figures, estimates, correlation and singular values.
#pragma once

#include <string>
#include <vector>

#include "mtcal/identification/identification.hpp"
#include "mtcal/report/report.hpp"

namespace mtcal {

// The files and texts the report names (hashed inputs, the workspace as given).
struct IdentificationReportInputs {
  std::vector<std::string> parameter_files;
  std::string measurements;
  std::string truth;      // the imposed machine's file, or ""
  std::string workspace;  // the workspace grid as text, or ""
};
Report identification_report(const Machine& prior, const IdentificationRun& run,
                             const IdentificationReportInputs& inputs, const std::string& command);
// That report with the inputs' SHA-256 known (files kept in the history store) and the test
// metadata shown given (the one above hashes the files and shows the session's), as
// positioning_report (report/evaluation.hpp).
struct IdentificationReportHashes {
  std::vector<std::string> parameter_files;  // as IdentificationReportInputs::parameter_files
  std::string measurements, truth;
};
Report identification_report(const Machine& prior, const IdentificationRun& run,
                             const IdentificationReportInputs& inputs, const IdentificationReportHashes& hashes,
                             const std::string& command, const ReportMetadata& metadata);

}  // namespace mtcal
