#include "mtcal/prediction/separation.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "mtcal/util/errors.hpp"
#include "mtcal/util/parse.hpp"

namespace mtcal {
namespace {

std::optional<double> cell(const TextTable& t, std::size_t row, std::size_t col, const std::string& source, bool required) {
  const std::string s = trim(t.rows[row][col]);
  if (s.empty()) {
    if (required) throw InputError({source, t.lines[row], t.columns[col]}, "expected a number, found an empty cell");
    return std::nullopt;
  }
  const auto v = parse_number(s);
  if (!v) throw InputError({source, t.lines[row], t.columns[col]}, "expected a number, found '" + s + "'");
  return v;
}

std::size_t need(const TextTable& t, const std::string& name, const std::string& source) {
  const int c = t.column(name);
  if (c < 0) throw InputError({source, t.header_line, name}, "missing column '" + name + "'");
  return static_cast<std::size_t>(c);
}

int step_of(const TextTable& t, std::size_t r, std::size_t col, const std::string& source) {
  const double s = *cell(t, r, col, source, true);
  if (s != std::floor(s) || s < 1 || s > 1000)
    throw InputError({source, t.lines[r], "step"}, fmt::format("expected a step number 1, 2, ..., found {:g}", s));
  return static_cast<int>(s);
}

}  // namespace

std::vector<PositionStep> separate_position(const TextTable& t, const std::string& source) {
  const std::size_t cs = need(t, "step", source);
  std::vector<std::pair<std::size_t, std::size_t>> pairs;  // cmm, probe column
  std::vector<char> axes;
  for (std::size_t c = 0; c < t.columns.size(); ++c) {
    const std::string& n = t.columns[c];
    if (n.rfind("cmm_", 0) != 0) continue;
    const std::string f = n.substr(4);
    const char ax = f.empty() ? 0 : static_cast<char>(std::toupper(static_cast<unsigned char>(f[0])));
    if (ax != 'X' && ax != 'Y' && ax != 'Z')
      throw InputError({source, t.header_line, n}, "expected a feature name starting with X, Y or Z after 'cmm_', found '" + f + "'");
    pairs.emplace_back(c, need(t, "probe_" + f, source));
    axes.push_back(ax);
  }
  if (pairs.empty()) throw InputError({source, t.header_line, ""}, "expected columns cmm_<feature> and probe_<feature> (e.g. cmm_Y1, probe_Y1)");
  std::vector<PositionStep> out;
  auto slot = [&](int step, char ax) -> PositionStep& {
    for (auto& p : out)
      if (p.step == step && p.axis == ax) return p;
    out.push_back({step, ax, std::nan(""), 0.0, 0});
    return out.back();
  };
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    const int step = step_of(t, r, cs, source);
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      const auto cm = cell(t, r, pairs[k].first, source, false);
      const auto pr = cell(t, r, pairs[k].second, source, false);
      if (cm.has_value() != pr.has_value())
        throw InputError({source, t.lines[r], t.columns[cm ? pairs[k].second : pairs[k].first]},
                         "expected a value in both the CMM and the probe column of a feature, or in neither");
      if (!cm) continue;
      PositionStep& p = slot(step, axes[k]);
      p.e_pos += *cm - *pr;
      ++p.count;
      const std::string dcol = std::string("d_") + static_cast<char>(std::tolower(axes[k]));
      const std::size_t dc = need(t, dcol, source);
      if (std::isnan(p.distance)) p.distance = *cell(t, r, dc, source, true);
    }
  }
  for (auto& p : out) p.e_pos /= p.count;
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.axis != b.axis ? a.axis < b.axis : a.step < b.step; });
  return out;
}

std::vector<DimensionRecord> read_dimension_table(const TextTable& t, const std::string& source) {
  const auto idx = t.require_columns({"workpiece", "step", "axis", "nominal", "measured", "e_pf", "e_pt", "e_pos"}, source);
  std::vector<DimensionRecord> out;
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    DimensionRecord d;
    d.line = t.lines[r];
    d.workpiece = trim(t.rows[r][idx[0]]);
    if (d.workpiece.empty()) throw InputError({source, d.line, "workpiece"}, "expected a workpiece name, found an empty cell");
    d.step = step_of(t, r, idx[1], source);
    const std::string ax = trim(t.rows[r][idx[2]]);
    if (ax != "X" && ax != "Y") throw InputError({source, d.line, "axis"}, "expected X or Y, found '" + ax + "'");
    d.axis = ax[0];
    d.nominal = *cell(t, r, idx[3], source, true);
    d.measured = *cell(t, r, idx[4], source, true);
    d.e_pf = cell(t, r, idx[5], source, false);
    d.e_pt = cell(t, r, idx[6], source, false);
    d.e_pos = cell(t, r, idx[7], source, false);
    for (const auto& o : out)
      if (o.workpiece == d.workpiece && o.step == d.step && o.axis == d.axis)
        throw InputError({source, d.line, "workpiece"}, fmt::format("{} step {} {} is given twice (first on line {})", d.workpiece, d.step, d.axis, o.line));
    out.push_back(d);
  }
  return out;
}

std::vector<ControlStep> separate_control(const std::vector<DimensionRecord>& records, const std::string& a,
                                          const std::string& b, const std::string& source,
                                          const std::map<std::pair<int, char>, double>& subtract) {
  std::vector<ControlStep> out;
  auto components = [&](const DimensionRecord& d) {
    for (const auto* c : {&d.e_pf, &d.e_pt, &d.e_pos})
      if (!c->has_value())
        throw InputError({source, d.line, c == &d.e_pf ? "e_pf" : c == &d.e_pt ? "e_pt" : "e_pos"},
                         fmt::format("{} step {} {} is compared (eq. 3.11-3.15) but this component is empty", d.workpiece, d.step, d.axis));
  };
  bool any_a = false, any_b = false;
  for (const auto& ra : records) {
    any_a |= ra.workpiece == a;
    any_b |= ra.workpiece == b;
    if (ra.workpiece != a) continue;
    const auto rb = std::find_if(records.begin(), records.end(),
                                 [&](const auto& o) { return o.workpiece == b && o.step == ra.step && o.axis == ra.axis; });
    if (rb == records.end()) continue;
    components(ra);
    components(*rb);
    ControlStep c{ra.step, ra.axis, ra.nominal, 0.0};
    c.value = ((ra.measured - ra.nominal) - (rb->measured - rb->nominal)) - (*ra.e_pf - *rb->e_pf) - (*ra.e_pt - *rb->e_pt) -
              (*ra.e_pos - *rb->e_pos);
    if (!subtract.empty()) {
      const auto it = subtract.find({ra.step, ra.axis});
      if (it == subtract.end())
        throw InputError({source, ra.line, "step"}, fmt::format("no e_ctrl(2400-100) for step {} {} to subtract (eq. 3.15)", ra.step, ra.axis));
      c.value -= it->second;
    }
    out.push_back(c);
  }
  if (!any_a || !any_b)
    throw InputError({source, 0, "workpiece"}, fmt::format("workpiece '{}' is not in the table", any_a ? b : a));
  if (out.empty()) throw InputError({source, 0, "step"}, fmt::format("{} and {} share no step and axis", a, b));
  std::sort(out.begin(), out.end(), [](const auto& x, const auto& y) { return x.axis != y.axis ? x.axis < y.axis : x.step < y.step; });
  return out;
}

}  // namespace mtcal
