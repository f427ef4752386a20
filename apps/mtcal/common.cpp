#include "common.hpp"
#include "history.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>

#include <fmt/format.h>

#include "mtcal/evaluation/error_stream.hpp"
#include "mtcal/io/text/joints.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/parse.hpp"
#include "mtcal/util/request_error.hpp"
#include "mtcal/util/units.hpp"

namespace mtcal::cli {

namespace {
std::string g_command_line;
}

void set_command_line(int argc, char** argv) {
  g_command_line = "mtcal";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool quote = a.empty() || a.find_first_of(" \t\"'\\$`") != std::string::npos;
    g_command_line += " ";
    if (!quote) {
      g_command_line += a;
      continue;
    }
    g_command_line += "'";
    for (char c : a) g_command_line += c == '\'' ? std::string("'\\''") : std::string(1, c);
    g_command_line += "'";
  }
}

const std::string& command_line() { return g_command_line; }

void check_outputs(const std::vector<std::string>& inputs, const std::vector<std::string>& outputs) {
  note_inputs(inputs);  // the files a recorded result came from (history.hpp)
  namespace fs = std::filesystem;
  auto same = [](const std::string& a, const std::string& b) {
    std::error_code ec;
    if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);
    return fs::weakly_canonical(a, ec) == fs::weakly_canonical(b, ec);
  };
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    if (outputs[i].empty()) continue;
    for (const auto& in : inputs)
      if (!in.empty() && same(outputs[i], in))
        throw InputError({outputs[i], 0, ""},
                         "this output would replace the input '" + printable(in) + "'; choose another path");
    for (std::size_t j = i + 1; j < outputs.size(); ++j)
      if (!outputs[j].empty() && same(outputs[i], outputs[j]))
        throw InputError({outputs[i], 0, ""}, "two outputs are written to this one path");
  }
}

std::vector<std::string> model_inputs(const ModelOptions& o) {
  std::vector<std::string> in{o.machine};
  in.insert(in.end(), o.params.begin(), o.params.end());
  return in;
}

const CLI::Validator kFinite(
    [](std::string& s) -> std::string {
      const auto v = parse_number(s);
      return v ? std::string() : "expected a finite number, found '" + printable(s) + "'";
    },
    "FINITE");

const CLI::Validator kUnitName(
    [](std::string& s) -> std::string {
      const auto u = find_unit(s);
      if (u && !u->ratio) return {};
      return "expected a unit of length (" + accepted_units(Dimension::Length, false) + ") or angle (" +
             accepted_units(Dimension::Angle, false) + "), found '" + printable(s) + "'";
    },
    "UNIT");

void require_finite_numbers(CLI::App& app) {
  CLI::Validator finite = kFinite;
  finite.description("");  // the help shows the types as they were
  for (CLI::Option* opt : app.get_options()) {
    const std::string type = opt->get_type_name();
    if (type.rfind("FLOAT", 0) == 0 && type.find("FINITE") == std::string::npos) opt->check(finite);
  }
  for (CLI::App* sub : app.get_subcommands({})) require_finite_numbers(*sub);
}

void rethrow_for_options(const InputError& e, const std::vector<std::pair<std::string, std::string>>& names) {
  const std::string message = std::string(e.what()).substr(e.where().describe().size() + 2);
  for (const auto& [from, to] : names)
    if (e.where().file == from) {
      SourceLocation where = e.where();
      where.file = to;
      throw InputError(where, message);
    }
  // Located in the data (a program's block), caused by the values of options: those are named.
  if (const auto* r = dynamic_cast<const RequestError*>(&e)) {
    std::string options;
    for (const auto& cause : r->causes())
      for (const auto& [from, to] : names)
        if (cause == from) options += (options.empty() ? "" : ", ") + to;
    if (!options.empty()) throw InputError(e.where(), message + " (" + options + ")");
  }
  throw;
}

std::vector<std::string> split_list(const std::string& s) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start <= s.size()) {
    auto end = s.find(',', start);
    if (end == std::string::npos) end = s.size();
    if (end > start) out.push_back(s.substr(start, end - start));
    start = end + 1;
  }
  return out;
}

void add_model_options(CLI::App* cmd, ModelOptions& o) {
  cmd->add_option("--machine,-m", o.machine, "Machine file (YAML, see docs/machine-file.md)")->required();
  cmd->add_option(
      "--params", o.params,
      "Parameter file(s) whose errors replace the machine's (e.g. from mtcal rotary-axis --out, or an Etalon "
      "exchange file); "
      "repeatable, applied in order before --only and --set");
  cmd->add_option("--set", o.set,
                  "Override a parameter: NAME=VALUE with a unit (EC0Y=20urad, EC0Y=20um/m, EX0C=3um, "
                  "EXX.1=5ppm) or a bare number in the parameter's internal unit that `mtcal errors` lists "
                  "(mm, rad, mm/mm ...: EC0Y=2e-5); repeatable");
  cmd->add_option("--only", o.only,
                  "Keep only these errors or parameters (comma-separated, e.g. EXX,EC0Y); all "
                  "others are set to zero before --set applies");
  cmd->add_option("--tool-length", o.tool_length,
                  "Tool length in mm, or with a unit: 200mm, 8in (overrides the machine file)")
      ->transform(length_in(1.0, "LENGTH"));
}

Machine load(const ModelOptions& o) {
  Machine m = load_machine(o.machine);
  note_machine(m.name);
  note_model_files(o.machine, o.params);
  for (const auto& p : o.params) load_parameters(m, p);
  if (o.tool_length) {
    if (!std::isfinite(*o.tool_length) || *o.tool_length < 0)
      throw InputError({"--tool-length", 0, ""}, fmt::format("expected a length >= 0 in mm, found {}", *o.tool_length));
    m.tool.length = *o.tool_length;
  }
  // --only first, so that --set can give a value to an error that --only did not keep.
  if (!o.only.empty()) {
    const auto names = split_list(o.only);
    if (names.empty()) throw InputError({"--only", 0, ""}, "expected error or parameter names, found none");
    m.keep_only(names);
  }
  for (const auto& s : o.set) {
    auto eq = s.find('=');
    if (eq == std::string::npos || eq == 0)
      throw InputError({"--set", 0, s}, "expected NAME=VALUE, found '" + printable(s) + "'");
    const std::string name = s.substr(0, eq), value = s.substr(eq + 1);
    const auto i = m.parameter_index(name);
    if (!i) m.set_parameter(name, 0.0);  // throws: the message says what a valid name looks like
    const std::string unit = m.parameters()[*i].unit;
    const double v = parse_in_unit(value, unit, {"--set", 0, name});
    if (const auto w = implausible_parameter(name, unit, v); !w.empty()) warn("--set " + s + ": " + w);
    m.set_parameter(*i, v);
  }
  return m;
}

void warn(const std::string& message) { std::cerr << "mtcal: warning: " << message << "\n"; }

namespace {
CLI::Validator quantity_validator(Dimension d, double bare_factor, const char* unit_name) {
  return CLI::Validator(
      [=](std::string& s) -> std::string {
        try {
          // Rewritten as a bare number in the option's unit, which CLI11 then converts: 17
          // digits read back to the same double. A bare number stays as written; a decimal unit
          // of a decimal option's unit ("20um" for an option in mm) converts exactly.
          const double internal = parse_quantity(s, d, bare_factor, false, {});  // checks the unit
          const TypedValue v = parse_typed_value(s, d, {});
          const auto value = v.unit ? convert_number(v.text, v.unit->to_internal, bare_factor) : v.number;
          s = fmt::format("{:.17g}", value.value_or(internal / bare_factor));
          return {};
        } catch (const InputError& e) {
          std::string msg = std::string(e.what()).substr(e.where().describe().size() + 2);
          if (msg.rfind("expected a number", 0) == 0)  // no number at all: say what the option wants
            msg = fmt::format("expected {}: a finite number, optionally with a unit ({}), found '{}'",
                              d == Dimension::Length ? "a length" : "an angle", accepted_units(d, false), s);
          return msg;
        }
      },
      unit_name);
}
}  // namespace

CLI::Validator length_in(double mm_per_unit, const char* unit_name) {
  return quantity_validator(Dimension::Length, mm_per_unit, unit_name);
}
CLI::Validator angle_in(double rad_per_unit, const char* unit_name) {
  return quantity_validator(Dimension::Angle, rad_per_unit, unit_name);
}

}  // namespace mtcal::cli

namespace mtcal::cli {

std::vector<std::vector<double>> checked_grid(const Machine& m, const std::string& spec, bool travel_check,
                                              std::size_t max_count) {
  auto values = parse_grid(m, spec, "--grid");
  check_grid(m, values, "--grid", travel_check, max_count);
  // A grid typed in metres on a machine in mm: the span is a tiny part of the axis' travel.
  for (std::size_t k = 0; k < m.axes.size(); ++k) {
    const Axis& ax = m.axes[k];
    const auto [lo, hi] = std::minmax_element(values[k].begin(), values[k].end());
    if (ax.kind != AxisKind::Linear || !ax.travel || values[k].size() < 2) continue;
    const double span = *hi - *lo, travel = ax.travel->max - ax.travel->min;
    if (std::isfinite(travel) && travel > 10.0 && span < 0.01 * travel)
      warn(
          fmt::format("--grid: axis {} spans {:g} mm, under 1% of its {:g} mm travel; values are mm "
                      "(write -0.4m:0.4m:21 for metres)",
                      ax.letter, span, travel));
  }
  return values;
}

// "X=100,Z=-450" -> program zero in machine axis positions (mm, deg); letters of the machine only.
GcodePosition parse_program_origin(const Machine& m, const std::string& spec) {
  GcodePosition o{};
  if (spec.empty()) return o;
  std::array<bool, 6> seen{};
  for (const auto& item : split_list(spec)) {
    const auto eq = item.find('=');
    if (eq != 1)
      throw InputError({"--origin", 0, item},
                       "expected AXIS=VALUE items separated by commas, found '" + printable(item) + "'");
    const char letter = item[0];
    const auto slot = std::find(std::begin(kGcodeAxes), std::end(kGcodeAxes), letter) - std::begin(kGcodeAxes);
    if (slot == 6 || !m.axis_index(letter))
      throw InputError({"--origin", 0, item}, fmt::format("axis '{}' is not in topology {}", letter, m.topology.chain));
    const auto s = static_cast<std::size_t>(slot);
    if (seen[s]) throw InputError({"--origin", 0, item}, fmt::format("axis '{}' given twice", letter));
    seen[s] = true;
    const auto v = parse_number(item.substr(2));
    if (!v) throw InputError({"--origin", 0, item}, "expected a number, found '" + printable(item.substr(2)) + "'");
    if (std::abs(*v) > kMaxJointValue)
      throw InputError({"--origin", 0, item},
                       fmt::format("expected a joint position within +-{:g}, found {:g}", kMaxJointValue, *v));
    o[s] = *v;
  }
  return o;
}

}  // namespace mtcal::cli
