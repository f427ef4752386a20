// HTML report of a calibration campaign (mtcal campaign --report): probed centres before/after, parameters against the truth, reached poses.
#pragma once

#include <string>
#include <vector>

#include "mtcal/identification/campaign.hpp"
#include "mtcal/report/report.hpp"

namespace mtcal {

// The files the report names and hashes ("" where not given).
struct CampaignReportInputs {
  std::vector<std::string> machine_files;  // the machine file and parameter files
  std::string before, after, identified, truth, poses_before, poses_after;
};
Report campaign_report_page(const Machine& m, const CampaignResult& r, const CampaignReportInputs& inputs,
                            const std::string& command);

}  // namespace mtcal
