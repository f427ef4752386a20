#include "gcode_input.hpp"
#include "mtcal/util/units.hpp"

#include <algorithm>
#include <iostream>

#include <fmt/format.h>

#include "common.hpp"
#include "mtcal/io/gcode/rs274.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal::cli {
namespace {

double units_scale(const std::string& units, const char* option) {
  if (units == "mm") return 1.0;
  if (units == "in") return kMmPerInch;
  throw InputError({option, 0, ""}, fmt::format("expected mm or in, found '{}'", printable(units)));
}

// A value parsed as --origin is (parse_program_origin), its errors located in `option`.
template <class F>
void relocated(const char* option, F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    if (e.where().file == "--origin")
      throw InputError({option, 0, e.where().field}, std::string(e.what()).substr(e.where().describe().size() + 2));
    throw;
  }
}

}  // namespace

void add_gcode_input_options(CLI::App* app, GcodeInputOptions& o) {
  app->add_option("--interpreter", o.interpreter,
                  "Who reads the program: mtcal (its reader: the ISO dialect, docs/gcode.md), rs274 (LinuxCNC's "
                  "interpreter, package linuxcnc-uspace: parameters, expressions, O-word subroutines), auto (mtcal's "
                  "reader unless the program needs rs274; default)")
      ->check(CLI::IsMember({"auto", "mtcal", "rs274"}));
  app->add_option("--rs274", o.rs274, "LinuxCNC's interpreter to run: a path or a name on PATH (default rs274)");
  app->add_option("--rs274-timeout", o.rs274_timeout, "Seconds before LinuxCNC's interpreter is stopped (default 300)")
      ->check(CLI::Range(0.1, 86400.0));
  app->add_option("--tool-table", o.tool_table,
                  "Tool table in LinuxCNC's format (\"T1 P1 Z50.0 D6 ;comment\"): the lengths G43 H applies");
  app->add_option("--tool-units", o.tool_units, "Units of the tool table's lengths: mm (default) or in")
      ->check(CLI::IsMember({"mm", "in"}));
  app->add_option("--parameters", o.parameters,
                  "LinuxCNC parameter file (.var): work offsets G54-G59.3 (5221...), G28/G30 positions (5161..., "
                  "5181...), the system in effect (5220); read, never written");
  app->add_option("--parameter-units", o.parameter_units, "Units of the parameter file's lengths: mm (default) or in")
      ->check(CLI::IsMember({"mm", "in"}));
  app->add_option("--work-offset", o.work_offsets,
                  "A work offset, \"G55:X=100,Y=50,Z=-200\" (mm, deg; repeatable; over --parameters)");
  app->add_option("--g28", o.g28, "The position G28 returns to, \"X=0,Y=0,Z=0\" (mm, deg; default all 0)");
  app->add_option("--g30", o.g30, "The position G30 returns to (mm, deg; default all 0)");
  for (const char* name : {"--interpreter", "--rs274", "--rs274-timeout", "--tool-table", "--tool-units",
                           "--parameters", "--parameter-units", "--work-offset", "--g28", "--g30"})
    o.options.push_back(app->get_option(name));
}

void check_gcode_input_options(const GcodeInputOptions& o, bool program_given) {
  if (program_given) return;
  for (const CLI::Option* opt : o.options)
    if (opt->count() > 0)
      throw InputError({opt->get_name(), 0, ""}, "acts only on a G-code program: expected --gcode beside it");
}

std::vector<std::string> gcode_input_files(const GcodeInputOptions& o) {
  std::vector<std::string> files;
  if (!o.tool_table.empty()) files.push_back(o.tool_table);
  if (!o.parameters.empty()) files.push_back(o.parameters);
  return files;
}

GcodeSetupInputs gcode_setup_inputs(const Machine& m, const GcodeInputOptions& o) {
  GcodeSetupInputs in;
  in.tool_table = o.tool_table;
  in.tool_scale = units_scale(o.tool_units, "--tool-units");
  in.parameters = o.parameters;
  in.parameter_scale = units_scale(o.parameter_units, "--parameter-units");
  for (const std::string& item : o.work_offsets) {
    const auto colon = item.find(':');
    const auto index = work_system_index(item.substr(0, colon));
    if (colon == std::string::npos || !index)
      throw InputError({"--work-offset", 0, ""},
                       fmt::format("expected SYSTEM:AXIS=VALUE,... with SYSTEM one of G54 G55 G56 G57 G58 G59 G59.1 "
                                   "G59.2 G59.3 (e.g. \"G55:X=100,Y=50\"), found '{}'",
                                   printable(item)));
    WorkOffsetEntry entry;
    entry.system = *index;
    relocated("--work-offset", [&] {
      const GcodePosition given = parse_program_origin(m, item.substr(colon + 1));
      // Axes not named keep the value the parameter file gave.
      for (const auto& part : split_list(item.substr(colon + 1))) {
        const auto slot = std::find(std::begin(kGcodeAxes), std::end(kGcodeAxes), part[0]) - std::begin(kGcodeAxes);
        if (slot < 6) entry.values[static_cast<std::size_t>(slot)] = given[static_cast<std::size_t>(slot)];
      }
    });
    in.work_offsets.push_back(entry);
  }
  if (!o.g28.empty()) relocated("--g28", [&] { in.g28 = parse_program_origin(m, o.g28); });
  if (!o.g30.empty()) relocated("--g30", [&] { in.g30 = parse_program_origin(m, o.g30); });
  return in;
}

mtcal::GcodeInputOptions gcode_input_options(const GcodeInputOptions& o) {
  mtcal::GcodeInputOptions r;
  r.interpreter = parse_gcode_interpreter(o.interpreter, "--interpreter");
  r.rs274.executable = o.rs274;
  r.rs274.timeout = o.rs274_timeout;
  for (const CLI::Option* opt : o.options)
    if (opt->get_name() == "--rs274" && opt->count() > 0) r.rs274_named = true;
  return r;
}

namespace {

std::string machine_axes(const Machine& m) {
  std::string axes;
  for (const auto& ax : m.axes) axes += ax.letter;
  return axes;
}

// The library's errors in the options' words: the interpreter named by --rs274, the tools by --tool-table.
template <class F>
auto in_option_words(const GcodeInputOptions& o, F&& f) {
  try {
    return f();
  } catch (const GcodeToolMissing& e) {
    const std::string hint =
        o.tool_table.empty()
            ? fmt::format("give the tools with --tool-table FILE in LinuxCNC's format, e.g. its sim "
                          "configuration's {}",
                          kLinuxcncSimToolTable)
            : "--tool-table " + printable(o.tool_table, 160);
    throw InputError(e.where(), e.interpreter_message() + " (" + hint + ")");
  } catch (const InputError& e) {
    rethrow_for_options(e, {{"rs274", "--rs274"}});
  }
}

}  // namespace

GcodeInput open_gcode(const std::string& path, const Machine& m, const GcodeInputOptions& o) {
  const GcodeSetupInputs setup = gcode_setup_inputs(m, o);
  const mtcal::GcodeInputOptions options = gcode_input_options(o);
  return in_option_words(o, [&] { return mtcal::open_gcode(path, machine_axes(m), setup, options); });
}

GcodeProgram read_gcode_program(const std::string& path, const Machine& m, const GcodeInputOptions& o) {
  const GcodeSetupInputs setup = gcode_setup_inputs(m, o);
  const mtcal::GcodeInputOptions options = gcode_input_options(o);
  return in_option_words(o, [&] { return mtcal::read_gcode_program(path, machine_axes(m), setup, options); });
}

void print_gcode_warnings(const std::vector<std::string>& warnings, std::size_t total) {
  for (const auto& w : warnings) warn(w);
  if (total > warnings.size())
    warn(fmt::format("{} more warnings about the program not shown", total - warnings.size()));
}

}  // namespace mtcal::cli
