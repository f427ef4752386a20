// mtcal toolpath: the volumetric error along a G-code program (Fletcher 2009, 4.3).
#include <algorithm>
#include <cmath>
#include <iostream>
#include <iterator>
#include <memory>
#include <optional>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "common.hpp"
#include "mtcal/evaluation/toolpath.hpp"
#include "mtcal/io/files.hpp"
#include "mtcal/io/gcode.hpp"
#include "mtcal/io/joints.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/report/report.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/parse.hpp"

namespace mtcal::cli {
namespace {

using json = nlohmann::ordered_json;

constexpr std::size_t kPlotPoints = 20000;  // points kept for the report's plots
constexpr std::size_t kArrows = 300;        // error vectors drawn along the 3D path

struct ToolpathCliOptions {
  ModelOptions model;
  std::string gcode, origin, out, report;
  double step = 0.5, angle_step = 0.5;
  bool skip_rapids = false, json_out = false, no_travel_check = false, no_direction = false;
  int threads = 0;
};

// "X=100,Z=-450" -> program zero in machine axis positions (mm, deg); letters of the machine only.
GcodePosition parse_origin(const Machine& m, const std::string& spec) {
  GcodePosition o{};
  if (spec.empty()) return o;
  std::array<bool, 6> seen{};
  for (const auto& item : split_list(spec)) {
    const auto eq = item.find('=');
    if (eq != 1) throw InputError({"--origin", 0, item}, "expected AXIS=VALUE items separated by commas, found '" + item + "'");
    const char letter = item[0];
    const auto slot = std::find(std::begin(kGcodeAxes), std::end(kGcodeAxes), letter) - std::begin(kGcodeAxes);
    if (slot == 6 || !m.axis_index(letter))
      throw InputError({"--origin", 0, item}, fmt::format("axis '{}' is not in topology {}", letter, m.topology.chain));
    const auto s = static_cast<std::size_t>(slot);
    if (seen[s]) throw InputError({"--origin", 0, item}, fmt::format("axis '{}' given twice", letter));
    seen[s] = true;
    const auto v = parse_number(item.substr(2));
    if (!v) throw InputError({"--origin", 0, item}, "expected a number, found '" + item.substr(2) + "'");
    o[s] = *v;
  }
  return o;
}

// Every stride-th point, the stride doubling whenever the kept points would exceed kPlotPoints,
// so that a program of unknown length leaves an evenly thinned path.
class PlotSampler {
 public:
  explicit PlotSampler(std::size_t axes) : axes_(axes) {}
  void add(const ToolpathChunk& c) {
    for (std::size_t i = 0; i < c.size(); ++i, ++seen_) {
      if (seen_ % stride_) continue;
      if (s_.size() == kPlotPoints) thin();
      if (seen_ % stride_) continue;
      s_.push_back(c.s[i]);
      line_.push_back(c.line[i]);
      q_.insert(q_.end(), c.q.begin() + static_cast<std::ptrdiff_t>(i * axes_),
                c.q.begin() + static_cast<std::ptrdiff_t>((i + 1) * axes_));
      e_.insert(e_.end(), c.error.begin() + static_cast<std::ptrdiff_t>(i * 6),
                c.error.begin() + static_cast<std::ptrdiff_t>(i * 6 + 3));
    }
  }
  std::size_t size() const { return s_.size(); }
  std::size_t stride() const { return stride_; }
  std::vector<double> s_, q_, e_;
  std::vector<int> line_;

 private:
  void thin() {
    std::size_t j = 0;
    for (std::size_t i = 0; i < s_.size(); i += 2, ++j) {
      s_[j] = s_[i];
      line_[j] = line_[i];
      std::copy_n(&q_[i * axes_], axes_, &q_[j * axes_]);
      std::copy_n(&e_[i * 3], 3, &e_[j * 3]);
    }
    s_.resize(j);
    line_.resize(j);
    q_.resize(j * axes_);
    e_.resize(j * 3);
    stride_ *= 2;
  }
  std::size_t axes_, stride_ = 1, seen_ = 0;
};

const char* kRangeUnits[6] = {"mm", "mm", "mm", "rad", "rad", "rad"};

void write_report(const ToolpathCliOptions& o, const ErrorModel& model, const ToolpathSummary& sum,
                  const PlotSampler& p) {
  const Machine& m = model.machine();
  const std::size_t n = m.axes.size();
  Report r("Tool-path simulation: " + o.gcode, command_line());
  r.set_machine(m);
  r.add_input("G-code program", o.gcode);
  for (const auto& f : o.model.params) r.add_input("parameter file", f);
  r.add_figure("points", fmt::format("{}", sum.points), fmt::format("along {} blocks, every ≤ {:g} mm", sum.blocks, o.step));
  r.add_figure("path length", fmt::format("{:.3f}", sum.path_length), o.skip_rapids ? "mm (rapids left out)" : "mm");
  if (sum.points)
    r.add_figure("largest |(dx, dy, dz)|", fmt::format("{:.3f}", sum.max_error * 1e3),
                 fmt::format("µm at line {} ({})", sum.max_line, format_joint_values(m, sum.max_at, ", ")));
  if (sum.counts.ignored_words)
    r.add_warning(fmt::format("{} S, T, M words and G40 G49 G80 G94 were read and ignored: they move no axis.",
                              sum.counts.ignored_words));
  if (p.stride() > 1)
    r.add_warning(fmt::format("The plots show every {}th of the {} points; the figures above use all of them.",
                              p.stride(), sum.points));
  if (o.no_direction) r.add_warning("Evaluated without directions of motion: reversal terms are zero.");

  r.add_section("Error along the path");
  r.add_paragraph("The path is the nominal tool point in the workpiece frame (mm), coloured by the translational "
                  "error |(dx, dy, dz)| in µm; red lines show the error vectors (dx, dy, dz), magnified, at evenly spaced points. "
                  "Fletcher et al. 2009, section 4.3.");
  nlohmann::json x = nlohmann::json::array(), y = x, z = x, mag = x, text = x;
  std::vector<Vec3> pts(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    pts[i] = model.nominal_pose(std::span<const double>(&p.q_[i * n], n)).t;
    const double* e = &p.e_[i * 3];
    x.push_back(pts[i].x());
    y.push_back(pts[i].y());
    z.push_back(pts[i].z());
    const double um = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]) * 1e3;
    mag.push_back(um);
    text.push_back(fmt::format("line {}, s {:.3f} mm<br>|e| {:.2f} µm", p.line_[i], p.s_[i], um));
  }
  nlohmann::json path = {{"type", "scatter3d"}, {"mode", "lines"}, {"x", x}, {"y", y}, {"z", z}, {"text", text},
                         {"line", {{"width", 5}, {"color", mag}, {"colorscale", "Viridis"}, {"showscale", true},
                                   {"colorbar", {{"title", {{"text", "|e| µm"}}}}}}},
                         {"hovertemplate", "%{text}<extra></extra>"},
                         {"name", "path"}};
  // Error vectors as line segments from the path, the largest a twentieth of the path's extent
  // long (a scale in mm per µm); lines, unlike cones, keep a visible size along a dense path.
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  double big = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    lo = lo.cwiseMin(pts[i]);
    hi = hi.cwiseMax(pts[i]);
    big = std::max(big, mag[i].get<double>());
  }
  const double extent = p.size() ? (hi - lo).norm() : 0.0;
  const double scale = big > 0 && extent > 0 ? extent / 20 / big : 0.0;  // mm per µm
  nlohmann::json ax = nlohmann::json::array(), ay = ax, az = ax;
  const std::size_t every = std::max<std::size_t>(1, p.size() / kArrows);
  for (std::size_t i = 0; i < p.size(); i += every) {
    const Vec3 e(p.e_[i * 3] * 1e3, p.e_[i * 3 + 1] * 1e3, p.e_[i * 3 + 2] * 1e3);
    const Vec3 tip = pts[i] + scale * e;
    // From the path point to the tip, then a gap before the next segment.
    ax.insert(ax.end(), {pts[i].x(), tip.x(), nullptr});
    ay.insert(ay.end(), {pts[i].y(), tip.y(), nullptr});
    az.insert(az.end(), {pts[i].z(), tip.z(), nullptr});
  }
  nlohmann::json arrows = {{"type", "scatter3d"}, {"mode", "lines"}, {"x", ax}, {"y", ay}, {"z", az},
                           {"line", {{"width", 2}, {"color", "firebrick"}}}, {"hoverinfo", "skip"},
                           {"name", "error vectors"}};
  r.add_plot(fmt::format("Tool path (mm, workpiece frame) coloured by |error| (µm), with the error vectors (red, "
                         "1 µm drawn as {:.3g} mm)", scale),
             {{"data", {path, arrows}},
              {"layout", {{"scene", {{"xaxis", {{"title", {{"text", "x (mm)"}}}}},
                                     {"yaxis", {{"title", {{"text", "y (mm)"}}}}},
                                     {"zaxis", {{"title", {{"text", "z (mm)"}}}}},
                                     {"aspectmode", "data"}}},
                          {"showlegend", false}}}});

  nlohmann::json s = nlohmann::json::array();
  std::array<nlohmann::json, 3> comp{nlohmann::json::array(), nlohmann::json::array(), nlohmann::json::array()};
  for (std::size_t i = 0; i < p.size(); ++i) {
    s.push_back(p.s_[i]);
    for (std::size_t c = 0; c < 3; ++c) comp[c].push_back(p.e_[i * 3 + c] * 1e3);
  }
  nlohmann::json traces = nlohmann::json::array();
  const char* names[3] = {"dX", "dY", "dZ"};
  for (std::size_t c = 0; c < 3; ++c)
    traces.push_back({{"type", "scattergl"}, {"mode", "lines"}, {"x", s}, {"y", comp[c]}, {"name", names[c]}});
  traces.push_back({{"type", "scattergl"}, {"mode", "lines"}, {"x", s}, {"y", mag}, {"name", "|e|"},
                    {"line", {{"color", "black"}}}});
  r.add_plot("Error components and magnitude (µm) along the path (mm), as Fletcher 2009's figure 7",
             {{"data", traces},
              {"layout", {{"xaxis", {{"title", {{"text", "path length (mm)"}}}}},
                          {"yaxis", {{"title", {{"text", "error (µm)"}}}}}}}});

  r.add_section("Ranges");
  std::vector<std::vector<std::string>> rows;
  for (std::size_t c = 0; c < 6; ++c)
    rows.push_back({kOutputKeys[c], kRangeUnits[c], fmt::format("{:.6g}", sum.range[c][0]),
                    fmt::format("{:.6g}", sum.range[c][1])});
  r.add_table("Smallest and largest value of each error component over every point", {"component", "unit", "min", "max"},
              rows);
  r.write(o.report);
}

int run_toolpath(const ToolpathCliOptions& o) {
  {
    auto inputs = model_inputs(o.model);
    inputs.push_back(o.gcode);
    check_outputs(inputs, {o.out, o.report});
  }
  const Machine m = load(o.model);
  const ErrorModel model(m);
  const std::size_t n = m.axes.size();

  ToolpathOptions opt;
  opt.step = o.step;
  opt.angle_step = o.angle_step;
  opt.skip_rapids = o.skip_rapids;
  opt.origin = parse_origin(m, o.origin);
  opt.directions = !o.no_direction;
  opt.travel_check = !o.no_travel_check;
  opt.batch.threads = o.threads;
  ToolpathInterpolator check(m, opt);  // refuses a bad --step before reading anything

  std::unique_ptr<AtomicFile> file;
  if (!o.out.empty()) {
    file = std::make_unique<AtomicFile>(o.out);
    std::string header = "line,n,motion,s";
    for (const auto& ax : m.axes) header += std::string(",") + ax.letter;
    for (const char* k : kOutputKeys) header += std::string(",") + k;
    file->stream() << header << "\n";
  }
  if (!o.report.empty()) AtomicFile probe(o.report);  // refuse a bad report path before the work

  const std::string text = read_text_file(o.gcode, "G-code program");
  GcodeOptions go;
  go.axes.clear();
  for (const auto& ax : m.axes) go.axes += ax.letter;
  GcodeReader reader(text, o.gcode, go);

  std::vector<double> inv(n);
  for (std::size_t k = 0; k < n; ++k) inv[k] = 1.0 / joint_unit_factor(m.axes[k]);
  std::optional<PlotSampler> sampler;
  if (!o.report.empty()) sampler.emplace(n);
  fmt::memory_buffer buf;
  const auto summary = simulate_toolpath(model, reader, opt, [&](const ToolpathChunk& c) {
    if (sampler) sampler->add(c);
    if (!file) return;
    buf.clear();
    auto out = std::back_inserter(buf);
    for (std::size_t i = 0; i < c.size(); ++i) {
      fmt::format_to(out, "{},", c.line[i]);
      if (c.n[i] >= 0) fmt::format_to(out, "{}", c.n[i]);
      fmt::format_to(out, ",{},{:.6f}", to_string(c.motion[i]), c.s[i]);
      for (std::size_t k = 0; k < n; ++k) fmt::format_to(out, ",{:.12g}", c.q[i * n + k] * inv[k]);
      for (std::size_t e = 0; e < 6; ++e) fmt::format_to(out, ",{:.9e}", c.error[i * 6 + e]);
      buf.push_back('\n');
    }
    file->stream().write(buf.data(), static_cast<std::streamsize>(buf.size()));
  });
  if (file) file->commit();
  if (sampler) write_report(o, model, summary, *sampler);

  if (o.json_out) {
    json j;
    j["points"] = summary.points;
    j["blocks"] = summary.blocks;
    j["path_length"] = summary.path_length;
    j["ignored_words"] = summary.counts.ignored_words;
    j["rapids_skipped"] = summary.rapids_skipped;
    const json at = summary.max_at.empty() ? json::object() : joint_json(m, summary.max_at);
    j["max_error"] = {{"value", summary.max_error},
                      {"line", summary.points ? json(summary.max_line) : json(nullptr)},
                      {"at", at}};
    json range = json::object();
    for (std::size_t c = 0; c < 6; ++c)
      range[kOutputKeys[c]] = summary.points ? json::array({summary.range[c][0], summary.range[c][1]})
                                             : json::array({nullptr, nullptr});
    j["range"] = range;
    if (!o.out.empty()) j["out"] = o.out;
    if (!o.report.empty()) j["report"] = o.report;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::cout << fmt::format("machine      {} ({})\n", m.name, m.topology.chain);
  std::cout << fmt::format("program      {}: {} lines, {} blocks that move{}\n", o.gcode, summary.counts.lines,
                           summary.counts.moves,
                           summary.counts.ignored_words
                               ? fmt::format(", {} S/T/M and no-op G words ignored", summary.counts.ignored_words)
                               : std::string());
  std::cout << fmt::format("points       {} along {} blocks, {:.3f} mm of path{}\n", summary.points, summary.blocks,
                           summary.path_length,
                           summary.rapids_skipped ? fmt::format(" ({} rapids left out)", summary.rapids_skipped) : "");
  if (summary.points) {
    std::cout << fmt::format("largest translational error  {:.6f} mm  at line {} ({})\n", summary.max_error,
                             summary.max_line, format_joint_values(m, summary.max_at));
    for (std::size_t c = 0; c < 6; ++c)
      std::cout << fmt::format("{} {:>16.9g} .. {:<16.9g} {}\n", kOutputKeys[c], summary.range[c][0],
                               summary.range[c][1], kRangeUnits[c]);
  }
  if (!o.out.empty()) std::cout << "wrote        " << o.out << "\n";
  if (!o.report.empty()) std::cout << "report       " << o.report << "\n";
  return 0;
}

}  // namespace

// The library names its parameters; the user typed options.
int run_toolpath_command(const ToolpathCliOptions& o) {
  try {
    return run_toolpath(o);
  } catch (const InputError& e) {
    rethrow_for_options(e, {{"step", "--step"}, {"angle step", "--angle-step"}});
  }
}

std::vector<Command> add_toolpath_commands(CLI::App& app) {
  auto o = std::make_shared<ToolpathCliOptions>();
  auto* c = app.add_subcommand(
      "toolpath",
      "Simulate a G-code program (G0 G1 G2 G3, G17-G19, G20/G21, G90/G91): points along the path every --step mm "
      "and the volumetric error of the tool relative to the workpiece at each (Fletcher 2009, 4.3). See "
      "docs/toolpath.md");
  add_model_options(c, o->model);
  c->add_option("--gcode", o->gcode, "G-code program (RS274 subset, docs/toolpath.md); axis words only for the "
                                     "machine's axes")
      ->required();
  c->add_option("--step", o->step, "Largest X Y Z path length between points, mm (default 0.5)")->check(kFinite);
  c->add_option("--angle-step", o->angle_step, "Largest A B C motion between points, deg (default 0.5)")
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
              "Machine-readable summary: points, blocks, path_length, ignored_words, rapids_skipped, max_error "
              "{value, line, at}, range {dx: [min, max], ...}, out, report");
  c->add_option("--report", o->report,
                "Write an HTML report: the path in 3D coloured by |error| with the error vectors, the errors along the path");
  return {{c, [o] { return run_toolpath_command(*o); }}};
}

}  // namespace mtcal::cli
