// The parameter file of an identification, with its provenance and uncertainties as comments.
#include "mtcal/io/model/identified_parameters_file.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "mtcal/io/system/files.hpp"
#include "mtcal/io/model/machine_file.hpp"

namespace mtcal {

std::string identified_parameters_yaml(const Machine& prior, const IdentificationResult& r,
                                       const std::string& measurements_source) {
  std::string comment =
      fmt::format("Identified by mtcal identify from {} ({} residuals, {} unknowns, rank {}, rms {:.3f} um)",
                  measurements_source, r.residuals, r.unknowns, r.identifiability.rank,
                  std::max(r.rms_ball, r.rms_facet) * 1e3);
  for (const auto& p : r.parameters)
    comment += fmt::format("\n{} = {:.9g} {} +- {:.3g} (standard uncertainty)", p.name, p.value, p.unit, p.u);
  for (const auto& u : r.identifiability.unidentifiable)
    comment += "\nnot identifiable, left at the machine's value: " + u;
  return parameters_yaml(r.machine, identified_errors(prior, r), comment);
}

void write_identified_parameters(const std::string& path, const Machine& prior, const IdentificationResult& result,
                                 const std::string& measurements_source) {
  write_file_atomically(path, identified_parameters_yaml(prior, result, measurements_source));
}

}  // namespace mtcal
