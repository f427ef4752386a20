// HTML report of the rotary-axis location test: both estimators, centres and their circle, residuals, the triples'
// distributions.
#pragma once

#include <string>

#include "mtcal/model/machine.hpp"
#include "mtcal/probing/rotary_probing.hpp"
#include "mtcal/report/report.hpp"

namespace mtcal {

// Writes the report to path; command: the command line shown; machine: the machine file's model
// when one gave the nominal axis (else null); max_rms: the limit of the contacts' rms distance
// from their sphere (mm), against which large fits are flagged.
void write_rotary_report(const std::string& path, const std::string& command, const Machine* machine,
                         const RotaryAxisResult& result, double max_rms);
// That report, unwritten, as positioning_report (report/evaluation.hpp): the contacts' or centres'
// file result.centres.source of this SHA-256, the test metadata shown given (write_rotary_report:
// the session's). A recorded result's report is made with it from the store (report/recorded.hpp).
Report rotary_report(const std::string& command, const Machine* machine, const RotaryAxisResult& result,
                     double max_rms, const std::string& input_sha256, const ReportMetadata& metadata);

}  // namespace mtcal
