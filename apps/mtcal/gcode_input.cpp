#include "gcode_input.hpp"
#include "mtcal/util/units.hpp"

#include <algorithm>
#include <iostream>

#include <fmt/format.h>

#include "common.hpp"
#include "mtcal/io/system/files.hpp"
#include "mtcal/io/gcode/rs274.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal::cli {
namespace {

// The tool table of LinuxCNC's sim configuration axis_mm.ini (T1-T10 in mm), which the Debian
// package linuxcnc-uspace installs (dpkg -L linuxcnc-uspace).
constexpr const char* kLinuxcncSimToolTable = "/usr/share/doc/linuxcnc/examples/sample-configs/sim/axis/sim_mm.tbl";

double units_scale(const std::string& units, const char* option) {
  if (units == "mm") return 1.0;
  if (units == "in") return kMmPerInch;
  throw InputError({option, 0, ""}, fmt::format("expected mm or in, found '{}'", printable(units)));
}

GcodeSetup setup_of(const Machine& m, const GcodeInputOptions& o) {
  GcodeSetup setup;
  if (!o.parameters.empty())
    read_parameter_file(o.parameters, setup, units_scale(o.parameter_units, "--parameter-units"));
  if (!o.tool_table.empty()) {
    setup.tools = read_tool_table(o.tool_table, units_scale(o.tool_units, "--tool-units"));
    setup.has_tool_table = true;
  }
  auto relocate = [&](const char* option, auto&& f) {
    try {
      f();
    } catch (const InputError& e) {
      if (e.where().file == "--origin") throw InputError({option, 0, e.where().field}, e.what());
      throw;
    }
  };
  for (const std::string& item : o.work_offsets) {
    const auto colon = item.find(':');
    const std::string name = item.substr(0, colon);
    int index = -1;
    for (int k = 0; k < 9; ++k)
      if (name == work_system_name(k)) index = k;
    if (colon == std::string::npos || index < 0)
      throw InputError({"--work-offset", 0, ""},
                       fmt::format("expected SYSTEM:AXIS=VALUE,... with SYSTEM one of G54 G55 G56 G57 G58 G59 G59.1 "
                                   "G59.2 G59.3 (e.g. \"G55:X=100,Y=50\"), found '{}'",
                                   printable(item)));
    relocate("--work-offset", [&] {
      GcodePosition p = setup.work_offsets[static_cast<std::size_t>(index)];
      const GcodePosition given = parse_program_origin(m, item.substr(colon + 1));
      // Axes not named keep the value the parameter file gave.
      for (const auto& part : split_list(item.substr(colon + 1))) {
        const auto slot = std::find(std::begin(kGcodeAxes), std::end(kGcodeAxes), part[0]) - std::begin(kGcodeAxes);
        if (slot < 6) p[static_cast<std::size_t>(slot)] = given[static_cast<std::size_t>(slot)];
      }
      setup.work_offsets[static_cast<std::size_t>(index)] = p;
    });
  }
  if (!o.g28.empty()) relocate("--g28", [&] { setup.g28 = parse_program_origin(m, o.g28); });
  if (!o.g30.empty()) relocate("--g30", [&] { setup.g30 = parse_program_origin(m, o.g30); });
  return setup;
}

Rs274Options rs274_options(const GcodeInputOptions& o) {
  Rs274Options r;
  r.executable = o.rs274;
  r.timeout = o.rs274_timeout;
  return r;
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

GcodeInput open_gcode(const std::string& path, const Machine& m, const GcodeInputOptions& o) {
  GcodeInput in;
  in.options.axes.clear();
  for (const auto& ax : m.axes) in.options.axes += ax.letter;
  in.options.setup = setup_of(m, o);
  std::string program = read_text_file(path, "G-code program");
  bool use_rs274 = o.interpreter == "rs274";
  if (o.interpreter == "auto") {
    if (const auto need = gcode_needs_interpreter(program, path, in.options)) {
      in.why = need->what();
      if (find_rs274(o.rs274).empty()) {
        // The reader's message without its location, which the new error carries.
        std::string what = need->what();
        const std::string at = need->where().describe() + ": ";
        if (what.rfind(at, 0) == 0) what.erase(0, at.size());
        throw InputError(need->where(), fmt::format("{}; LinuxCNC's interpreter '{}' is not installed (Debian package "
                                                    "linuxcnc-uspace)",
                                                    what, o.rs274));
      }
      use_rs274 = true;
    }
  }
  if (!use_rs274) {
    // A --rs274 the program does not need still names a program that must exist (not ignored).
    for (const CLI::Option* opt : o.options)
      if (opt->get_name() == "--rs274" && opt->count() > 0 && find_rs274(o.rs274).empty())
        throw InputError({"--rs274", 0, ""}, fmt::format("'{}' is not a program that can be run (LinuxCNC's "
                                                         "interpreter, Debian package linuxcnc-uspace)",
                                                         printable(o.rs274)));
    in.text = std::move(program);
    in.interpreter = "mtcal";
    in.moves = std::make_unique<GcodeReader>(in.text, path, in.options);
    return in;
  }
  refuse_lathe_program(program, path);
  Rs274Output out = [&] {
    try {
      return run_rs274(path, in.options.setup, rs274_options(o));
    } catch (const InputError& e) {
      // LinuxCNC's "Requested tool 1 not found in the tool table" (its sample programs select
      // tools): say where the tools come from. The message stays the interpreter's.
      if (std::string(e.what()).find("not found in the tool table") == std::string::npos) throw;
      std::string message = std::string(e.what()).substr(e.where().describe().size() + 2);
      // The line's text goes (its number is in the location): what to do must fit in one line.
      if (const auto at = message.rfind(" (in '"); at != std::string::npos) message.resize(at);
      const std::string hint =
          o.tool_table.empty()
              ? fmt::format("give the tools with --tool-table FILE in LinuxCNC's format, e.g. its sim "
                            "configuration's {}",
                            kLinuxcncSimToolTable)
              : "--tool-table " + printable(o.tool_table, 160);
      throw InputError(e.where(), message + " (" + hint + ")");
    }
  }();
  in.text = std::move(out.calls);
  in.interpreter = "rs274";
  if (out.missing_end)
    in.notes.push_back(
        fmt::format("{}: the file ends with no M2, M30 or '%' (LinuxCNC's interpreter says so): the "
                    "moves up to its end are simulated",
                    path));
  in.moves = std::make_unique<CanonReader>(in.text, path, in.options);
  return in;
}

GcodeProgram read_gcode_program(const std::string& path, const Machine& m, const GcodeInputOptions& o) {
  GcodeInput in = open_gcode(path, m, o);
  GcodeProgram p;
  p.source = path;
  p.interpreter = in.interpreter;
  GcodeMove mv;
  while (in.moves->next(mv)) p.moves.push_back(mv);
  p.counts = in.moves->counts();
  p.warnings = in.notes;
  p.warnings.insert(p.warnings.end(), in.moves->warnings().begin(), in.moves->warnings().end());
  p.counts.warnings += in.notes.size();
  return p;
}

void print_gcode_warnings(const std::vector<std::string>& warnings, std::size_t total) {
  for (const auto& w : warnings) warn(w);
  if (total > warnings.size())
    warn(fmt::format("{} more warnings about the program not shown", total - warnings.size()));
}

}  // namespace mtcal::cli
