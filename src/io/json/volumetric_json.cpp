#include "mtcal/io/json/volumetric_json.hpp"

#include <string>

namespace mtcal {

Json to_json(const Machine& m, const ErrorMap& map, const PointPair& p) {
  return {{"from", joint_json(m, map.configuration(p.i))},
          {"to", joint_json(m, map.configuration(p.j))},
          {"error_from", vec3_json(map.error[p.i])},
          {"error_to", vec3_json(map.error[p.j])},
          {"difference", vec3_json(map.error[p.j] - map.error[p.i])}};
}

Json to_json(const ContributionAnalysis& c, std::size_t top) {
  Json items = Json::array();
  for (std::size_t k = 0; k < c.items.size() && k < top; ++k) {
    const auto& it = c.items[k];
    items.push_back(
        {{"error", it.error.str()}, {"effect", vec3_json(it.effect)}, {"along", it.along}, {"share", it.share}});
  }
  return {{"exact", vec3_json(c.exact)},
          {"first_order", vec3_json(c.first_order)},
          {"residual", c.residual},
          {"items", items}};
}

Json to_json(const Distribution& d) {
  const auto& h = d.histogram;
  return {{"count", d.count},
          {"mean", d.mean},
          {"min", d.min},
          {"max", d.max},
          {"bins", h.counts.size()},
          {"bin_width", h.width},
          {"lo", h.lo},
          {"counts", h.counts},
          {"p50", h.quantile(0.5)},
          {"p90", h.quantile(0.9)},
          {"p95", h.quantile(0.95)},
          {"p99", h.quantile(0.99)}};
}

Json to_json(const Machine& m, const BoxVa& b) {
  return {{"fraction", b.fraction},
          {"lo", joint_json(m, b.lo)},
          {"hi", joint_json(m, b.hi)},
          {"points", b.points},
          {"va", b.va.value}};
}

Json to_json(const GroupingComparison& g, const VolumetricAccuracy& exact) {
  return {{"angle", g.options.angle_tolerance},
          {"magnitude", g.options.magnitude_tolerance},
          {"groups", g.result.groups},
          {"records", g.result.kept.size()},
          {"comparisons", g.result.comparisons},
          {"va", g.result.va.value},
          {"va_exact", exact.va.value},
          {"difference_percent", g.difference_percent},
          {"comparison_reduction_percent", g.comparison_reduction_percent}};
}

Json to_json(const Machine& m, const ErrorMap& map, const VolumetricStudy& s, double seconds_map) {
  const VolumetricAccuracy& va = s.va;
  Json j;
  j["machine"] = m.name;
  j["points"] = va.points;
  j["pairs"] = va.pairs;
  j["va"] = va.va.value;
  j["va_x"] = va.component[0].value;
  j["va_y"] = va.component[1].value;
  j["va_z"] = va.component[2].value;
  j["critical_pair"] = to_json(m, map, va.va);
  j["component_pairs"] = {{"x", to_json(m, map, va.component[0])},
                          {"y", to_json(m, map, va.component[1])},
                          {"z", to_json(m, map, va.component[2])}};
  j["contributions"] = to_json(s.critical, s.critical.items.size());
  j["distance_evaluations"] = va.distance_evaluations;
  j["seconds"] = {{"map", seconds_map}, {"va", s.seconds_va}, {"histogram", s.seconds_histogram}};
  if (s.box_va) {
    const JointBox& box = *s.box;
    const VolumetricAccuracy& b = *s.box_va;
    j["box"] = {{"lo", joint_json(m, box.lo)},  {"hi", joint_json(m, box.hi)},
                {"points", b.points},           {"va", b.va.value},
                {"va_x", b.component[0].value}, {"va_y", b.component[1].value},
                {"va_z", b.component[2].value}, {"critical_pair", to_json(m, *s.box_map, b.va)}};
    // Unnamed axes span everything: JSON has no infinity, so they are left out.
    for (auto* side : {&j["box"]["lo"], &j["box"]["hi"]})
      for (std::size_t k = 0; k < m.axes.size(); ++k)
        if (!box.named[k]) side->erase(std::string(1, m.axes[k].letter));
  }
  if (!s.scan.empty()) {
    j["box_scan"] = Json::array();
    for (const auto& b : s.scan) j["box_scan"].push_back(to_json(m, b));
  }
  if (s.pairs) {
    j["histogram"] = to_json(*s.pairs);
    j["error_distribution"] = to_json(*s.magnitudes);
  }
  if (s.grouping) j["grouping"] = to_json(*s.grouping, va);
  return j;
}

Json to_json(const Machine& m, const ContributionStudy& s, std::size_t top) {
  Json j;
  j["mode"] = s.mode;
  j["at"] = joint_json(m, s.a);
  if (!s.b.empty()) j["from"] = joint_json(m, s.b);
  if (s.va) j["va"] = s.va->va.value;
  const Json cj = to_json(s.analysis, top);
  for (auto it = cj.begin(); it != cj.end(); ++it) j[it.key()] = it.value();
  if (s.va && s.what_if_asked) {
    j["what_if"] = Json::array();
    for (const auto& w : s.what_if) {
      Json x = {{"error", w.error.str()},
                {"va_without", w.va},
                {"gain", s.va->va.value - w.va},
                {"share", w.share},
                {"disagrees", w.disagrees}};
      if (w.disagrees) {
        x["critical_pair_without"] = {{"from", joint_json(m, w.from)}, {"to", joint_json(m, w.to)}};
        x["along_there"] = w.along_there;
        x["cancelled"] = Json::array();
        for (const auto& [e, against] : w.cancelled)
          x["cancelled"].push_back({{"error", e.str()}, {"against", against}});
      }
      j["what_if"].push_back(x);
    }
  }
  if (s.sequence) {
    Json steps = Json::array();
    for (const auto& st : s.sequence->steps) steps.push_back({{"error", st.error.str()}, {"va", st.va}});
    j["correction_sequence"] = {{"target_va", s.sequence->target},
                                {"start_va", s.sequence->start},
                                {"reached", s.sequence->reached},
                                {"steps", steps}};
  }
  return j;
}

Json to_json(const Machine& m, const DiagonalProfile& d) {
  return {{"name", d.name},
          {"from", joint_json(m, d.start)},
          {"to", joint_json(m, d.end)},
          {"length", d.length},
          {"direction", vec3_json(d.direction)},
          {"range", d.range},
          {"position", d.position},
          {"deviation", d.deviation}};
}

Json to_json(const Machine& m, const std::vector<DiagonalProfile>& diagonals) {
  Json j;
  j["machine"] = m.name;
  j["diagonals"] = Json::array();
  for (const auto& d : diagonals) j["diagonals"].push_back(to_json(m, d));
  return j;
}

}  // namespace mtcal
