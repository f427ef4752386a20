#include "mtcal/report/toolpath.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "mtcal/io/points/error_csv.hpp"
#include "mtcal/io/text/joints.hpp"
#include "mtcal/report/report.hpp"

namespace mtcal {
namespace {

constexpr std::size_t kArrows = 300;  // error vectors drawn along the 3D path
const char* kRangeUnits[6] = {"mm", "mm", "mm", "rad", "rad", "rad"};

}  // namespace

ToolpathPlotSampler::ToolpathPlotSampler(std::size_t axes, std::size_t limit) : axes_(axes), limit_(limit) {}

void ToolpathPlotSampler::add(const ToolpathChunk& c) {
  for (std::size_t i = 0; i < c.size(); ++i, ++seen_) {
    if (seen_ % stride_) continue;
    if (s_.size() == limit_) thin();
    if (seen_ % stride_) continue;
    s_.push_back(c.s[i]);
    line_.push_back(c.line[i]);
    q_.insert(q_.end(), c.q.begin() + static_cast<std::ptrdiff_t>(i * axes_),
              c.q.begin() + static_cast<std::ptrdiff_t>((i + 1) * axes_));
    e_.insert(e_.end(), c.error.begin() + static_cast<std::ptrdiff_t>(i * 6),
              c.error.begin() + static_cast<std::ptrdiff_t>(i * 6 + 3));
  }
}

void ToolpathPlotSampler::thin() {
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

void write_toolpath_report(const std::string& file, const ErrorModel& model, const ToolpathSummary& sum,
                           const ToolpathPlotSampler& p, const ToolpathReportInputs& o, const ReportSources& sources) {
  const Machine& m = model.machine();
  const std::size_t n = m.axes.size();
  Report r("Tool-path simulation: " + o.program, sources.command);
  r.set_machine(m);
  if (o.program_file) r.add_input("G-code program", o.program);
  for (const auto& f : sources.parameter_files) r.add_input("parameter file", f);
  r.add_figure("points", fmt::format("{}", sum.points),
               fmt::format("along {} blocks, every ≤ {:g} mm", sum.blocks, o.step));
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
  if (!o.directions) r.add_warning("Evaluated without directions of motion: reversal terms are zero.");

  r.add_section("Error along the path");
  r.add_paragraph(
      "The path is the nominal tool point in the workpiece frame (mm), coloured by the translational "
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
  nlohmann::json path = {{"type", "scatter3d"},
                         {"mode", "lines"},
                         {"x", x},
                         {"y", y},
                         {"z", z},
                         {"text", text},
                         {"line",
                          {{"width", 5},
                           {"color", mag},
                           {"colorscale", "Viridis"},
                           {"showscale", true},
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
  nlohmann::json arrows = {{"type", "scatter3d"},
                           {"mode", "lines"},
                           {"x", ax},
                           {"y", ay},
                           {"z", az},
                           {"line", {{"width", 2}, {"color", "firebrick"}}},
                           {"hoverinfo", "skip"},
                           {"name", "error vectors"}};
  r.add_plot(fmt::format("Tool path (mm, workpiece frame) coloured by |error| (µm), with the error vectors (red, "
                         "1 µm drawn as {:.3g} mm)",
                         scale),
             {{"data", {path, arrows}}, {"layout", machine_scene_layout()}});

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
  traces.push_back({{"type", "scattergl"},
                    {"mode", "lines"},
                    {"x", s},
                    {"y", mag},
                    {"name", "|e|"},
                    {"line", {{"color", "black"}}}});
  r.add_plot("Error components and magnitude (µm) along the path (mm), as Fletcher 2009's figure 7",
             {{"data", traces},
              {"layout",
               {{"xaxis", {{"title", {{"text", "path length (mm)"}}}}},
                {"yaxis", {{"title", {{"text", "error (µm)"}}}}}}}});

  r.add_section("Ranges");
  std::vector<std::vector<std::string>> rows;
  for (std::size_t c = 0; c < 6; ++c)
    rows.push_back({kErrorKeys[c], kRangeUnits[c], fmt::format("{:.6g}", sum.range[c][0]),
                    fmt::format("{:.6g}", sum.range[c][1])});
  r.add_table("Smallest and largest value of each error component over every point",
              {"component", "unit", "min", "max"}, rows);
  r.write(file);
}

}  // namespace mtcal
