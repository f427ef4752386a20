// HTML report of an identification: what was estimated, how well, and what could not be.
#include "mtcal/report/identification.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "mtcal/io/system/files.hpp"

namespace mtcal {

Report identification_report(const Machine& prior, const IdentificationRun& run, const IdentificationReportInputs& in,
                             const std::string& command) {
  IdentificationReportHashes hashes;
  for (const auto& p : in.parameter_files) hashes.parameter_files.push_back(sha256_hex(read_text_file(p, "parameter file")));
  if (!in.measurements.empty()) hashes.measurements = sha256_hex(read_text_file(in.measurements, "measurements"));
  if (!in.truth.empty()) hashes.truth = sha256_hex(read_text_file(in.truth, "imposed machine"));
  return identification_report(prior, run, in, hashes, command, session_metadata());
}

Report identification_report(const Machine& prior, const IdentificationRun& run, const IdentificationReportInputs& in,
                             const IdentificationReportHashes& hashes, const std::string& command,
                             const ReportMetadata& metadata) {
  using json = nlohmann::ordered_json;
  const IdentificationResult& r = run.result;
  const auto& mc = run.monte_carlo;
  const bool truth = !in.truth.empty();
  Report rep("Identification of " + prior.name, command);
  rep.set_metadata(metadata);
  rep.set_machine(prior);
  for (std::size_t i = 0; i < in.parameter_files.size(); ++i)
    rep.add_input("parameter file", in.parameter_files[i], hashes.parameter_files.at(i));
  // Empty: made in memory (Python).
  if (!in.measurements.empty()) rep.add_input("measurements", in.measurements, hashes.measurements);
  if (truth) rep.add_input("imposed machine", in.truth, hashes.truth);
  rep.add_figure("residual RMS", fmt::format("{:.3f} (balls), {:.3f} (facets)", r.rms_ball * 1e3, r.rms_facet * 1e3),
                 "µm");
  rep.add_figure("rank / unknowns", fmt::format("{} / {}", r.identifiability.rank, r.unknowns), "");
  rep.add_figure("condition number", fmt::format("{:.4g}", r.identifiability.condition), "(scaled Jacobian)");
  if (run.va)
    rep.add_figure("VA of the identified model", fmt::format("{:.3f}", *run.va * 1e3), "µm over " + in.workspace);
  if (run.deviation)
    rep.add_figure("e_V against the imposed machine",
                   fmt::format("max {:.4f}, rms {:.4f}", run.deviation->max * 1e3, run.deviation->rms * 1e3), "µm");
  for (const auto& u : r.identifiability.unidentifiable)
    rep.add_warning("Not identifiable from these measurements, excluded: " + u + ".");
  if (!r.converged) rep.add_warning("The solver did not report convergence: " + r.termination);
  rep.add_section("Estimates");
  std::vector<std::vector<std::string>> rows;
  for (std::size_t i = 0; i < r.parameters.size(); ++i) {
    const auto& p = r.parameters[i];
    std::vector<std::string> row{p.name, fmt::format("{:.6g}", p.value), fmt::format("{:.3g}", p.u), p.unit};
    if (mc) row.push_back(fmt::format("{:.3g}", mc->stdev[i]));
    if (truth && i < run.imposed.size()) row.push_back(fmt::format("{:.6g}", run.imposed[i]));
    rows.push_back(row);
  }
  std::vector<std::string> cols{"parameter", "value", "u (covariance)", "unit"};
  if (mc) cols.push_back(fmt::format("u (Monte Carlo, {} runs)", mc->runs));
  if (truth) cols.push_back("imposed");
  rep.add_table("Estimated parameters (standard uncertainties)", cols, rows);
  json z = json::array(), names = json::array();
  for (std::size_t i = 0; i < r.parameters.size(); ++i) {
    names.push_back(r.parameters[i].name);
    json row = json::array();
    for (std::size_t j = 0; j < r.parameters.size(); ++j)
      row.push_back(r.correlation(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)));
    z.push_back(row);
  }
  if (!r.parameters.empty())
    rep.add_plot("Correlation of the estimates", {{"data",
                                                   {{{"type", "heatmap"},
                                                     {"x", names},
                                                     {"y", names},
                                                     {"z", z},
                                                     {"zmin", -1},
                                                     {"zmax", 1},
                                                     {"colorscale", "RdBu"}}}},
                                                  {"layout", {{"yaxis", {{"autorange", "reversed"}}}}}});
  json sv = json::array(), idx = json::array();
  for (std::size_t i = 0; i < r.identifiability.singular_values.size(); ++i)
    idx.push_back(i + 1), sv.push_back(r.identifiability.singular_values[i]);
  rep.add_plot("Singular values of the scaled Jacobian (all unknowns)",
               {{"data", {{{"type", "scatter"}, {"mode", "markers+lines"}, {"x", idx}, {"y", sv}}}},
                {"layout",
                 {{"yaxis", {{"type", "log"}, {"title", {{"text", "singular value"}}}}},
                  {"xaxis", {{"title", {{"text", "index"}}}}}}}});
  rep.add_paragraph(
      fmt::format("Solver: {} after {} iterations; cost {:.6g} → {:.6g}; {} residuals, {} unknowns; σ0 {:.4g}.",
                  r.termination, r.iterations, r.initial_cost, r.final_cost, r.residuals, r.unknowns, r.sigma0));
  return rep;
}

}  // namespace mtcal
