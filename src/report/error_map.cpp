#include "mtcal/report/error_map.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "mtcal/io/text/joints.hpp"
#include "mtcal/report/report.hpp"

namespace mtcal {

nlohmann::json error_cone_figure(const Machine& m, const std::vector<ConeSample>& samples,
                                 const std::vector<PlotMark>& marks, bool join_marks) {
  nlohmann::json x = nlohmann::json::array(), y = x, z = x, u = x, v = x, w = x, text = x;
  for (const auto& s : samples) {
    x.push_back(s.nominal.x());
    y.push_back(s.nominal.y());
    z.push_back(s.nominal.z());
    u.push_back(s.error.x() * 1e3);
    v.push_back(s.error.y() * 1e3);
    w.push_back(s.error.z() * 1e3);
    text.push_back(format_joint_values(m, s.q, ", "));
  }
  // Scale and colour from the errors, not from the spacing of the points (Plotly's "scaled" mode
  // makes cones vanish where 5-axis configurations put tool points close together): a cone of
  // the 95th-percentile error is 6 % of the workspace diagonal long ("raw": length = |e| ·
  // sizeref in mm), and the colour bar spans 0 to the 99th percentile so that one outlier does
  // not turn every other cone the same colour.
  std::vector<double> norms;
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  for (const auto& s : samples) {
    norms.push_back(s.error.norm() * 1e3);
    lo = lo.cwiseMin(s.nominal);
    hi = hi.cwiseMax(s.nominal);
  }
  auto percentile = [&](double p) {
    if (norms.empty()) return 0.0;
    std::vector<double> sorted = norms;
    const auto k = static_cast<std::size_t>(p * static_cast<double>(norms.size() - 1));
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(k), sorted.end());
    return sorted[k];
  };
  const double diagonal = samples.empty() ? 1.0 : std::max((hi - lo).norm(), 1.0);
  const double p95 = std::max(percentile(0.95), 1e-9), p99 = std::max(percentile(0.99), 1e-9);
  nlohmann::json cones = {{"type", "cone"},
                          {"x", x},
                          {"y", y},
                          {"z", z},
                          {"u", u},
                          {"v", v},
                          {"w", w},
                          {"text", text},
                          {"sizemode", "raw"},
                          {"sizeref", 0.06 * diagonal / p95},
                          {"anchor", "tail"},
                          {"colorscale", "Viridis"},
                          {"reversescale", true},
                          {"cmin", 0.0},
                          {"cmax", p99},
                          {"colorbar", {{"title", {{"text", "|e| (µm)"}}}, {"len", 0.8}}},
                          {"hovertemplate", "%{text}<br>|e| %{norm:.2f} µm<extra></extra>"},
                          {"name", "error"}};
  nlohmann::json data = nlohmann::json::array({cones});
  if (!marks.empty()) {
    nlohmann::json mx = nlohmann::json::array(), my = mx, mz = mx, label = mx;
    for (const auto& mk : marks) {
      mx.push_back(mk.nominal.x());
      my.push_back(mk.nominal.y());
      mz.push_back(mk.nominal.z());
      label.push_back(mk.label);
    }
    data.push_back({{"type", "scatter3d"},
                    {"mode", join_marks ? "lines+markers+text" : "markers+text"},
                    {"x", mx},
                    {"y", my},
                    {"z", mz},
                    {"marker", {{"size", 8}, {"color", "red"}}},
                    {"line", {{"color", "red"}, {"width", 4}}},
                    {"text", label},
                    {"name", "marked"}});
  }
  nlohmann::json layout = machine_scene_layout();
  layout["margin"] = {{"l", 0}, {"r", 0}, {"t", 30}, {"b", 0}};
  layout["annotations"] = {
      {{"text", fmt::format("cone length: {:.3g} mm per µm (95th percentile {:.3g} µm = 6 % of the "
                            "workspace diagonal); colour 0 to {:.3g} µm (99th percentile)",
                            0.06 * diagonal / p95, p95, p99)},
       {"xref", "paper"},
       {"yref", "paper"},
       {"x", 0},
       {"y", 1.0},
       {"showarrow", false},
       {"xanchor", "left"},
       {"yanchor", "bottom"},
       {"font", {{"size", 11}}}}};
  return {{"data", data}, {"layout", layout}};
}

namespace {
constexpr std::size_t kMapPoints = 3000;        // cones in the 3D error map
constexpr std::size_t kMagnitudes = 2'000'000;  // values behind the distribution
constexpr std::size_t kLargest = 10;
}  // namespace

ErrorStreamReport::ErrorStreamReport(const ErrorModel& model, std::size_t count)
    : model_(model),
      count_(count),
      stride_(std::max<std::size_t>(1, (count + kMapPoints - 1) / kMapPoints)),
      magnitude_stride_(std::max<std::size_t>(1, (count + kMagnitudes - 1) / kMagnitudes)) {}

void ErrorStreamReport::add(const ErrorChunk& c) {
  for (std::size_t r = 0; r < c.size(); ++r) add(c.first + r, &c.q[r * c.axes], &c.error[r * 6]);
}

void ErrorStreamReport::add(std::size_t index, const double* q, const double* e) {
  const std::size_t n = model_.axis_count();
  const double t = std::hypot(e[0], e[1], e[2]);
  if (index % magnitude_stride_ == 0) magnitudes_.push_back(static_cast<float>(t * 1e3));
  const bool sample = index % stride_ == 0;
  const bool large =
      largest_.size() < kLargest || t > std::hypot(largest_.back().e[0], largest_.back().e[1], largest_.back().e[2]);
  if (!sample && !large) return;
  Sample s;
  s.q.assign(q, q + n);
  std::copy(e, e + 6, s.e);
  s.nominal = model_.nominal_pose(s.q).t;
  if (sample) samples_.push_back(s);
  if (large) {
    largest_.push_back(s);
    std::sort(largest_.begin(), largest_.end(), [](const Sample& a, const Sample& b) {
      return std::hypot(a.e[0], a.e[1], a.e[2]) > std::hypot(b.e[0], b.e[1], b.e[2]);
    });
    if (largest_.size() > kLargest) largest_.pop_back();
  }
}

void ErrorStreamReport::write(const std::string& path, const ReportSources& sources) const {
  const Machine& m = model_.machine();
  Report r("Volumetric error of " + m.name, sources.command);
  r.set_machine(m);
  for (const auto& p : sources.parameter_files) r.add_input("parameter file", p);
  if (!sources.points_file.empty()) r.add_input("configurations", sources.points_file);
  if (!sources.grid.empty()) r.add_figure("grid", sources.grid, "mm, deg");
  r.add_figure("configurations", fmt::format("{}", count_), "");
  r.add_figure("tool length", fmt::format("{:g}", m.tool.length), "mm");
  auto config_text = [&](const std::vector<double>& q) { return format_joint_values(m, q, ", "); };
  if (!largest_.empty()) {
    const auto& top = largest_.front();
    r.add_figure("largest translational error", fmt::format("{:.3f}", std::hypot(top.e[0], top.e[1], top.e[2]) * 1e3),
                 "µm at " + config_text(top.q));
  }
  if (stride_ > 1)
    r.add_warning(
        fmt::format("The error map shows every {}th of the {} configurations ({} cones); the largest "
                    "errors and the figures above use all of them.",
                    stride_, count_, samples_.size()));

  r.add_section("Error map");
  r.add_paragraph(
      "Each cone is the translational error of the tool relative to the workpiece (dx, dy, dz) at the "
      "nominal tool point, in the workpiece frame; colour and size show its magnitude in µm. The red "
      "marker is the configuration with the largest error.");
  std::vector<ConeSample> cones;
  for (const auto& s : samples_) cones.push_back({s.q, s.nominal, Vec3(s.e[0], s.e[1], s.e[2])});
  std::vector<PlotMark> marks;
  if (!largest_.empty()) marks.push_back({"largest", largest_.front().nominal});
  r.add_plot("Translational error vectors over the evaluated configurations (µm, at nominal tool points in mm)",
             error_cone_figure(m, cones, marks));

  r.add_section("Distribution");
  // Histogram binned here so that the page stays small for millions of configurations.
  const float hi = magnitudes_.empty() ? 1.0f : *std::max_element(magnitudes_.begin(), magnitudes_.end());
  const int bins = 50;
  std::vector<std::size_t> counts(bins, 0);
  for (float mval : magnitudes_) {
    const int b = hi > 0 ? std::min(bins - 1, static_cast<int>(mval / hi * bins)) : 0;
    ++counts[static_cast<std::size_t>(b)];
  }
  nlohmann::json centres = nlohmann::json::array(), cnt = nlohmann::json::array();
  for (int b = 0; b < bins; ++b) {
    centres.push_back((b + 0.5) * hi / bins);
    cnt.push_back(counts[static_cast<std::size_t>(b)]);
  }
  r.add_plot(magnitude_stride_ > 1
                 ? fmt::format("Magnitude of the translational error, every {}th configuration", magnitude_stride_)
                 : std::string("Magnitude of the translational error over all configurations"),
             {{"data", {{{"type", "bar"}, {"x", centres}, {"y", cnt}, {"name", "configurations"}}}},
              {"layout",
               {{"xaxis", {{"title", {{"text", "|(dx, dy, dz)| (µm)"}}}}},
                {"yaxis", {{"title", {{"text", "configurations"}}}}},
                {"bargap", 0.02}}}});

  r.add_section("Largest errors");
  std::vector<std::vector<std::string>> rows;
  for (const auto& s : largest_)
    rows.push_back({config_text(s.q), fmt::format("{:.3f}", s.e[0] * 1e3), fmt::format("{:.3f}", s.e[1] * 1e3),
                    fmt::format("{:.3f}", s.e[2] * 1e3),
                    fmt::format("{:.3f}", std::hypot(s.e[0], s.e[1], s.e[2]) * 1e3),
                    fmt::format("{:.2f}", s.e[3] * 1e6), fmt::format("{:.2f}", s.e[4] * 1e6),
                    fmt::format("{:.2f}", s.e[5] * 1e6)});
  r.add_table("The configurations with the largest translational errors (workpiece frame)",
              {"configuration (mm, deg)", "dx (µm)", "dy (µm)", "dz (µm)", "|e| (µm)", "rx (µrad)", "ry (µrad)",
               "rz (µrad)"},
              rows);
  r.write(path);
}

void write_parameters_report(const std::string& path, const Machine& m, std::span<const ErrorParameter> listed,
                             std::size_t all, bool nonzero_only, const ReportSources& sources) {
  Report r("Error parameters of " + m.name, sources.command);
  r.set_machine(m);
  for (const auto& p : sources.parameter_files) r.add_input("parameter file", p);
  std::vector<std::vector<std::string>> rows;
  nlohmann::json names = nlohmann::json::array(), values = names;
  for (const auto& p : listed) {
    rows.push_back({p.name, std::string(to_string(p.error.kind)), p.unit, fmt::format("{:.9g}", p.value)});
    if (p.error.kind != ErrorKind::Motion && p.value != 0.0) {
      names.push_back(p.name);
      values.push_back(p.value * (is_rotation(p.error.component) ? 1e6 : 1e3));
    }
  }
  r.add_figure("parameters", fmt::format("{} of {}", listed.size(), all), nonzero_only ? "(non-zero)" : "");
  r.add_section("Location and mounting errors");
  r.add_plot("Location and mounting errors (µm for translations, µrad for rotations)",
             {{"data", {{{"type", "bar"}, {"x", names}, {"y", values}, {"name", "value"}}}},
              {"layout", {{"yaxis", {{"title", {{"text", "µm or µrad"}}}}}}}});
  r.add_section("Every parameter");
  r.add_table("Parameters in internal units (mm, rad); motion-error coefficients per mm^i or rad^i",
              {"name", "kind", "unit", "value"}, rows);
  r.write(path);
}

void write_effects_report(const std::string& path, const Machine& m, std::span<const double> at,
                          const std::string& around, std::span<const ErrorEffect> effects,
                          const ReportSources& sources) {
  std::vector<std::vector<std::string>> rows;
  nlohmann::json bar_names = nlohmann::json::array(), bar_values = nlohmann::json::array();
  for (const auto& e : effects) {
    const auto& v = e.effect;
    const std::string name = e.error.str();
    rows.push_back({name, std::string(to_string(e.error.kind)), e.rotational ? "1 µrad" : "1 µm",
                    fmt::format("{:.4g}", v[0]), fmt::format("{:.4g}", v[1]), fmt::format("{:.4g}", v[2]),
                    fmt::format("{:.4g}", v[3]), fmt::format("{:.4g}", v[4]), fmt::format("{:.4g}", v[5])});
    bar_names.push_back(name);
    bar_values.push_back(std::hypot(v[0], v[1], v[2]));
  }
  Report r("Single-error effects on " + m.name, sources.command);
  r.set_machine(m);
  for (const auto& p : sources.parameter_files) r.add_input("parameter file", p);
  r.add_figure("configuration", format_joint_values(m, std::vector<double>(at.begin(), at.end()), ", "), "mm, deg");
  r.add_figure("tool length", fmt::format("{:g}", m.tool.length), "mm");
  r.add_figure("linearised about", around, "machine");
  r.add_section("Effect of each error on the tool point");
  r.add_plot("Size of the tool-point displacement per 1 µm or 1 µrad of each error (µm)",
             {{"data", {{{"type", "bar"}, {"x", bar_names}, {"y", bar_values}, {"name", "|(dx, dy, dz)|"}}}},
              {"layout", {{"yaxis", {{"title", {{"text", "µm per µm or µrad"}}}}}}}});
  r.add_table("Effect per 1 µm (translational errors) or 1 µrad (rotational errors), workpiece frame",
              {"error", "kind", "per", "dx (µm)", "dy (µm)", "dz (µm)", "rx (µrad)", "ry (µrad)", "rz (µrad)"}, rows);
  r.write(path);
}

}  // namespace mtcal
