// mtcal compensate --gcode: the corrected G-code program (docs/compensation-gcode.md).
#include "cmd_gcode_correction.hpp"

#include "acceptance.hpp"

#include <chrono>
#include <iostream>

#include <fmt/format.h>

#include "mtcal/compensation/gcode_correction.hpp"
#include "mtcal/io/system/files.hpp"
#include "mtcal/io/gcode/reader.hpp"
#include "mtcal/io/json/gcode_correction_json.hpp"
#include "mtcal/io/gcode/rewrite.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal::cli {

void add_gcode_correction_options(CLI::App& app, GcodeCorrectionCliOptions& o) {
  app.add_option("--gcode", o.gcode,
                 "G-code program to correct, read as 'mtcal toolpath' reads it (docs/gcode.md): corrected in place "
                 "when each block is one move in program coordinates, else written anew with every move expanded");
  add_gcode_input_options(&app, o.input);
  app.add_option("--out", o.out,
                 "Corrected program: the input with new coordinates and the lines of subdivided moves, everything "
                 "else kept; written completely or not at all");
  app.add_option("--max-deviation", o.max_deviation,
                 "Largest distance (mm) of the corrected tool path from the programmed one inside a move; moves are "
                 "cut into pieces until it holds (default 0.001)")
      ->check(kFinite);
  app.add_flag("--linearise-arcs", o.linearise_arcs,
               "Write arcs as straight pieces; by default they stay arcs, cut where the correction varies along them");
  app.add_option("--origin", o.origin,
                 "Program zero in machine axis positions, like G54: \"X=..,Y=..,Z=..\" (mm, deg; default all 0), as "
                 "for 'mtcal toolpath'");
  app.add_option("--decimals", o.decimals, "Digits after the decimal point of written mm and deg (inch: one more)")
      ->check(CLI::Range(0, 12));
  app.add_flag("--no-direction", o.no_direction,
               "Correct with no direction of motion (reversal terms 0) instead of each axis's direction of travel");
  app.add_flag("--no-orientation", o.no_orientation,
               "Keep the rotary axes as programmed: correct the tool point only, not the tool's orientation");
  app.add_flag("--no-travel-check", o.no_travel_check, "Allow commanded positions outside the axes' travels");
  app.add_flag("--json", o.json_out,
               "Machine-readable summary: correction {moves, moves_corrected, subdivisions, transitions, ...}, "
               "rewrite {lines_in, lines_changed, lines_added}, seconds, out");
}

namespace {

GcodeCorrectionOptions correction_options(const Machine& m, const GcodeCorrectionCliOptions& o) {
  GcodeCorrectionOptions opt;
  opt.max_deviation = o.max_deviation;
  opt.linearise_arcs = o.linearise_arcs;
  opt.directions = !o.no_direction;
  opt.orientation = !o.no_orientation;
  opt.travel_check = !o.no_travel_check;
  opt.origin = parse_program_origin(m, o.origin);
  return opt;
}

void print_correction(const GcodeCorrectionCliOptions& o, const Machine& m, const GcodeProgram& program,
                      const GcodeCorrectionResult& result, const CorrectedProgram& c, double seconds) {
  const GcodeRewriteSummary& rs = c.summary;
  std::cout << fmt::format("machine      {} ({})\n", m.name, m.topology.chain);
  std::cout << fmt::format("program      {}: {} lines, {} moves{}\n", o.gcode, rs.lines_in, result.moves.size(),
                           program.interpreter == "rs274" ? " (read by LinuxCNC's interpreter rs274)" : "");
  std::cout << fmt::format("corrected    {} moves; {} pieces added ({} reversal moves); arcs {} kept, {} linearised\n",
                           result.moves_corrected, result.subdivisions, result.transitions, result.arcs_kept,
                           result.arcs_linearised);
  std::cout << fmt::format("correction   up to {:.6f} mm (X Y Z), {:.6f} deg (A B C)\n", result.max_correction,
                           result.max_rotary_correction);
  std::cout << fmt::format("solver       {} points, at most {} iterations, residual {:.3g} mm\n", result.points_solved,
                           result.max_iterations, result.max_residual);
  std::cout << fmt::format("tool point   error before {:.6f} mm, deviation after {:.6f} mm (at the points checked)\n",
                           result.max_error_before, result.max_deviation_after);
  for (const auto& w : result.warnings) std::cout << "warning      " << w << "\n";
  if (c.expanded)
    std::cout << fmt::format(
        "wrote        {} ({} lines: every move expanded, absolute mm; docs/gcode.md) in {:.3f} s\n", o.out,
        rs.lines_added, seconds);
  else
    std::cout << fmt::format("wrote        {} ({} lines changed, {} added) in {:.3f} s\n", o.out, rs.lines_changed,
                             rs.lines_added, seconds);
}

int run(const GcodeCorrectionCliOptions& o) {
  if (o.gcode.empty()) throw InputError({"--gcode", 0, ""}, "expected a G-code program to correct");
  if (o.out.empty()) throw InputError({"--out", 0, ""}, "expected the path of the corrected program");
  {
    auto inputs = model_inputs(o.model);
    inputs.push_back(o.gcode);
    for (const auto& f : gcode_input_files(o.input)) inputs.push_back(f);
    check_outputs(inputs, {o.out});
  }
  const Machine m = load(o.model);
  const ErrorModel model(m);
  const GcodeCorrectionOptions opt = correction_options(m, o);
  AtomicFile file(o.out);  // refuses a bad output path before the work
  const auto t0 = std::chrono::steady_clock::now();
  const GcodeProgram program = read_gcode_program(o.gcode, m, o.input);
  print_gcode_warnings(program.warnings, program.counts.warnings);
  const GcodeCorrectionResult result = correct_program(model, program, opt);
  GcodeRewriteOptions ro;
  ro.decimals = o.decimals;
  const CorrectedProgram c = corrected_program(m, program, read_text_file(o.gcode, "G-code program"), result.moves, ro);
  file.stream() << c.text;
  file.commit();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!o.json_out) {
    print_correction(o, m, program, result, c, seconds);
    return 0;
  }
  print_json(to_json(m, o.gcode, program.interpreter, result, c, seconds, o.out));
  return 0;
}

}  // namespace

int run_gcode_correction(const GcodeCorrectionCliOptions& o) {
  try {
    return run(o);
  } catch (const InputError& e) {
    rethrow_for_options(e, {{"max deviation", "--max-deviation"}, {"decimals", "--decimals"}});
  }
}

}  // namespace mtcal::cli
