// JSON of the identification results (simulate, identify, identifiability): keys in docs/identification.md.
#pragma once

#include <string>

#include "mtcal/identification/identification.hpp"
#include "mtcal/identification/machine_params.hpp"
#include "mtcal/io/json/json.hpp"

namespace mtcal {

// rank unknowns condition condition_identifiable singular_values identifiable unidentifiable
// null_directions columns.
Json to_json(const Identifiability& id);

// The artefact's estimated or simulated state by feature id: {"balls": {id: [x, y, z]}, "facets": {id: offset}}.
Json artefact_json(const std::vector<ProbeFeature>& features, const ArtefactState& state);

// simulate: records residuals noise_um artefact_error_um seed truth{balls facets} [out]. The
// noise and artefact error as the caller gave them (um); out: the measurement file written, or "".
Json to_json(const Simulation& sim, double noise_um, double artefact_error_um, std::uint64_t seed,
             const std::string& out = "");

// identify: termination converged iterations seconds residuals unknowns rank condition
// singular_values rms_um sigma0 fit{poor sigma0 bound probability degrees_of_freedom} initial_cost final_cost parameters correlation unidentifiable
// null_directions artefact [pretravel] [monte_carlo] [va] [e_v] [out] [report].
Json to_json(const IdentificationRun& run, const std::string& out = "", const std::string& report = "");

// identifiability with a subset size: candidates always choose examined count pruned seconds
// subsets[parameters condition residue].
Json to_json(const SubsetAnalysis& a, const SubsetOptions& options, double seconds);

// Estimated errors (ballbar --to-params) by parameter name: {"NAME": {"value", "u"}}, a
// motion error's non-zero coefficients as "NAME.SUFFIX" (internal units mm, rad).
Json estimated_parameters_json(const std::vector<EstimatedError>& params);

}  // namespace mtcal
