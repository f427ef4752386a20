// The JSON an identification printed (identify --json), read back: estimates with u, residuals, the artefact's balls.
#pragma once

#include <string>

#include "mtcal/identification/campaign.hpp"

namespace mtcal {

// Reads what `mtcal identify --json` prints (keys in docs/identification.md): parameters{NAME:
// {value u unit}}, converged, residuals, unknowns, rank, rms_um{ball facet}, sigma0,
// unidentifiable, artefact{balls{ID: [x y z]}}. A u of null (rank deficient) reads as NaN.
// Throws InputError naming the file and the key for text that is not such JSON.
IdentifiedSummary read_identification_json(const std::string& path);
IdentifiedSummary parse_identification_json(const std::string& text, const std::string& source);

}  // namespace mtcal
