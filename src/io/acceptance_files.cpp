// Acceptance-report metadata and tolerance files (io/acceptance_files.hpp).
#include "mtcal/io/acceptance_files.hpp"

#include <yaml-cpp/yaml.h>

#include "mtcal/io/files.hpp"
#include "yaml_reader.hpp"

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

Json to_json(const ReportMetadata& m) {
  Json j = Json::object();
  for (const auto& [k, v] : m.entries()) j[k] = v;
  return j;
}

Json to_json(const ToleranceVerdict& v) {
  Json checks = Json::array();
  for (const auto& c : v.checks)
    checks.push_back({{"quantity", c.quantity}, {"value", c.value}, {"limit", c.limit}, {"pass", c.pass}});
  return {{"verdict", v.pass() ? "pass" : "fail"}, {"unit", "um"}, {"checks", checks}};
}

}  // namespace mtcal
