// Error-separation tables (Yaqoob 2017 Tables 5.3, 5.6; docs/prediction.md): text tables into the domain's records.
#include "mtcal/io/instruments/separation_file.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

#include <fmt/format.h>

#include "mtcal/io/text/number_format.hpp"

#include "mtcal/util/errors.hpp"
#include "mtcal/util/parse.hpp"

namespace mtcal {
namespace {

std::optional<double> cell(const TextTable& t, std::size_t row, std::size_t col, const std::string& source,
                           bool required) {
  const std::string s = trim(t.rows[row][col]);
  if (s.empty()) {
    if (required) throw InputError({source, t.lines[row], t.columns[col]}, "expected a number, found an empty cell");
    return std::nullopt;
  }
  const auto v = parse_number(s);
  if (!v) throw InputError({source, t.lines[row], t.columns[col]}, "expected a number, found '" + printable(s) + "'");
  return v;
}

std::size_t need(const TextTable& t, const std::string& name, const std::string& source) {
  const int c = t.column(name);
  if (c < 0) throw InputError({source, t.header_line, name}, "missing column '" + printable(name) + "'");
  return static_cast<std::size_t>(c);
}

int step_of(const TextTable& t, std::size_t r, std::size_t col, const std::string& source) {
  const double s = *cell(t, r, col, source, true);
  if (s != std::floor(s) || s < 1 || s > 1000)
    throw InputError({source, t.lines[r], "step"}, fmt::format("expected a step number 1, 2, ..., found {:g}", s));
  return static_cast<int>(s);
}

}  // namespace

std::vector<PositionObservation> read_position_observations(const TextTable& t, const std::string& source) {
  const std::size_t cs = need(t, "step", source);
  std::vector<std::pair<std::size_t, std::size_t>> pairs;  // cmm, probe column
  std::vector<char> axes;
  for (std::size_t c = 0; c < t.columns.size(); ++c) {
    const std::string& n = t.columns[c];
    if (n.rfind("cmm_", 0) != 0) continue;
    const std::string f = n.substr(4);
    const char ax = f.empty() ? 0 : static_cast<char>(std::toupper(static_cast<unsigned char>(f[0])));
    if (ax != 'X' && ax != 'Y' && ax != 'Z')
      throw InputError({source, t.header_line, n},
                       "expected a feature name starting with X, Y or Z after 'cmm_', found '" + printable(f) + "'");
    pairs.emplace_back(c, need(t, "probe_" + f, source));
    axes.push_back(ax);
  }
  if (pairs.empty())
    throw InputError({source, t.header_line, ""},
                     "expected columns cmm_<feature> and probe_<feature> (e.g. cmm_Y1, probe_Y1)");
  std::vector<PositionObservation> out;
  // The distance of a step and axis is read from its first observation's row only (the thesis
  // gives it once per step): later rows' d_<axis> cells are not read.
  std::vector<std::pair<int, char>> distance_read;
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    const int step = step_of(t, r, cs, source);
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      const auto cm = cell(t, r, pairs[k].first, source, false);
      const auto pr = cell(t, r, pairs[k].second, source, false);
      if (cm.has_value() != pr.has_value())
        throw InputError({source, t.lines[r], t.columns[cm ? pairs[k].second : pairs[k].first]},
                         "expected a value in both the CMM and the probe column of a feature, or in neither");
      if (!cm) continue;
      PositionObservation o;
      o.step = step;
      o.axis = axes[k];
      o.feature = t.columns[pairs[k].first].substr(4);
      o.cmm = *cm;
      o.probe = *pr;
      o.line = t.lines[r];
      const std::string dcol = std::string("d_") + static_cast<char>(std::tolower(axes[k]));
      const std::size_t dc = need(t, dcol, source);
      const std::pair<int, char> key{step, axes[k]};
      if (std::find(distance_read.begin(), distance_read.end(), key) == distance_read.end()) {
        o.distance = *cell(t, r, dc, source, true);
        distance_read.push_back(key);
      }
      out.push_back(o);
    }
  }
  return out;
}

std::vector<DimensionRecord> read_dimension_table(const TextTable& t, const std::string& source) {
  const auto idx =
      t.require_columns({"workpiece", "step", "axis", "nominal", "measured", "e_pf", "e_pt", "e_pos"}, source);
  std::vector<DimensionRecord> out;
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    DimensionRecord d;
    d.line = t.lines[r];
    d.workpiece = trim(t.rows[r][idx[0]]);
    if (d.workpiece.empty())
      throw InputError({source, d.line, "workpiece"}, "expected a workpiece name, found an empty cell");
    d.step = step_of(t, r, idx[1], source);
    const std::string ax = trim(t.rows[r][idx[2]]);
    if (ax != "X" && ax != "Y")
      throw InputError({source, d.line, "axis"}, "expected X or Y, found '" + printable(ax) + "'");
    d.axis = ax[0];
    d.nominal = *cell(t, r, idx[3], source, true);
    d.measured = *cell(t, r, idx[4], source, true);
    d.e_pf = cell(t, r, idx[5], source, false);
    d.e_pt = cell(t, r, idx[6], source, false);
    d.e_pos = cell(t, r, idx[7], source, false);
    for (const auto& o : out)
      if (o.workpiece == d.workpiece && o.step == d.step && o.axis == d.axis)
        throw InputError({source, d.line, "workpiece"}, fmt::format("{} step {} {} is given twice (first on line {})",
                                                                    d.workpiece, d.step, d.axis, o.line));
    out.push_back(d);
  }
  return out;
}

std::vector<PositionObservation> read_position_observations(const std::string& path) {
  return read_position_observations(read_text_csv(path), path);
}

std::vector<DimensionRecord> read_dimension_table(const std::string& path) {
  return read_dimension_table(read_text_csv(path), path);
}

std::string separation_csv(const PositionSeparation& s) {
  std::string csv = "axis,step,distance,e_pos,count\n";
  for (const auto& p : s.steps)
    csv += fmt::format("{},{},{:g},{},{}\n", p.axis, p.step, p.distance, format_number(p.e_pos), p.count);
  return csv;
}

std::string separation_csv(const ControlSeparation& s) {
  std::string csv = "axis,step,distance," + s.quantity + "\n";
  for (const auto& c : s.steps)
    csv += fmt::format("{},{},{:g},{}\n", c.axis, c.step, c.distance, format_number(c.value));
  return csv;
}

}  // namespace mtcal
