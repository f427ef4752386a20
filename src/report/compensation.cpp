#include "mtcal/report/compensation.hpp"

#include <fmt/format.h>

#include "mtcal/report/report.hpp"

namespace mtcal {

void write_compensation_report(const std::string& path, const std::string& command, const Machine& m,
                               const std::vector<std::pair<std::string, std::string>>& inputs,
                               const std::string& out_dir, const TargetOutput& out) {
  const CompensationSummary& s = out.summary;
  const ResidualSummary& r = s.residual;
  Report rep("Compensation for " + s.target, command);
  rep.set_machine(m);
  for (const auto& [label, file] : inputs) rep.add_input(label, file);
  rep.add_figure("max |e| before", fmt::format("{:.3f}", r.max_norm_before * 1e3), "µm");
  rep.add_figure("max |e| after", fmt::format("{:.3f}", r.max_norm_after * 1e3), "µm");
  rep.add_figure("VA before", fmt::format("{:.3f}", r.va_before * 1e3), "µm");
  rep.add_figure("VA after", fmt::format("{:.3f}", r.va_after * 1e3), "µm");
  for (const auto& w : s.warnings) rep.add_warning(w);

  rep.add_section("What was written");
  rep.add_paragraph(fmt::format("Target {}: the numbers are {}. Source of that rule: {}", s.target,
                                to_string(s.quantity), s.sign_source));
  std::vector<std::vector<std::string>> files;
  for (const auto& f : out.files)
    files.push_back({out_dir.empty() ? f.name : out_dir + "/" + f.name, std::to_string(f.text.size()), f.text.substr(0, f.text.find('\n'))});
  rep.add_table("Files", {"file", "bytes", "first line"}, files);

  rep.add_section("Error before and after");
  rep.add_paragraph(fmt::format(
      "Over {} configurations of the residual grid, each approached moving + and moving − on every axis; after = the "
      "machine commanded to the corrections the target's own rule gives (interpolation, held ends, direction).",
      r.configurations));
  nlohmann::json before = {{"type", "bar"},
                           {"name", "before"},
                           {"x", {"x", "y", "z", "|e|", "VA"}},
                           {"y",
                            {r.max_before[0] * 1e3, r.max_before[1] * 1e3, r.max_before[2] * 1e3,
                             r.max_norm_before * 1e3, r.va_before * 1e3}}};
  nlohmann::json after = {{"type", "bar"},
                          {"name", "after"},
                          {"x", {"x", "y", "z", "|e|", "VA"}},
                          {"y",
                           {r.max_after[0] * 1e3, r.max_after[1] * 1e3, r.max_after[2] * 1e3, r.max_norm_after * 1e3,
                            r.va_after * 1e3}}};
  rep.add_plot("Largest error per component, largest |e| and volumetric accuracy (µm), before and after",
               {{"data", {before, after}},
                {"layout", {{"barmode", "group"}, {"yaxis", {{"title", {{"text", "µm"}}}}}}}});
  std::vector<std::vector<std::string>> rows;
  for (const auto& n : s.not_compensated)
    rows.push_back(
        {n.what, fmt::format("{:.3f}", n.max_error * (n.unit == "mm" ? 1e3 : 1e6)), n.unit == "mm" ? "µm" : "µrad"});
  if (!rows.empty()) {
    rep.add_section("What the target cannot hold");
    rep.add_table("Each error alone over the residual grid", {"error", "largest effect", "unit"}, rows);
  }
  rep.write(path);
}

}  // namespace mtcal
