// HTML reports of the volumetric-accuracy evaluations: volumetric (critical pair, error map, contributions,
// distributions, reduced volumes, grouping), contributions, diagonals.
#pragma once

#include <string>
#include <vector>

#include "mtcal/evaluation/diagonals.hpp"
#include "mtcal/evaluation/tolerance.hpp"
#include "mtcal/evaluation/volumetric_study.hpp"
#include "mtcal/report/error_map.hpp"

namespace mtcal {

// box_text: the box as the user wrote it (shown with its VA), or empty. verdict: VA and its
// components against their tolerances, shown as a PASS/FAIL banner (none when empty).
void write_volumetric_report(const std::string& path, const ErrorModel& model, const ErrorMap& map,
                             const VolumetricStudy& study, const std::string& box_text, const ReportSources& sources,
                             const ToleranceVerdict& verdict = {});

void write_contributions_report(const std::string& path, const Machine& m, const ContributionStudy& study,
                                const ReportSources& sources);

// box_text: the box as the user wrote it.
void write_diagonals_report(const std::string& path, const Machine& m, const std::vector<DiagonalProfile>& diagonals,
                            const std::string& box_text, const ReportSources& sources);

}  // namespace mtcal
