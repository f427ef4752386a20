// Parameter files of estimated errors (io/model/estimated_parameters_file.hpp).
#include "mtcal/io/model/estimated_parameters_file.hpp"

#include <cmath>
#include <sstream>
#include <variant>

#include <fmt/format.h>

#include "mtcal/io/system/files.hpp"

namespace mtcal {
namespace {

std::string list(const std::vector<double>& v) {
  std::string s = "[";
  for (std::size_t i = 0; i < v.size(); ++i) s += fmt::format("{}{:.17g}", i ? ", " : "", v[i]);
  return s + "]";
}

std::string comment_lines(const std::string& text, const std::string& indent) {
  std::string out;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) out += indent + "# " + line + "\n";
  return out;
}

std::string u_text(double u) { return u == u ? fmt::format("{:.3g}", u) : std::string("unknown"); }

}  // namespace

std::string estimated_parameters_yaml(const std::vector<EstimatedError>& errors, const std::string& description) {
  std::string y = comment_lines(description, "");
  y += "mtcal_parameters: 1\n";
  y += "errors:\n";
  for (const auto& e : errors) {
    const std::string name = e.name.str();
    const bool angular =
        e.name.component == Component::A || e.name.component == Component::B || e.name.component == Component::C;
    const char* unit = angular ? "rad" : "mm";
    y += comment_lines(fmt::format("{} from {}: {}", name, e.source, e.method), "  ");
    if (!e.motion) {
      y += fmt::format("  {}: {{value: {:.17g}, unit: {}}}  # +- {} {} (standard uncertainty)\n", name, e.value, unit,
                       u_text(e.uncertainty.empty() ? NAN : e.uncertainty[0]), unit);
      continue;
    }
    const MotionFunction& f = *e.motion;
    std::string u;
    for (std::size_t i = 0; i < f.parameter_count() && i < e.uncertainty.size(); ++i)
      u += fmt::format("{}{}.{} {}", i ? ", " : "", name, f.parameter_suffix(i), u_text(e.uncertainty[i]));
    y += comment_lines("standard uncertainties (internal units): " + u, "  ");
    const char* arg = e.rotary_argument ? "rad" : "mm";
    std::visit(
        [&](const auto& form) {
          using T = std::decay_t<decltype(form)>;
          if constexpr (std::is_same_v<T, Polynomial>) {
            y += fmt::format("  {}: {{unit: {}, argument_unit: {}, polynomial: {}, reversal: {:.17g}}}\n", name, unit,
                             arg, list({form.coefficients.begin(), form.coefficients.end()}), form.reversal);
          } else if constexpr (std::is_same_v<T, Table>) {
            y += fmt::format(
                "  {}:\n    unit: {}\n    argument_unit: {}\n    table:\n      positions: {}\n"
                "      forward: {}\n",
                name, unit, arg, list(form.positions), list(form.forward));
            if (!form.backward.empty()) y += fmt::format("      backward: {}\n", list(form.backward));
          } else {
            y +=
                fmt::format("  {}: {{unit: {}, fourier: {{constant: {:.17g}, cos: {}, sin: {}}}, reversal: {:.17g}}}\n",
                            name, unit, form.constant, list(form.cos_terms), list(form.sin_terms), form.reversal);
          }
        },
        f.form());
  }
  return y;
}

void write_estimated_parameters(const std::string& path, const std::vector<EstimatedError>& errors,
                                const std::string& description) {
  write_file_atomically(path, estimated_parameters_yaml(errors, description));
}

}  // namespace mtcal
