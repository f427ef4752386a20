// mtcal command line: a thin layer that parses options, calls the library and prints results.
#include <csignal>
#include <cstdio>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <unistd.h>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "mtcal/evaluation/contributions.hpp"
#include "mtcal/evaluation/error_stream.hpp"
#include "mtcal/io/points/error_csv.hpp"
#include "mtcal/io/json/error_map_json.hpp"
#include "mtcal/io/json/campaign_json.hpp"
#include "mtcal/io/model/drawn_parameters_file.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/identification/error_draw.hpp"
#include "mtcal/util/parse.hpp"
#include "mtcal/io/system/files.hpp"
#include "mtcal/io/text/joints.hpp"
#include "mtcal/io/text/number_format.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/report/error_map.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/parallel.hpp"
#include "mtcal/util/solver_log.hpp"
#include "mtcal/util/suggest.hpp"
#include "mtcal/kinematics/kernel_isa.hpp"
#include "mtcal/version.hpp"
#include "mtcal/report/report.hpp"
#include "acceptance.hpp"
#include "budget.hpp"
#include "common.hpp"
#include "planning_command.hpp"
#include "history.hpp"

using namespace mtcal;
using namespace mtcal::cli;

namespace mtcal::cli {
// The browser front end on a history store: serve (cmd_serve.cpp).
std::vector<Command> add_serve_commands(CLI::App& app);
}  // namespace mtcal::cli

namespace {

std::string fmt_num(double v) { return format_number(v); }

// Configurations per second and thread of the exact model, batched: 2.0e6 measured with
// `eval --grid` of 5e5 points on hu40t-wCBXfYZt, --threads 1 (docs/reliability.md).
constexpr double kEvaluationsPerSecond = 2e6;

struct EvalOptions {
  ModelOptions model;
  std::string at, points, grid, out, report;
  bool json_out = false, no_travel_check = false;
  int threads = 0;
};

int run_eval_at(const EvalOptions& o, const Machine& m) {
  if (!o.out.empty()) throw InputError({"--out", 0, ""}, "--out goes with --points or --grid, not --at");
  if (!o.report.empty()) throw InputError({"--report", 0, ""}, "--report goes with --points or --grid, not --at");
  const auto q = parse_joint_values(m, o.at, "--at");
  check_joints(m, q, "--at", !o.no_travel_check);
  const VolumetricError e = ErrorModel(m).evaluate(q);
  if (!e.translation.allFinite() || !e.rotation.allFinite())
    throw Error("the model gives a non-finite error at --at " + o.at + " (check the machine's error values)");
  const Json j = to_json(e);
  if (o.json_out) {
    print_json(j);
    return 0;
  }
  int c = 0;
  for (const auto& [key, value] : j.items())
    std::cout << fmt::format("{} {:>16} {}\n", key, fmt_num(value.get<double>()), c++ < 3 ? "mm" : "rad");
  return 0;
}

void print_stream_summary(const EvalOptions& o, const Machine& m, const StreamSummary& s) {
  std::cout << fmt::format("machine      {} ({})\n", m.name, m.topology.chain);
  std::cout << fmt::format("evaluated    {} configurations in {:.3f} s ({:.3g} per second)\n", s.count, s.seconds,
                           s.seconds > 0 ? static_cast<double>(s.count) / s.seconds : 0.0);
  if (s.count) {
    std::cout << fmt::format("largest translational error  {:.6f} mm  at {}\n", s.max_translation.value,
                             format_joint_values(m, s.max_translation.at));
    std::cout << fmt::format("largest rotational error     {:.3f} urad  at {}\n", s.max_rotation.value * 1e6,
                             format_joint_values(m, s.max_rotation.at));
  }
  if (!o.out.empty()) std::cout << "wrote        " << o.out << "\n";
  if (!o.report.empty()) std::cout << "report       " << o.report << "\n";
}

// --out FILE.npy: the binary NumPy array instead of CSV text.
bool npy_out(const std::string& out) { return out.size() > 4 && out.compare(out.size() - 4, 4, ".npy") == 0; }

// Progress on a terminal for runs of more than one chunk.
std::function<void(std::size_t, std::size_t)> stream_progress(std::size_t count, std::size_t chunk) {
  if (count <= chunk || !::isatty(STDERR_FILENO)) return {};
  return [](std::size_t done, std::size_t total) {
    std::cerr << fmt::format("\r  {} / {} configurations ({:.0f}%)", done, total,
                             100.0 * static_cast<double>(done) / static_cast<double>(total))
              << std::flush;
  };
}

// Batched modes: configurations from the CSV rows or the grid, streamed in chunks so that a
// grid of any size runs in bounded memory.
int run_eval_stream(const EvalOptions& o, const Machine& m) {
  const ErrorModel model(m);
  ConfigurationList list;
  GridValues grid;
  if (!o.points.empty())
    list = read_configurations(m, o.points, !o.no_travel_check);
  else
    grid = checked_grid(m, o.grid, !o.no_travel_check);
  const auto source = o.points.empty() ? ConfigurationSource::grid(grid) : ConfigurationSource::list(list);
  {
    // Streamed in chunks: the memory is bounded; the time and the --out file grow with the count.
    // Per row: the axis values (about 12 characters each), directions, 6 errors of 16 characters.
    const double count = static_cast<double>(source.size()), axes = static_cast<double>(m.axes.size());
    const double row = npy_out(o.out) ? 8 * (axes * (source.has_directions() ? 2 : 1) + 6)
                                      : axes * 13 + (source.has_directions() ? axes * 3 : 0) + 6 * 17;
    const double threads = static_cast<double>(worker_count(o.threads, source.size()));
    check_estimate({fmt::format("eval {} of {:.4g} configurations", o.points.empty() ? "--grid" : "--points", count), 0,
                    count / kEvaluationsPerSecond / threads, o.out.empty() ? 0.0 : count * row});
  }
  std::optional<ErrorStreamCsv> file;
  std::optional<ErrorStreamNpy> npy;
  if (npy_out(o.out))
    npy.emplace(o.out, m, source.has_directions());
  else if (!o.out.empty())
    file.emplace(o.out, m, source.has_directions(), o.threads);
  std::optional<ErrorStreamReport> report;
  if (!o.report.empty()) {
    AtomicFile probe_path(o.report);  // refuse a bad report path before the work
    report.emplace(model, source.size());
  }
  StreamOptions so{o.threads, std::size_t{1} << 20, {}};
  so.progress = stream_progress(source.size(), so.chunk);
  std::function<void(const ErrorChunk&)> sink;  // none without outputs: the stream skips the configurations
  if (report || file || npy)
    sink = [&](const ErrorChunk& c) {
      if (report) report->add(c);
      if (file) file->write(c);
      if (npy) npy->write(c);
    };
  const StreamSummary summary = evaluate_stream(model, source, sink, so);
  if (so.progress) std::cerr << "\r" << std::string(60, ' ') << "\r" << std::flush;
  if (file) file->commit();
  if (npy) npy->commit();
  if (report) report->write(o.report, {command_line(), o.model.params, o.points, o.grid});
  if (!o.json_out) {
    print_stream_summary(o, m, summary);
    return 0;
  }
  Json j = to_json(m, summary);
  if (!o.out.empty()) j["out"] = o.out;
  if (!o.report.empty()) j["report"] = o.report;
  print_json(j);
  return 0;
}

int run_eval(const EvalOptions& o) {
  const int modes = !o.at.empty() + !o.points.empty() + !o.grid.empty();
  if (modes != 1) throw InputError({"eval", 0, ""}, "expected exactly one of --at, --points, --grid");
  {
    auto inputs = model_inputs(o.model);
    inputs.push_back(o.points);
    check_outputs(inputs, {o.out, o.report});
  }
  const Machine m = load(o.model);
  return o.at.empty() ? run_eval_stream(o, m) : run_eval_at(o, m);
}

struct ErrorsOptions {
  ModelOptions model;
  std::string report, out, out_nominal;
  std::optional<std::uint64_t> draw;
  std::vector<std::string> draw_only, draw_table;
  std::size_t draw_table_points = ErrorDrawOptions{}.table_points;
  std::string draw_length = "5:50", draw_angle = "10:100";
  bool json_out = false, nonzero = false;
};

// "LO:HI" of --draw-length-um / --draw-angle-urad, in the option's unit.
std::pair<double, double> draw_range(const std::string& spec, const char* option) {
  const auto colon = spec.find(':');
  const auto lo = colon == std::string::npos ? std::nullopt : parse_number(spec.substr(0, colon));
  const auto hi = colon == std::string::npos ? std::nullopt : parse_number(spec.substr(colon + 1));
  if (!lo || !hi || *lo < 0 || *hi < *lo)
    throw InputError({option, 0, spec}, "expected LO:HI with 0 <= LO <= HI, found '" + printable(spec) + "'");
  return {*lo, *hi};
}

// --draw SEED: the machine's errors replaced by a drawn truth (identification/error_draw.hpp).
ErrorDraw run_draw(const ErrorsOptions& o, const Machine& m) {
  ErrorDrawOptions d;
  d.seed = *o.draw;
  d.only = o.draw_only;
  d.tables = o.draw_table;
  d.table_points = o.draw_table_points;
  const auto [llo, lhi] = draw_range(o.draw_length, "--draw-length-um");
  const auto [alo, ahi] = draw_range(o.draw_angle, "--draw-angle-urad");
  d.length_lo = llo * 1e-3, d.length_hi = lhi * 1e-3, d.angle_lo = alo * 1e-6, d.angle_hi = ahi * 1e-6;
  d.only_source = "--draw-only";
  d.tables_source = "--draw-table";
  d.size_source = "--draw-length-um";
  return draw_errors(m, d);
}

int run_errors(const ErrorsOptions& o) {
  check_outputs(model_inputs(o.model), {o.report, o.out, o.out_nominal});
  draw_range(o.draw_length, "--draw-length-um");  // malformed values are refused with or without --draw
  draw_range(o.draw_angle, "--draw-angle-urad");
  if (!o.draw)
    for (const auto& [set, name] : {std::pair{!o.draw_only.empty(), "--draw-only"}, {!o.draw_table.empty(), "--draw-table"},
                                    {!o.out_nominal.empty(), "--out-nominal"}})
      if (set) throw InputError({name, 0, ""}, std::string(name) + " goes with --draw SEED");
  for (const auto* p : {&o.out, &o.out_nominal})
    if (!p->empty()) AtomicFile check(*p);
  const Machine loaded = load(o.model);
  std::optional<ErrorDraw> draw;
  if (o.draw) draw = run_draw(o, loaded);
  const Machine& m = draw ? draw->truth : loaded;
  const auto listed = listed_parameters(m, o.nonzero || draw.has_value());
  if (!o.report.empty())
    write_parameters_report(o.report, m, listed, m.parameter_count(), o.nonzero || draw.has_value(),
                            {command_line(), o.model.params, "", ""});
  const std::string about = fmt::format("Drawn by mtcal errors --draw {} from machine {}", draw ? draw->seed : 0,
                                        o.model.machine);
  if (!o.out.empty()) {
    if (draw)
      write_truth_parameters(o.out, *draw, about);
    else
      write_file_atomically(o.out, every_error_yaml(m, "Errors of machine " + o.model.machine));
  }
  if (!o.out_nominal.empty()) write_nominal_parameters(o.out_nominal, *draw, about);
  if (o.json_out) {
    Json j = to_json(m, std::span<const ErrorParameter>(listed));
    if (draw) j["draw"] = to_json(*draw);
    if (!o.out.empty()) j["out"] = o.out;
    if (!o.out_nominal.empty()) j["out_nominal"] = o.out_nominal;
    print_json(j);
    return 0;
  }
  if (draw) {
    std::cout << fmt::format("drew {} errors with seed {} (size: the largest |value| over the travel)\n",
                             draw->drawn.size(), draw->seed);
    for (const auto& e : draw->drawn)
      std::cout << fmt::format("  {:<5} {:>10.3f} {}{}\n", e.error.str(), e.size * (e.rotational ? 1e6 : 1e3),
                               e.rotational ? "urad" : "um", e.table ? "  (table)" : "");
  }
  std::cout << fmt::format("{:<10} {:<9} {:<10} {:>16}\n", "name", "kind", "unit", "value");
  for (const auto& p : listed)
    std::cout << fmt::format("{:<10} {:<9} {:<10} {:>16}\n", p.name, to_string(p.error.kind), p.unit, fmt_num(p.value));
  if (!o.out.empty()) std::cout << "wrote " << o.out << "\n";
  if (!o.out_nominal.empty()) std::cout << "wrote " << o.out_nominal << "\n";
  return 0;
}

// --errors: names the machine has.
std::vector<ErrorName> wanted_errors(const Machine& m, const std::string& list) {
  std::vector<ErrorName> out;
  for (const auto& w : split_list(list)) {
    auto en = ErrorName::parse(w);
    if (!en || !m.has_error(*en))
      throw InputError({"--errors", 0, w}, "unknown error name '" + printable(w) + "'" + name_hint(m, w) +
                                               " for topology " + m.topology.chain);
    out.push_back(*en);
  }
  return out;
}

void print_effects(std::span<const ErrorEffect> effects) {
  std::cout << fmt::format("{:<6} {:<9} {:<5} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10}\n", "error", "kind", "per",
                           "dx um", "dy um", "dz um", "rx urad", "ry urad", "rz urad");
  for (const auto& e : effects) {
    const auto& v = e.effect;
    std::cout << fmt::format("{:<6} {:<9} {:<5} {:>10.4g} {:>10.4g} {:>10.4g} {:>10.4g} {:>10.4g} {:>10.4g}\n",
                             e.error.str(), to_string(e.error.kind), e.rotational ? "urad" : "um", v[0], v[1], v[2],
                             v[3], v[4], v[5]);
  }
}

struct EffectsOptions {
  ModelOptions model;
  std::string at, errors, around = "nominal", report;
  bool json_out = false, no_travel_check = false;
};

int run_effects(const EffectsOptions& o) {
  check_outputs(model_inputs(o.model), {o.report});
  Machine m = load(o.model);
  // About the nominal machine the effects are the errors' definitions (exact zeros where an
  // error has no effect); about the actual machine they include second-order cross terms.
  if (o.around == "nominal") m.clear_errors();
  const auto q = parse_joint_values(m, o.at, "--at");
  check_joints(m, q, "--at", !o.no_travel_check);
  const auto wanted = wanted_errors(m, o.errors);
  const auto effects = single_error_effects(m, q, wanted);
  if (!o.report.empty())
    write_effects_report(o.report, m, q, o.around, effects, {command_line(), o.model.params, "", ""});
  if (o.json_out)
    print_json(to_json(m, q, o.around, effects));
  else
    print_effects(effects);
  return 0;
}

Command add_eval_command(CLI::App& app) {
  auto o = std::make_shared<EvalOptions>();
  auto* eval = app.add_subcommand("eval",
                                  "Volumetric error (dx dy dz in mm, rx ry rz in rad) of the tool "
                                  "relative to the workpiece at joint configurations");
  add_model_options(eval, o->model);
  eval->add_option("--at", o->at,
                   "One configuration, e.g. \"X=100,Y=50,Z=-20,B=30,C=90\" (mm, deg, or with a unit: X=0.1m, "
                   "B=0.5rad; axes not named are 0)");
  eval->add_option("--points", o->points,
                   "CSV of configurations: columns named by axis letters (mm, deg), "
                   "optional dirX ... = +1/-1 directions of motion");
  eval->add_option("--grid", o->grid,
                   "Full grid, e.g. \"X=-300:300:7,B=-90:90:5\": per axis lo:hi:count, count values evenly spaced "
                   "from lo to hi inclusive (step (hi-lo)/(count-1)), or one value; axes not named are 0; mm and deg, "
                   "or with a unit (-0.3m:0.3m:7, -1.5rad:1.5rad:5). Configurations (and --out rows) run through the "
                   "grid with the last axis of the topology's chain varying fastest (wCBXfYZt: C slowest, then B, X, "
                   "Y, Z fastest)");
  eval->add_option("--out", o->out,
                   "Write every configuration with dx,dy,dz,rx,ry,rz to this CSV; a name ending in .npy writes a "
                   "NumPy array file instead (float64 rows, the same columns, numpy.load reads it; exact doubles, "
                   "several times faster to write than text)");
  eval->add_option("--report", o->report,
                   "Write an HTML report (error map, distribution, largest errors; "
                   "self-contained, opens offline) of a --points or --grid run");
  eval->add_flag("--json", o->json_out, "Machine-readable output (keys dx dy dz rx ry rz for --at)");
  eval->add_flag("--no-travel-check", o->no_travel_check, "Evaluate outside the axes' travel too");
  eval->add_option("--threads", o->threads, "Threads for batches (0: all cores)")->check(CLI::Range(0, 4096));
  return {eval, [o] { return run_eval(*o); }};
}

Command add_errors_command(CLI::App& app) {
  auto o = std::make_shared<ErrorsOptions>();
  auto* errors = app.add_subcommand("errors",
                                    "List every error parameter of a machine: name, kind, "
                                    "internal unit, value");
  add_model_options(errors, o->model);
  errors->add_flag("--json", o->json_out, "Machine-readable output");
  errors->add_flag("--nonzero", o->nonzero, "Only parameters whose value is not zero");
  errors->add_option("--report", o->report, "Write an HTML report of the parameters");
  errors->add_option("--out", o->out,
                     "Write a parameter file (--params reads it) with every error of the machine: the drawn truth "
                     "with --draw (every other error zero), else the machine's values");
  errors->add_option("--draw", o->draw,
                     "Replace the machine's errors by a truth drawn with this seed: every location error (or "
                     "--draw-only), each of a random size in --draw-length-um / --draw-angle-urad and sign; the same "
                     "seed gives the same truth (docs/campaign.md)");
  errors->add_option("--draw-only", o->draw_only,
                     "With --draw: only these errors or parameters (e.g. the --estimate list of identify, so that "
                     "the truth is within the calibration's reach), comma-separated")
      ->delimiter(',');
  errors->add_option("--draw-table", o->draw_table,
                     "With --draw: these motion errors drawn as tables (e.g. ECC,EXX): a smooth curve at "
                     "--draw-table-points positions over the axis' travel, zero at the axis' zero")
      ->delimiter(',');
  errors->add_option("--draw-table-points", o->draw_table_points, "Positions of a --draw-table table")
      ->check(CLI::Range(2, 10000))
      ->capture_default_str();
  errors->add_option("--draw-length-um", o->draw_length, "With --draw: LO:HI, the size of a length error, um")
      ->capture_default_str();
  errors->add_option("--draw-angle-urad", o->draw_angle, "With --draw: LO:HI, the size of an angle error, urad")
      ->capture_default_str();
  errors->add_option("--out-nominal", o->out_nominal,
                     "With --draw: a parameter file of the same errors in the same forms (the tables' positions), "
                     "every value zero: the model the calibration starts from");
  return {errors, [o] { return run_errors(*o); }};
}

Command add_effects_command(CLI::App& app) {
  auto o = std::make_shared<EffectsOptions>();
  auto* effects =
      app.add_subcommand("effects",
                         "Effect of each single error on the tool at one configuration: dx dy dz (um) and rx ry rz "
                         "(urad) per 1 um or 1 urad of the error (first-order sensitivity of the exact model)");
  add_model_options(effects, o->model);
  effects->add_option("--at", o->at, "The configuration, e.g. \"X=100,B=30\" (mm, deg; axes not named are 0)")
      ->required();
  effects->add_option("--errors", o->errors, "Only these errors, comma-separated (e.g. EXX,EC0Y,EX0C)");
  effects
      ->add_option("--around", o->around,
                   "Linearise about the error-free machine (nominal, the errors' definitions) or about the "
                   "machine with its errors (actual)")
      ->check(CLI::IsMember({"nominal", "actual"}))
      ->capture_default_str();
  effects->add_flag("--json", o->json_out, "Machine-readable output (keys error kind per dx dy dz rx ry rz)");
  effects->add_flag("--no-travel-check", o->no_travel_check, "Allow a configuration outside the travel");
  effects->add_option("--report", o->report, "Write an HTML report of the effects");
  return {effects, [o] { return run_effects(*o); }};
}

// Examples at the end of each command's --help, run from a clone's top folder. The ctest
// readme_tour runs every one of them after README's tour (whose files some of them read), so an
// example cannot name an option the command does not take.
constexpr std::pair<const char*, const char*> kExamples[] = {
    {"eval",
     "  mtcal eval -m examples/machines/hu40t-wCBXfYZt.yaml --at \"X=100,Y=50,Z=-20,B=30,C=90\"\n"
     "  mtcal eval -m examples/machines/vmc-3axis.yaml --grid \"X=-400:400:5,Y=-250:250:3\" --out grid-errors.csv\n"
     "  mtcal eval -m examples/machines/vmc-3axis.yaml --at \"Y=200\" --set EC0Y=20urad --only EC0Y\n"},
    {"errors",
     "  mtcal errors -m examples/machines/vmc-3axis.yaml --nonzero\n"
     "  mtcal errors -m examples/machines/hu40t-wCBXfYZt.yaml --json\n"
     "  # a truth to rehearse a campaign on: seed 7, the location errors of C and B, ECC as a table\n"
     "  mtcal errors -m examples/machines/hu40t-wCBXfYZt.yaml --draw 7 --draw-only EX0C,EY0C,EA0C,EB0C,EX0B,EZ0B \\\n"
     "      --draw-table ECC --out truth.yaml --out-nominal nominal.yaml\n"},
    {"effects",
     "  mtcal effects -m examples/machines/hu40t-wCBXfYZt.yaml --at \"X=100,B=30,C=90\" --errors EX0C,EA0C,EXX\n"},
    {"probe-sim",
     "  mtcal probe-sim -m examples/machines/hu40t-wCBXfYZt.yaml --axis C --angles 0:350:36 --noise 0.001 "
     "--out contacts.csv\n"},
    {"rotary-axis",
     "  mtcal rotary-axis --axis C --contacts contacts.csv --sphere-diameter 30 --stylus-diameter 6 \\\n"
     "      --machine examples/machines/hu40t-wCBXfYZt.yaml --out c-axis.yaml\n"},
    {"iso230-2",
     "  mtcal iso230-2 examples/data/iso230-2-x-axis.csv\n"
     "  mtcal iso230-2 examples/data/iso230-2-x-axis.csv --unit mm --json --report iso230-2.html\n"},
    {"ballbar",
     "  mtcal ballbar --predict -m examples/machines/hu40t-wCBXfYZt.yaml --plane XY --radius 150 --centre "
     "\"Z=-100\" --out trace.csv\n"
     "  mtcal ballbar trace.csv --radius 150 --report ballbar.html\n"},
    {"compare", "  mtcal compare examples/data/mohammed2019-ballbar-vs-samba.csv --json\n"},
    {"volumetric",
     "  mtcal volumetric -m examples/machines/vmc-3axis.yaml --grid \"X=-400:400:21,Y=-250:250:21,Z=-500:0:21\"\n"
     "  mtcal volumetric -m examples/machines/vmc-3axis.yaml --grid \"X=-400:400:11,Y=-250:250:11,Z=-500:0:11\" \\\n"
     "      --histogram auto --box \"X=-200:200,Y=-125:125\" --report va.html\n"},
    {"contributions",
     "  mtcal contributions -m examples/machines/vmc-3axis.yaml --grid \"X=-400:400:21,Y=-250:250:21,Z=-500:0:21\"\n"
     "  mtcal contributions -m examples/machines/vmc-3axis.yaml --at \"X=400,Y=250,Z=0\"\n"},
    {"diagonals", "  mtcal diagonals -m examples/machines/vmc-3axis.yaml --box \"X=-400:400,Y=-250:250,Z=-500:0\"\n"},
    {"toolpath",
     "  mtcal toolpath -m examples/machines/vmc-3axis.yaml --gcode examples/gcode/pocket.nc \\\n"
     "      --origin \"X=-40,Y=-25,Z=-400\" --step 0.5 --out path-errors.csv\n"
     "  mtcal toolpath -m examples/machines/vmc-3axis.yaml --gcode examples/gcode/drill-plate.nc \\\n"
     "      --tool-table examples/gcode/tools.tbl --work-offset \"G54:X=-150,Y=-100,Z=-450\" --json\n"
     "  # LinuxCNC's programs (parameters, O-word subroutines) through its interpreter rs274, if installed:\n"
     "  #   mtcal toolpath -m examples/machines/vmc-3axis.yaml --gcode /usr/share/linuxcnc/ncfiles/spiral.ngc \\\n"
     "  #       --origin \"Z=-300\" --interpreter rs274\n"},
    {"simulate",
     "  mtcal simulate -m examples/machines/hu40t-wCBXfYZt.yaml --plan examples/plans/hu40t-samba-tango.csv \\\n"
     "      --noise-um 1 --seed 7 --scale-bar 1:2:304.8 --out samba.csv\n"},
    {"identify",
     "  mtcal identify -m examples/machines/hu40t-wCBXfYZt.yaml --measurements samba.csv --scale-bar 1:2:304.8 \\\n"
     "      --estimate EC0Y,EB0Z,EA0Z,EX0C,EY0C,EA0C,EB0C --out identified.yaml\n"},
    {"identifiability",
     "  mtcal identifiability -m examples/machines/hu40t-wCBXfYZt.yaml --plan examples/plans/hu40t-samba-tango.csv \\\n"
     "      --estimate EX0C,EX0B,EX0X,EXt\n"},
    {"regress", "  mtcal regress examples/prediction/yaqoob2017-table5_8.csv --x t --y e_splz\n"},
    {"predict",
     "  mtcal predict --model examples/prediction/yaqoob2017-model.yaml --points "
     "examples/prediction/yaqoob2017-w2-points.csv\n"},
    {"separate",
     "  mtcal separate position examples/prediction/yaqoob2017-table5_3.csv\n"
     "  mtcal separate control examples/prediction/yaqoob2017-table5_6.csv --a W2 --b W5\n"},
    {"process-error", "  mtcal process-error --feed 100,200,400,800,1600 --speed 3500 --ae 1 --ap 5\n"},
};

// Every command, in the order of the help text.
std::vector<Command> add_commands(CLI::App& app) {
  std::vector<Command> all{add_eval_command(app), add_errors_command(app), add_effects_command(app)};
  for (auto* add : {add_probing_commands, add_evaluation_commands, add_fit_motion_commands, add_compare_commands,
                    add_volumetric_commands, add_toolpath_commands, add_compensation_commands, add_prediction_commands,
                    add_identification_commands, add_planning_commands, add_campaign_commands, add_history_commands,
                    add_serve_commands})
    for (auto& c : add(app)) all.push_back(std::move(c));
  // history diff, trend, rank beside the store's list, show, import, export, event add.
  for (auto& c : add_history_analysis_commands(*history_app())) all.push_back(std::move(c));
  // --precision on every command: the digits of the numbers it writes to CSV files and prints
  // unrounded (JSON always carries every double exactly).
  for (auto* sub : app.get_subcommands({}))
    sub->add_option_function<int>(
           "--precision", [](const int& d) { set_significant_digits(d); },
           "Significant digits of written numbers (CSV cells, unrounded printed values): 10 by default, up to 17 "
           "(every double read back bit for bit); JSON is always exact")
        ->check(CLI::Range(1, 17));
  for (const auto& [name, text] : kExamples)
    for (auto* sub : app.get_subcommands({}))
      if (sub->get_name() == name && sub->get_footer().empty()) sub->footer(std::string("Examples:\n") + text);
  return all;
}

// A first argument that names no command: one line naming those there are, exit 2.
bool unknown_command(CLI::App& app, int argc, char** argv) {
  if (argc < 2 || argv[1][0] == '-') return false;
  const std::string cmd = argv[1];
  std::string names;
  std::vector<std::string> all;
  for (const auto* sub : app.get_subcommands({})) {
    if (sub->get_name() == cmd) return false;
    names += (names.empty() ? "" : ", ") + sub->get_name();
    all.push_back(sub->get_name());
  }
  std::cerr << "mtcal: error: unknown command '" << printable(cmd) << "'" << did_you_mean(cmd, all)
            << " (expected one of " << names << "; see 'mtcal --help')\n";
  return true;
}

// An error message as one line of at most ~300 characters: control characters escaped (a newline
// becomes a space), the middle of a longer message cut with "…" (its start says what, its end
// often where).
std::string one_line(std::string msg) {
  for (auto& c : msg)
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
  std::string out;
  for (const char ch : msg) {
    const auto c = static_cast<unsigned char>(ch);
    if (c < 0x20 || c == 0x7f)
      out += fmt::format("\\x{:02x}", c);
    else
      out += ch;
  }
  constexpr std::size_t kMax = 300;
  if (out.size() <= kMax) return out;
  // Cut at character boundaries (never inside a UTF-8 sequence).
  std::size_t head = 200, tail = out.size() - 90;
  while (head > 0 && (static_cast<unsigned char>(out[head]) & 0xC0) == 0x80) --head;
  while (tail < out.size() && (static_cast<unsigned char>(out[tail]) & 0xC0) == 0x80) ++tail;
  return out.substr(0, head) + "\u2026" + out.substr(tail);
}

// An argument the command does not take: its closest option name, if one is close ("--grdi" ->
// "--grid"), and where the command's help is.
std::string extras_hint(CLI::App& app) {
  for (auto* sub : app.get_subcommands()) {
    std::vector<std::string> names;
    for (const auto* opt : sub->get_options())
      for (const auto& l : opt->get_lnames()) names.push_back("--" + l);
    std::string hint;
    // With the global options falling through, the extras may stay with the command or the app.
    std::vector<std::string> extras = sub->remaining();
    for (const auto& e : app.remaining()) extras.push_back(e);
    for (const auto& extra : extras) {
      if (extra.rfind("--", 0) != 0) continue;
      const auto c = closest_name(extra.substr(0, extra.find('=')), names);
      if (c) hint += " (did you mean '" + *c + "' for '" + printable(extra) + "'?)";
    }
    return hint + " (see 'mtcal " + sub->get_name() + " --help')";
  }
  return " (see 'mtcal --help')";
}

// Runs the parsed command; an error is one line on stderr and exit 1.
int run_command(const std::vector<Command>& commands) {
  try {
    // Every file the command writes appears at the end, all together, or none does.
    OutputGroup outputs;
    std::string name;
    const int rc = [&] {
      for (const auto& c : commands)
        if (c.app->parsed()) {
          // A wrong MTCAL_KERNEL_ISA is reported whichever command runs, not only by those
          // that reach the batched kernels.
          kernel_isa();
          load_session_metadata();
          set_static_copy_note(
              "A static copy for e-mail: the same command with <code>--report-pdf FILE</code> (the report printed to "
              "PDF) or <code>--report-png DIR</code> (each plot as a PNG image), docs/reports.md.");
          load_static_copies(*c.app);
          name = c.app->get_name();
          prepare_recording();
          return c.run();
        }
      throw Error("no command");
    }();
    std::cout.flush();
    if (!std::cout) throw Error("cannot write the results to standard output");
    // The record is part of the command's all-or-none output: stored (one transaction) only when
    // the command succeeded, taken out again if its files then cannot be put in place.
    const auto recorded = record_result(name);
    try {
      outputs.commit();
    } catch (...) {
      if (recorded) unrecord(*recorded);
      throw;
    }
    return rc;
  } catch (const LimitError& e) {
    std::cerr << "mtcal: error: " << one_line(e.what()) << " (" << limit_option(static_cast<int>(e.limit()))
              << " raises it; docs/reliability.md)\n";
    return 1;
  } catch (const std::bad_alloc&) {
    std::cerr << "mtcal: error: out of memory (the computation needs more memory than the system gives; see "
                 "--max-memory in docs/reliability.md)\n";
    return 1;
  } catch (const std::exception& e) {
    std::string msg = e.what();
    // Every command that checks configurations against the travels can be told not to.
    if (msg.find(" is outside the travel [") != std::string::npos) msg += " (use --no-travel-check to evaluate anyway)";
    std::cerr << "mtcal: error: " << one_line(msg) << "\n";
    return 1;
  }
}

}  // namespace

int main(int argc, char** argv) {
  // Past the file-size limit (ulimit -f) a write fails with EFBIG instead of killing the program
  // with SIGXFSZ: the output's temporary file is then removed and the error reported.
  std::signal(SIGXFSZ, SIG_IGN);
  set_command_line(argc, argv);
  CLI::App app{
      "mtcal - geometric accuracy of CNC machine tools: error models, evaluation, "
      "identification and compensation"};
  // The error kernels' instruction-set level too: the first thing to know about a speed report.
  app.set_version_flag("--version", std::function<std::string()>([] {
                         std::string levels;
                         for (KernelIsa isa : supported_kernel_isas()) levels += " " + std::string(to_string(isa));
                         std::string in_use;
                         try {
                           in_use = std::string(to_string(kernel_isa()));
                         } catch (const Error& e) {
                           in_use = std::string("none (") + e.what() + ")";
                         }
                         return std::string("mtcal ") + MTCAL_VERSION + "\nerror kernels: " + in_use +
                                " (this processor:" + levels + "; MTCAL_KERNEL_ISA chooses)";
                       }));
  app.require_subcommand(1);
  // Global options, before or after the command's name.
  app.fallthrough();
  bool verbose = false;
  app.add_flag("--verbose", verbose, "Let the nonlinear solver (Ceres) log to stderr; quiet otherwise");
  add_limit_options(app);
  add_record_options(app);
  const std::vector<Command> commands = add_commands(app);
  // After the commands: they would inherit it.
  app.footer(
      "Examples (from a clone's top folder; 'mtcal COMMAND --help' for each command's own):\n"
      "  mtcal eval -m examples/machines/hu40t-wCBXfYZt.yaml --at \"X=100,Y=50,Z=-20,B=30,C=90\"\n"
      "  mtcal volumetric -m examples/machines/vmc-3axis.yaml --grid \"X=-400:400:21,Y=-250:250:21,Z=-500:0:21\"\n"
      "README.md has a tour of every command; docs/ has a page per topic.");
  add_metadata_options(app);
  add_static_copy_options(app);
  require_finite_numbers(app);
  if (unknown_command(app, argc, argv)) return 2;
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ExtrasError& e) {
    std::cerr << "mtcal: error: " << one_line(e.what()) << extras_hint(app) << "\n";
    return 2;
  } catch (const CLI::ParseError& e) {
    // Usage errors: one line, exit 2 (help goes to stdout only when asked for).
    std::cerr << "mtcal: error: " << one_line(e.what()) << " (see 'mtcal --help')\n";
    return 2;
  }
  set_solver_logging(verbose);
  return run_command(commands);
}
