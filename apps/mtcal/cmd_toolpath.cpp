// mtcal toolpath: the volumetric error along a G-code program (Fletcher 2009, 4.3).
#include <numbers>
#include <algorithm>
#include <iostream>
#include <iterator>
#include <optional>

#include <fmt/format.h>

#include "acceptance.hpp"
#include "common.hpp"
#include "gcode_input.hpp"
#include "mtcal/evaluation/toolpath.hpp"
#include "mtcal/io/points/error_csv.hpp"
#include "mtcal/io/system/files.hpp"
#include "mtcal/io/gcode/reader.hpp"
#include "mtcal/io/text/joints.hpp"
#include "mtcal/io/json/toolpath_json.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/report/toolpath.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/parse.hpp"

namespace mtcal::cli {
namespace {

struct ToolpathCliOptions {
  ModelOptions model;
  GcodeInputOptions input;
  std::string gcode, origin, out, report;
  double step = 0.5, angle_step = 0.5;
  bool skip_rapids = false, json_out = false, no_travel_check = false, no_direction = false;
  int threads = 0;
};

ToolpathOptions toolpath_options(const Machine& m, const ToolpathCliOptions& o) {
  ToolpathOptions opt;
  opt.step = o.step;
  opt.angle_step = o.angle_step;
  opt.program = o.gcode;
  opt.skip_rapids = o.skip_rapids;
  opt.origin = parse_program_origin(m, o.origin);
  opt.directions = !o.no_direction;
  opt.travel_check = !o.no_travel_check;
  opt.batch.threads = o.threads;
  return opt;
}

void print_toolpath(const ToolpathCliOptions& o, const Machine& m, const ToolpathSummary& summary,
                    const GcodeInput& in) {
  const auto& k = summary.counts;
  std::cout << fmt::format("machine      {} ({})\n", m.name, m.topology.chain);
  if (in.interpreter == "rs274")
    std::cout << fmt::format("program      {}: read by LinuxCNC's interpreter rs274 ({} canonical calls), {} moves\n",
                             o.gcode, k.lines, k.moves);
  else
    std::cout << fmt::format("program      {}: {} lines, {} moves{}\n", o.gcode, k.lines, k.moves,
                             k.ignored_words ? fmt::format(", {} S/T/M and no-op G words ignored", k.ignored_words)
                                             : std::string());
  if (!in.why.empty()) std::cout << "interpreter  rs274, because " << in.why << "\n";
  if (k.cycles || k.tool_changes || k.m_words || k.expanded_blocks)
    std::cout << fmt::format("words        {} canned-cycle holes, {} tool changes, {} M, {} S, {} T words{}\n",
                             k.cycles, k.tool_changes, k.m_words, k.s_words, k.t_words,
                             k.warnings ? fmt::format(", {} warnings", k.warnings) : "");
  std::cout << fmt::format("points       {} along {} blocks, {:.3f} mm of path{}\n", summary.points, summary.blocks,
                           summary.path_length,
                           summary.rapids_skipped ? fmt::format(" ({} rapids left out)", summary.rapids_skipped) : "");
  if (summary.points) {
    std::cout << fmt::format("largest translational error  {:.6f} mm  at line {} ({})\n", summary.max_error,
                             summary.max_line, format_joint_values(m, summary.max_at));
    const char* units[6] = {"mm", "mm", "mm", "rad", "rad", "rad"};
    for (std::size_t c = 0; c < 6; ++c)
      std::cout << fmt::format("{} {:>16.9g} .. {:<16.9g} {}\n", kErrorKeys[c], summary.range[c][0],
                               summary.range[c][1], units[c]);
  }
  if (!o.out.empty()) std::cout << "wrote        " << o.out << "\n";
  if (!o.report.empty()) std::cout << "report       " << o.report << "\n";
}

int run_toolpath(const ToolpathCliOptions& o) {
  {
    auto inputs = model_inputs(o.model);
    inputs.push_back(o.gcode);
    for (const auto& f : gcode_input_files(o.input)) inputs.push_back(f);
    check_outputs(inputs, {o.out, o.report});
  }
  const Machine m = load(o.model);
  const ErrorModel model(m);
  const ToolpathOptions opt = toolpath_options(m, o);
  ToolpathInterpolator check(m, opt);  // refuses a bad --step before reading anything
  std::optional<ToolpathCsv> file;
  if (!o.out.empty()) file.emplace(o.out, m);
  if (!o.report.empty()) AtomicFile probe(o.report);  // refuse a bad report path before the work

  GcodeInput in = open_gcode(o.gcode, m, o.input);
  MoveSource& reader = *in.moves;
  std::optional<ToolpathPlotSampler> sampler;
  if (!o.report.empty()) sampler.emplace(m.axes.size());
  const auto summary = simulate_toolpath(model, reader, opt, [&](const ToolpathChunk& c) {
    if (sampler) sampler->add(c);
    if (file) file->write(c);
  });
  if (file) file->commit();
  if (sampler)
    write_toolpath_report(o.report, model, summary, *sampler, {o.gcode, o.step, o.skip_rapids, !o.no_direction},
                          {command_line(), o.model.params, "", ""});
  print_gcode_warnings(in.notes, in.notes.size());
  print_gcode_warnings(reader.warnings(), reader.counts().warnings);
  if (!o.json_out) {
    print_toolpath(o, m, summary, in);
    return 0;
  }
  Json j = to_json(m, summary);
  j["interpreter"] = in.interpreter;
  if (!o.out.empty()) j["out"] = o.out;
  if (!o.report.empty()) j["report"] = o.report;
  print_json(j);
  return 0;
}

// The library names its parameters; the user typed options.
int run_toolpath_command(const ToolpathCliOptions& o) {
  try {
    return run_toolpath(o);
  } catch (const InputError& e) {
    rethrow_for_options(e, {{"step", "--step"}, {"angle step", "--angle-step"}});
  }
}

}  // namespace

std::vector<Command> add_toolpath_commands(CLI::App& app) {
  auto o = std::make_shared<ToolpathCliOptions>();
  auto* c = app.add_subcommand(
      "toolpath",
      "Simulate a G-code program: points along the path every --step mm and the volumetric error of the tool "
      "relative to the workpiece at each (Fletcher 2009, 4.3). mtcal reads the ISO dialect (moves, arcs, "
      "G54-G59.3, G43 H, G28/G30, canned cycles G73 G81-G89); programs in LinuxCNC's full RS274NGC (parameters, "
      "expressions, O-word subroutines) go through LinuxCNC's interpreter rs274. See docs/toolpath.md, "
      "docs/gcode.md");
  add_model_options(c, o->model);
  c->add_option("--gcode", o->gcode, "G-code program (docs/gcode.md); axis words only for the machine's axes")
      ->required();
  add_gcode_input_options(c, o->input);
  c->add_option("--step", o->step, "Largest X Y Z path length between points, mm (default 0.5)")
      ->transform(length_in(1.0, "LENGTH"))
      ->check(kFinite);
  c->add_option("--angle-step", o->angle_step, "Largest A B C motion between points, deg (default 0.5)")
      ->transform(angle_in(std::numbers::pi / 180, "ANGLE"))
      ->check(kFinite);
  c->add_option("--origin", o->origin,
                "Program zero in machine axis positions, like G54: \"X=..,Y=..,Z=..\" (mm, deg; default all 0). "
                "Axes the program does not move stay here");
  c->add_flag("--skip-rapids", o->skip_rapids, "Leave G0 moves out of the points (they still move the axes)");
  c->add_flag("--no-direction", o->no_direction,
              "Evaluate with no direction of motion (reversal terms 0) instead of each axis's direction of travel");
  c->add_flag("--no-travel-check", o->no_travel_check, "Evaluate points outside the axes' travels too");
  c->add_option("--threads", o->threads, "Threads for the error evaluation (0: all)")->check(CLI::Range(0, 4096));
  c->add_option("--out", o->out,
                "Write every point as CSV: line,n,motion,s,<axes in chain order, mm/deg>,dx,dy,dz (mm),rx,ry,rz (rad)");
  c->add_flag("--json", o->json_out,
              "Machine-readable summary: points, blocks, path_length, ignored_words, words {m, s, t, tool_changes, "
              "cycles, warnings}, interpreter, rapids_skipped, max_error {value, line, at}, range {dx: [min, max], "
              "...}, out, report");
  c->add_option(
      "--report", o->report,
      "Write an HTML report: the path in 3D coloured by |error| with the error vectors, the errors along the path");
  return {{c, [o] { return run_toolpath_command(*o); }}};
}

}  // namespace mtcal::cli
