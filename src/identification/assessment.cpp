// identify with what the command reports around it: Monte Carlo, VA over a workspace, e_V against an imposed machine.
#include <algorithm>
#include <chrono>

#include "mtcal/evaluation/volumetric.hpp"
#include "mtcal/identification/identification.hpp"
#include "mtcal/kinematics/error_model.hpp"

namespace mtcal {

IdentificationRun identify_and_assess(const Machine& prior, const ProbingPlan& measurements,
                                      const IdentificationOptions& options, const AssessmentOptions& a) {
  using Clock = std::chrono::steady_clock;
  IdentificationRun run;
  run.features = measurements.features;
  run.seed = a.seed;
  run.workspace = !a.workspace.empty();
  const auto t0 = Clock::now();
  run.result = identify(prior, measurements, options);
  run.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  const IdentificationResult& r = run.result;
  if (a.monte_carlo_runs > 0) {
    MonteCarloOptions mo;
    mo.runs = a.monte_carlo_runs;
    mo.seed = a.seed;
    mo.threads = a.threads;
    mo.workspace = a.workspace;
    mo.progress = a.monte_carlo_progress;
    const auto t1 = Clock::now();
    run.monte_carlo = monte_carlo(prior, measurements, options, r, mo);
    run.monte_carlo_seconds = std::chrono::duration<double>(Clock::now() - t1).count();
  }
  if (a.truth) {
    run.deviation = model_deviation(r.machine, *a.truth, a.workspace);
    for (const auto& p : r.parameters) run.imposed.push_back(a.truth->parameter(*a.truth->parameter_index(p.name)));
  }
  if (!a.workspace.empty())
    run.va = volumetric_accuracy(grid_error_map(ErrorModel(r.machine), a.workspace).error).va.value;
  return run;
}

std::vector<ErrorName> identified_errors(const Machine& prior, const IdentificationResult& r) {
  std::vector<ErrorName> errors;
  for (const auto& p : r.parameters) {
    const auto e = prior.parameters()[*prior.parameter_index(p.name)].error;
    if (std::find(errors.begin(), errors.end(), e) == errors.end()) errors.push_back(e);
  }
  return errors;
}

}  // namespace mtcal
