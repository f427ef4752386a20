// JSON of a rehearsed calibration campaign: the drawn truth, the reached-pose check, the campaign report (docs/campaign.md).
#pragma once

#include <span>

#include "mtcal/evaluation/pose_check.hpp"
#include "mtcal/identification/campaign.hpp"
#include "mtcal/identification/error_draw.hpp"
#include "mtcal/io/json/json.hpp"

namespace mtcal {

// errors --draw: seed drawn[error size unit table parameters]; size in um (lengths) or urad
// (angles), the largest |value| over the axis' travel.
Json to_json(const ErrorDraw& draw);

// pose-check: poses tool_length max_um max_pose rms_um va_um va_pair max_direction_urad and, with
// per_pose, errors[line dx_um dy_um dz_um norm_um direction_urad] (lines from the poses read).
Json to_json(const PoseCheck& check, std::span<const ReachedPose> poses, bool per_pose);

// campaign: reference facets before{count max_um rms_um rms_coordinate_um max_record} after{...} improvement
// probed[record indexation feature rotary_deg line_before line_after before_um after_um]
// identification{source converged residuals unknowns rank rms_um{ball facet} sigma0 unidentifiable}
// parameters[name unit value u truth deviation ratio] not_estimated[name value] max_ratio beyond_3u
// random_poses{before after} probing_noise_um goals{residual parameters}; absent inputs give null.
Json to_json(const CampaignResult& r, const Machine& m);

}  // namespace mtcal
