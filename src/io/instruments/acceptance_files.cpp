// Acceptance-report metadata and tolerance files (io/instruments/acceptance_files.hpp).
#include "mtcal/io/instruments/acceptance_files.hpp"

#include <yaml-cpp/yaml.h>

#include "mtcal/io/system/files.hpp"
#include "../text/yaml_reader.hpp"

namespace mtcal {

using namespace detail::yaml;

namespace {

YAML::Node load(std::string_view text, const std::string& source) {
  try {
    return YAML::Load(std::string(text));
  } catch (const YAML::Exception& e) {
    throw InputError({source, e.mark.line + 1, ""}, "not valid YAML: " + e.msg);
  }
}

int line_of(const YAML::Node& n) { return n.IsDefined() ? n.Mark().line + 1 : 0; }

}  // namespace

ReportMetadata parse_report_metadata(std::string_view yaml_text, const std::string& source) {
  const YAML::Node root = load(yaml_text, source);
  const Ctx ctx{source, ""};
  if (!root.IsDefined() || root.IsNull())
    throw InputError({source, 0, ""}, "expected a map of metadata fields, found nothing");
  ReportMetadata m;
  for (const auto& [key, value] : entries(root, ctx, {}, false)) {
    const Ctx kc = ctx.child(key);
    m.set(key, text(value, kc), source, line_of(value));
  }
  return m;
}

ReportMetadata read_report_metadata(const std::string& path) {
  return parse_report_metadata(read_text_file(path, "metadata file"), path);
}

namespace {

Tolerances limits(const YAML::Node& n, const Ctx& ctx, std::initializer_list<std::string_view> quantities,
                  double scale) {
  Tolerances t;
  for (const auto& [q, v] : entries(n, ctx, quantities)) {
    const Ctx qc = ctx.child(q);
    const double x = number(v, qc);
    if (x < 0) qc.fail(v, "expected a permitted value >= 0, found " + describe(v));
    t.set(q, x * scale);
  }
  return t;
}

}  // namespace

Tolerances ToleranceFile::iso230_2_for(const std::string& axis) const {
  if (auto it = iso230_2.find(axis); it != iso230_2.end()) return it->second;
  if (auto it = iso230_2.find("any"); it != iso230_2.end()) return it->second;
  return {};
}

ToleranceFile parse_tolerance_file(std::string_view yaml_text, const std::string& source) {
  const YAML::Node root = load(yaml_text, source);
  const Ctx ctx{source, ""};
  if (!root.IsDefined() || root.IsNull())
    throw InputError({source, 0, ""}, "expected a map of tolerances, found nothing");
  const Entries top = entries(root, ctx, {"unit", "iso230-2", "iso230-4", "volumetric"}, false);
  double scale = 1;  // to µm
  if (top.count("unit")) {
    const std::string u = text(top["unit"], ctx.child("unit"));
    if (u == "mm")
      scale = 1000;
    else if (u != "um" && u != "µm")
      ctx.child("unit").fail(top["unit"], "expected um or mm, found '" + printable(u) + "'");
  }
  ToleranceFile f;
  if (top.count("iso230-2")) {
    const Ctx sc = ctx.child("iso230-2");
    for (const auto& [axis, n] : entries(top["iso230-2"], sc, {}))
      f.iso230_2[axis] = limits(n, sc.child(axis), {"A", "E", "M", "R", "B"}, scale);
  }
  if (top.count("iso230-4")) f.iso230_4 = limits(top["iso230-4"], ctx.child("iso230-4"), {"G", "F", "H"}, scale);
  if (top.count("volumetric"))
    f.volumetric = limits(top["volumetric"], ctx.child("volumetric"), {"VA", "VAx", "VAy", "VAz"}, scale);
  return f;
}

ToleranceFile read_tolerance_file(const std::string& path) {
  return parse_tolerance_file(read_text_file(path, "tolerance file"), path);
}

std::map<std::string, ToleranceBand> history_figure_bands(const ToleranceFile& f,
                                                          const std::vector<std::string>& axes) {
  // The names record_from_result gives the figures (docs/history.md, "What is recorded") and
  // which acceptance quantity limits each (docs/reports.md, "Tolerances and the verdict").
  std::map<std::string, ToleranceBand> out;
  auto iso230_2 = [&](const Tolerances& t, const std::string& suffix) {
    for (const auto& [q, limit] : t.limits) out[q + suffix] = ToleranceBand::at_most(limit);
  };
  for (const auto& [axis, t] : f.iso230_2)
    if (axis != "any") iso230_2(t, "_" + axis);
  if (const auto any = f.iso230_2.find("any"); any != f.iso230_2.end()) {
    for (const auto& axis : axes)
      if (!f.iso230_2.count(axis)) iso230_2(any->second, "_" + axis);
    iso230_2(any->second, "");  // results recorded without an axis
  }
  // ISO 230-4:2005: G limits G(b) and each direction's G; F limits |F max| and |F min|; H.
  for (const auto& [q, limit] : f.iso230_4.limits) {
    if (q == "G")
      for (const char* name : {"G_b", "G_cw", "G_ccw"}) out[name] = ToleranceBand::at_most(limit);
    else if (q == "F")
      for (const char* name : {"F_max", "F_min"}) out[name] = ToleranceBand::symmetric(limit);
    else
      out[q] = ToleranceBand::at_most(limit);
  }
  // Volumetric accuracy VA and its components (recorded as va, va_x, va_y, va_z).
  for (const auto& [q, limit] : f.volumetric.limits) {
    std::string name = "va";
    if (q.size() == 3) name += std::string("_") + static_cast<char>(q[2]);
    out[name] = ToleranceBand::at_most(limit);
  }
  return out;
}

}  // namespace mtcal
