#include "mtcal/io/model/drawn_parameters_file.hpp"

#include <vector>

#include <fmt/format.h>

#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/io/system/files.hpp"

namespace mtcal {
namespace {

std::vector<ErrorName> every_error(const Machine& m) {
  std::vector<ErrorName> out;
  for (const auto& p : m.parameters())
    if (out.empty() || !(out.back() == p.error)) out.push_back(p.error);
  return out;
}

std::string size_text(const DrawnError& e) {
  return e.rotational ? fmt::format("{:.3f} urad", e.size * 1e6) : fmt::format("{:.3f} um", e.size * 1e3);
}

}  // namespace

std::string every_error_yaml(const Machine& m, const std::string& comment) {
  return parameters_yaml(m, every_error(m), comment);
}

std::string truth_parameters_yaml(const ErrorDraw& draw, const std::string& description) {
  std::string c = description + "\n";
  c += fmt::format("Drawn with seed {}: {} errors; size = the largest |value| over the axis' travel.\n", draw.seed,
                   draw.drawn.size());
  for (const auto& e : draw.drawn)
    c += fmt::format("  {:<5} {:>14}{}\n", e.error.str(), size_text(e), e.table ? "  (table)" : "");
  c += "Every other error of the machine is zero.";
  return parameters_yaml(draw.truth, every_error(draw.truth), c);
}

std::string nominal_parameters_yaml(const ErrorDraw& draw, const std::string& description) {
  return parameters_yaml(draw.nominal, every_error(draw.nominal),
                         description + "\nEvery error zero, in the forms of the drawn truth (seed " +
                             std::to_string(draw.seed) + "): the model a calibration starts from.");
}

void write_truth_parameters(const std::string& path, const ErrorDraw& draw, const std::string& description) {
  write_file_atomically(path, truth_parameters_yaml(draw, description));
}

void write_nominal_parameters(const std::string& path, const ErrorDraw& draw, const std::string& description) {
  write_file_atomically(path, nominal_parameters_yaml(draw, description));
}

}  // namespace mtcal
