#include "mtcal/io/gcode/program_input.hpp"

#include <fmt/format.h>

#include "mtcal/io/system/files.hpp"

namespace mtcal {

std::optional<int> work_system_index(std::string_view name) {
  for (int k = 0; k < 9; ++k)
    if (name == work_system_name(k)) return k;
  return std::nullopt;
}

GcodeSetup make_gcode_setup(const GcodeSetupInputs& in) {
  GcodeSetup setup;
  if (!in.parameters.empty()) read_parameter_file(in.parameters, setup, in.parameter_scale);
  if (!in.tool_table.empty()) {
    setup.tools = read_tool_table(in.tool_table, in.tool_scale);
    setup.has_tool_table = true;
  }
  for (const WorkOffsetEntry& w : in.work_offsets) {
    if (w.system < 0 || w.system > 8)
      throw InputError({"work offsets", 0, ""},
                       fmt::format("expected a work coordinate system 0 (G54) to 8 (G59.3), found {}", w.system));
    GcodePosition& p = setup.work_offsets[static_cast<std::size_t>(w.system)];
    for (std::size_t slot = 0; slot < 6; ++slot)
      if (w.values[slot]) p[slot] = *w.values[slot];
  }
  if (in.g28) setup.g28 = *in.g28;
  if (in.g30) setup.g30 = *in.g30;
  return setup;
}

GcodeInterpreter parse_gcode_interpreter(const std::string& name, const std::string& field) {
  if (name == "auto") return GcodeInterpreter::Auto;
  if (name == "mtcal") return GcodeInterpreter::Mtcal;
  if (name == "rs274") return GcodeInterpreter::Rs274;
  throw InputError({field, 0, ""}, fmt::format("expected auto, mtcal or rs274, found '{}'", printable(name)));
}

GcodeInput open_gcode(const std::string& path, const std::string& axes, const GcodeSetupInputs& setup,
                      const GcodeInputOptions& o) {
  GcodeInput in;
  in.options.axes = axes;
  in.options.setup = make_gcode_setup(setup);
  std::string program = read_text_file(path, "G-code program");
  bool use_rs274 = o.interpreter == GcodeInterpreter::Rs274;
  if (o.interpreter == GcodeInterpreter::Auto) {
    if (const auto need = gcode_needs_interpreter(program, path, in.options)) {
      in.why = need->what();
      if (find_rs274(o.rs274.executable).empty()) {
        // The reader's message without its location, which the new error carries.
        std::string what = need->what();
        const std::string at = need->where().describe() + ": ";
        if (what.rfind(at, 0) == 0) what.erase(0, at.size());
        throw InputError(need->where(), fmt::format("{}; LinuxCNC's interpreter '{}' is not installed (Debian package "
                                                    "linuxcnc-uspace)",
                                                    what, o.rs274.executable));
      }
      use_rs274 = true;
    }
  }
  if (!use_rs274) {
    // An interpreter named that the program does not need still names a program that must exist.
    if (o.rs274_named && find_rs274(o.rs274.executable).empty())
      throw InputError({"rs274", 0, ""}, fmt::format("'{}' is not a program that can be run (LinuxCNC's "
                                                     "interpreter, Debian package linuxcnc-uspace)",
                                                     printable(o.rs274.executable)));
    in.text = std::move(program);
    in.interpreter = "mtcal";
    in.moves = std::make_unique<GcodeReader>(in.text, path, in.options);
    return in;
  }
  refuse_lathe_program(program, path);
  Rs274Output out = [&] {
    try {
      return run_rs274(path, in.options.setup, o.rs274);
    } catch (const InputError& e) {
      // LinuxCNC's "Requested tool 1 not found in the tool table": say where the tools come from.
      // The message stays the interpreter's.
      if (std::string(e.what()).find("not found in the tool table") == std::string::npos) throw;
      std::string message = std::string(e.what()).substr(e.where().describe().size() + 2);
      // The line's text goes (its number is in the location): what to do must fit in one line.
      if (const auto at = message.rfind(" (in '"); at != std::string::npos) message.resize(at);
      const std::string hint =
          setup.tool_table.empty()
              ? fmt::format("no tool table was given; LinuxCNC's sim configuration has one: {}", kLinuxcncSimToolTable)
              : "tool table " + printable(setup.tool_table, 160);
      throw GcodeToolMissing(e.where(), message + " (" + hint + ")", message);
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

GcodeProgram read_gcode_program(const std::string& path, const std::string& axes, const GcodeSetupInputs& setup,
                                const GcodeInputOptions& options) {
  GcodeInput in = open_gcode(path, axes, setup, options);
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

}  // namespace mtcal
