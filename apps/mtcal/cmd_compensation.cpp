// mtcal compensate: compensation files a controller loads (--format, docs/compensation.md), or a
// corrected G-code program (--gcode, docs/compensation-gcode.md).
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include <fmt/format.h>

#include "cmd_gcode_correction.hpp"
#include "acceptance.hpp"
#include "common.hpp"
#include "gcode_input.hpp"
#include "mtcal/compensation/compensation.hpp"
#include "mtcal/io/compensation/output.hpp"
#include "mtcal/io/compensation/output_json.hpp"
#include "mtcal/io/system/files.hpp"
#include "mtcal/io/text/joints.hpp"
#include "mtcal/model/joints.hpp"
#include "mtcal/report/compensation.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal::cli {

namespace {

struct CompensateOptions {
  GcodeCorrectionCliOptions gcode;  // model, --gcode, --out, --json and the program options
  std::string format, range, reference, report;
  std::size_t points = 0, residual_points = 11;
  int linuxcnc_type = 1, threads = 0;
  double skew_reference_length = 100.0;
  double fanuc_unit = 0.001;
};

CompensationOptions library_options(const Machine& m, const CompensateOptions& o) {
  CompensationOptions c;
  c.points = o.points;
  c.residual_points = o.residual_points;
  c.threads = o.threads;
  c.comp_file_type = o.linuxcnc_type;
  c.skew_reference_length = o.skew_reference_length;
  c.detection_unit = o.fanuc_unit;
  if (!o.reference.empty()) {
    c.reference = parse_joint_values(m, o.reference, "--reference");
    check_joints(m, c.reference, "--reference", false);  // 1e308 ran the tables with NaN positions
  }
  if (!o.range.empty()) {
    const JointBox box = parse_box(m, o.range, "--range");
    for (std::size_t a = 0; a < m.axes.size(); ++a) {
      if (!box.named[a]) continue;
      // A table samples lo < hi within the joint range (checked here, where the option is known).
      const double lo = to_user_units(m.axes[a], box.lo[a]), hi = to_user_units(m.axes[a], box.hi[a]);
      if (!(lo < hi) || std::abs(lo) > kMaxJointValue || std::abs(hi) > kMaxJointValue)
        throw InputError({"--range", 0, std::string(1, m.axes[a].letter)},
                         fmt::format("expected lo < hi within +-{:g} for a table along {}, found {:g}:{:g}",
                                     kMaxJointValue, m.axes[a].letter, lo, hi));
      c.sampling.push_back({m.axes[a].letter, lo, hi, o.points});
    }
  }
  return c;
}

// A target's warnings speak of the data; where one of this command's options is what they speak
// of, the command names it after the words that describe it (errors name theirs through
// RequestError and rethrow_for_options).
std::string naming_options(std::string text) {
  static constexpr std::pair<std::string_view, std::string_view> kCauses[] = {
      {"the compensation's reference position", "--reference"}};
  for (const auto& [words, option] : kCauses)
    if (const auto at = text.find(words); at != std::string::npos)
      text.insert(at + words.size(), fmt::format(" ({})", option));
  return text;
}

void print_summary(const TargetOutput& out, const std::string& dir) {
  const CompensationSummary& s = out.summary;
  std::cout << fmt::format("target       {}: numbers are {} ({})\n", s.target, to_string(s.quantity), s.sign_source);
  for (const auto& f : out.files)
    std::cout << "wrote        " << (std::filesystem::path(dir) / f.name).string() << "\n";
  const ResidualSummary& r = s.residual;
  std::cout << fmt::format(
      "tool point   over {} configurations, both directions: |e| up to {:.3f} um before, "
      "{:.3f} um after; VA {:.3f} um before, {:.3f} um after\n",
      r.configurations, r.max_norm_before * 1e3, r.max_norm_after * 1e3, r.va_before * 1e3, r.va_after * 1e3);
  std::cout << fmt::format("per axis     max |e| x y z before {:.3f} {:.3f} {:.3f} um, after {:.3f} {:.3f} {:.3f} um\n",
                           r.max_before[0] * 1e3, r.max_before[1] * 1e3, r.max_before[2] * 1e3, r.max_after[0] * 1e3,
                           r.max_after[1] * 1e3, r.max_after[2] * 1e3);
  for (const auto& c : s.commanded)
    std::cout << fmt::format("range        {} {:g}:{:g} {} ({})\n", c.axis, c.lo, c.hi, c.unit,
                             c.given ? "--range" : c.why);
  for (const auto& n : s.not_compensated)
    std::cout << fmt::format("not held     {} (alone up to {:.3f} um)\n", n.what, n.max_error * 1e3);
  for (const auto& w : s.warnings) std::cout << "warning      " << w << "\n";
}

int run_tables(const CompensateOptions& o) {
  if (o.format.empty())
    throw InputError({"--format", 0, ""}, "expected a controller (--format) or a program to correct (--gcode)");
  if (o.gcode.out.empty()) throw InputError({"--out", 0, ""}, "expected the output directory");
  check_outputs(model_inputs(o.gcode.model), {o.gcode.out, o.report});
  if (!o.report.empty()) AtomicFile check(o.report);  // refuse a bad path before the work
  const CompensationTarget& target = compensation_target(o.format);
  const Machine m = load(o.gcode.model);
  TargetOutput out = target.run(m, library_options(m, o));
  for (auto& w : out.summary.warnings) w = naming_options(w);
  // The folder is renamed into place at once, not with the command's other outputs: everything
  // that can still fail (the report) comes before it.
  if (!o.report.empty()) {
    std::vector<std::pair<std::string, std::string>> inputs;
    for (const auto& f : o.gcode.model.params) inputs.emplace_back("parameter file", f);  // the machine file is shown
    write_compensation_report(o.report, command_line(), m, inputs, o.gcode.out, out);
  }
  std::optional<Json> j;
  if (o.gcode.json_out) {
    j = to_json(out);
    (*j)["machine"] = m.name;
    (*j)["out"] = o.gcode.out;
    if (!o.report.empty()) (*j)["report"] = o.report;
  }
  write_target_output(o.gcode.out, out);
  if (j) {
    print_json(*j);
    return 0;
  }
  print_summary(out, o.gcode.out);
  return 0;
}

}  // namespace

std::vector<Command> add_compensation_commands(CLI::App& app) {
  auto o = std::make_shared<CompensateOptions>();
  std::string formats;
  for (const auto& t : compensation_targets()) formats += fmt::format("\n  {:<12}{}", t.name, t.description);
  auto* c = app.add_subcommand(
      "compensate",
      "Compensation from the error model: the files a controller loads (--format, --out DIR) with the residual "
      "predicted by the controller's own rule, or a corrected G-code program (--gcode, --out FILE). "
      "docs/compensation.md");
  add_model_options(c, o->gcode.model);
  add_gcode_correction_options(*c, o->gcode);
  c->add_option("--format", o->format, "Controller to write for:" + formats);
  c->add_option("--points", o->points, "Positions per table (default: the target's, e.g. 51 for LinuxCNC)")
      ->check(CLI::Range(2, 100000));
  c->add_option("--range", o->range,
                "Table ranges, e.g. \"X=-300:300,Y=-200:200\" (mm, deg; default: each axis's travel). "
                "linuxcnc-kins: the commanded travel of the module (default: each travel less the room its "
                "corrections need, computed and stated)");
  c->add_option("--reference", o->reference,
                "Where the other axes stand while one axis's table is sampled, e.g. \"Z=-250\" (default all 0)");
  c->add_option("--linuxcnc-type", o->linuxcnc_type,
                "LinuxCNC COMP_FILE_TYPE: 0 = columns are the positions reached, 1 = columns are corrections")
      ->check(CLI::IsMember({0, 1}));
  c->add_option(
      "--skew-reference-length", o->skew_reference_length,
      "rrf, fluidnc: the length (mm) the skew corrections refer to, M556 S / FluidNC distance_mm (default 100)");
  c->add_option("--fanuc-unit", o->fanuc_unit,
                "FANUC detection unit: mm (linear) and deg (rotary) per count of a pitch error value (default 0.001)")
      ->check(CLI::Range(1e-6, 1.0));
  c->add_option("--residual-points", o->residual_points, "Grid values per axis for the residual before/after")
      ->check(CLI::Range(2, 1000));
  c->add_option("--report", o->report, "With --format: an HTML page of the before/after and what is not held");
  c->add_option("--threads", o->threads, "Threads for the residual (0: all cores)")->check(CLI::Range(0, 4096));
  c->footer(
      "Examples:\n"
      "  mtcal compensate -m examples/machines/vmc-3axis.yaml --format linuxcnc --out comp-vmc/\n"
      "  mtcal compensate -m examples/machines/hu40t-wCBXfYZt.yaml --params identified.yaml --format linuxcnc "
      "--linuxcnc-type 0 \\\n"
      "      --points 101 --range \"X=-300:300\" --out comp-hu40t/ --json\n"
      "  mtcal compensate -m examples/machines/vmc-3axis.yaml --format rrf --skew-reference-length 200 --out rrf/\n"
      "  mtcal compensate -m examples/machines/hu40t-wCBXfYZt.yaml --format etalon --out etalon/\n"
      "  mtcal errors -m examples/machines/hu40t-wCBXfYZt.yaml --params etalon/volcomp.etalon   # read back\n"
      "  mtcal compensate -m examples/machines/vmc-3axis.yaml --format fanuc --fanuc-unit 0.0001 --out fanuc/\n"
      "  mtcal compensate -m examples/machines/vmc-3axis.yaml --gcode examples/gcode/pocket.nc \\\n"
      "      --origin \"X=-40,Y=-25,Z=-400\" --out pocket-corrected.nc\n"
      "  mtcal compensate -m examples/machines/vmc-3axis.yaml --gcode examples/gcode/drill-plate.nc \\\n"
      "      --tool-table examples/gcode/tools.tbl --work-offset \"G54:X=-150,Y=-100,Z=-450\" \\\n"
      "      --g28 \"X=0,Y=0,Z=-10\" --out drill-corrected.nc   # G28 below the Z travel's end: room for the "
      "correction\n"
      "Tables: --out is a new (or empty) directory, written completely or not at all. Program: --out is a file.\n"
      "docs/compensation.md (targets, signs, limits), docs/compensation-gcode.md (the corrected program), "
      "docs/gcode.md (programs with cycles, offsets or LinuxCNC's RS274NGC: written expanded).");
  return {{c, [o] {
             if (!o->gcode.gcode.empty()) {
               if (!o->format.empty())
                 throw InputError({"--format", 0, ""}, "expected either --format (tables) or --gcode (a program)");
               return run_gcode_correction(o->gcode);
             }
             check_gcode_input_options(o->gcode.input, false);
             try {
               return run_tables(*o);
             } catch (const InputError& e) {
               rethrow_for_options(e, {{"points", "--points"}});  // a controller's table limit
             }
           }}};
}

}  // namespace mtcal::cli
