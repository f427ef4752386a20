#include "mtcal/evaluation/iso230_2.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include <fmt/format.h>

#include "mtcal/io/csv.hpp"
#include "mtcal/io/files.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/parse.hpp"

namespace mtcal {
namespace {

double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return s / static_cast<double>(v.size());
}

double sample_sd(const std::vector<double>& v, double m) {
  double s = 0;
  for (double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / static_cast<double>(v.size() - 1));
}

}  // namespace

PositioningRuns read_positioning_csv(const std::string& path, const std::string& unit) {
  const TextTable table = read_text_csv(path, "positioning file");
  const auto c = table.require_columns({"target", "run", "direction", "measured"}, path);
  // target value -> direction -> run -> measured
  std::vector<double> order;
  std::map<double, std::map<int, std::map<long, double>>> data;
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    const auto& cells = table.rows[r];
    const int lineno = table.lines[r];
    auto num = [&](std::size_t col, const char* name) {
      const auto v = parse_number(cells[col]);
      if (!v) throw InputError({path, lineno, name}, "expected a number, found '" + cells[col] + "'");
      return *v;
    };
    const double target = num(c[0], "target"), measured = num(c[3], "measured"), run = num(c[1], "run");
    if (run != std::floor(run)) throw InputError({path, lineno, "run"}, "expected a whole run number");
    const std::string& d = cells[c[2]];
    int dir = 0;
    if (d == "up" || d == "+") dir = 1;
    else if (d == "down" || d == "-") dir = -1;
    else throw InputError({path, lineno, "direction"}, "expected up, down, + or -, found '" + d + "'");
    if (!data.count(target)) order.push_back(target);
    auto& runs = data[target][dir];
    if (runs.count(static_cast<long>(run)))
      throw InputError({path, lineno, "run"}, fmt::format("run {} of target {:g} ({}) given twice", run, target, d));
    runs[static_cast<long>(run)] = measured;
  }
  PositioningRuns r;
  r.unit = unit;
  std::sort(order.begin(), order.end());
  for (double t : order) {
    r.targets.push_back(t);
    std::vector<double> up, down;
    for (const auto& [run, v] : data[t][1]) up.push_back(v);
    for (const auto& [run, v] : data[t][-1]) down.push_back(v);
    r.up.push_back(up);
    r.down.push_back(down);
  }
  return r;
}

PositioningRuns read_positioning_dat(const std::string& path) {
  const std::string text = read_text_file(path, "positioning file");
  std::istringstream in(text);
  std::string line;
  int lineno = 0;
  std::map<long, double> targets;
  std::map<long, std::map<long, double>> fwd, bwd;
  std::string unit = "mm";
  const std::regex indexed(R"(^([A-Z_]+)\[(\d+)(?:,(\d+))?\]$)");
  while (std::getline(in, line)) {
    ++lineno;
    const std::string s = trim(line.substr(0, line.find('#')));
    if (s.empty()) continue;
    const auto eq = s.find('=');
    if (eq == std::string::npos) throw InputError({path, lineno, ""}, "expected KEY=VALUE, found '" + s + "'");
    const std::string key = trim(s.substr(0, eq)), value = trim(s.substr(eq + 1));
    if (key == "UNIT") {
      unit = value;
      continue;
    }
    if (key == "CYCLES" || key == "POSITIONS") continue;  // implied by the data
    std::smatch m;
    if (!std::regex_match(key, m, indexed))
      throw InputError({path, lineno, key}, "unknown key '" + key + "' (expected TGT_DATA[i], REF_DATA_FWD[i,j], REF_DATA_BWD[i,j], UNIT)");
    const auto v = parse_number(value);
    if (!v) throw InputError({path, lineno, key}, "expected a number, found '" + value + "'");
    const long i = std::stol(m[2]);
    const std::string name = m[1];
    if (name == "TGT_DATA" && !m[3].matched) {
      targets[i] = *v;
    } else if ((name == "REF_DATA_FWD" || name == "REF_DATA_BWD") && m[3].matched) {
      auto& dst = name == "REF_DATA_FWD" ? fwd : bwd;
      const long j = std::stol(m[3]);
      if (dst[i].count(j)) throw InputError({path, lineno, key}, "given twice");
      dst[i][j] = *v;
    } else {
      throw InputError({path, lineno, key}, "unknown key '" + key + "'");
    }
  }
  PositioningRuns r;
  r.unit = unit;
  for (const auto& [i, t] : targets) {
    r.targets.push_back(t);
    std::vector<double> up, down;
    for (const auto& [j, v] : fwd[i]) up.push_back(v);
    for (const auto& [j, v] : bwd[i]) down.push_back(v);
    r.up.push_back(up);
    r.down.push_back(down);
  }
  for (const auto& [i, runs] : fwd)
    if (!targets.count(i)) throw InputError({path, 0, fmt::format("REF_DATA_FWD[{},...]", i)}, "no TGT_DATA for this target");
  for (const auto& [i, runs] : bwd)
    if (!targets.count(i)) throw InputError({path, 0, fmt::format("REF_DATA_BWD[{},...]", i)}, "no TGT_DATA for this target");
  return r;
}

PositioningEvaluation evaluate_positioning(const PositioningRuns& in, const std::string& source) {
  const std::size_t m = in.targets.size();
  if (m < 2) throw InputError({source, 0, ""}, fmt::format("expected at least 2 targets, found {}", m));
  if (in.up.size() != m || in.down.size() != m) throw InputError({source, 0, ""}, "inconsistent run tables");
  const std::size_t n = in.up[0].size();
  for (std::size_t i = 0; i < m; ++i) {
    if (in.up[i].empty() || in.down[i].empty())
      throw InputError({source, 0, ""}, fmt::format("target {:g} lacks runs in the {} direction (ISO 230-2 needs both)",
                                                    in.targets[i], in.up[i].empty() ? "up (+)" : "down (-)"));
    if (in.up[i].size() != n || in.down[i].size() != n)
      throw InputError({source, 0, ""}, fmt::format("unequal run counts: target {:g} has {} up and {} down runs, "
                                                    "target {:g} has {} up",
                                                    in.targets[i], in.up[i].size(), in.down[i].size(), in.targets[0], n));
  }
  if (n < 2) throw InputError({source, 0, ""}, fmt::format("expected at least 2 runs per direction, found {}", n));

  PositioningEvaluation e;
  e.unit = in.unit;
  e.runs = n;
  double a_hi_up = -INFINITY, a_lo_up = INFINITY, a_hi_dn = -INFINITY, a_lo_dn = INFINITY;
  double e_hi_up = -INFINITY, e_lo_up = INFINITY, e_hi_dn = -INFINITY, e_lo_dn = INFINITY;
  double m_hi = -INFINITY, m_lo = INFINITY, b_sum = 0;
  for (std::size_t i = 0; i < m; ++i) {
    TargetEvaluation t;
    t.target = in.targets[i];
    std::vector<double> up, dn;  // deviations x_ij = measured - target
    for (double v : in.up[i]) up.push_back(v - t.target);
    for (double v : in.down[i]) dn.push_back(v - t.target);
    t.mean_up = mean(up);  // divided by the number of runs n, not of targets
    t.mean_down = mean(dn);
    t.mean = 0.5 * (t.mean_up + t.mean_down);
    t.reversal = t.mean_up - t.mean_down;
    t.s_up = sample_sd(up, t.mean_up);
    t.s_down = sample_sd(dn, t.mean_down);
    t.R_up = 4 * t.s_up;
    t.R_down = 4 * t.s_down;
    t.R = std::max({2 * t.s_up + 2 * t.s_down + std::abs(t.reversal), t.R_up, t.R_down});
    e.B = std::max(e.B, std::abs(t.reversal));
    b_sum += t.reversal;
    e.R = std::max(e.R, t.R);
    e.R_up = std::max(e.R_up, t.R_up);
    e.R_down = std::max(e.R_down, t.R_down);
    e_hi_up = std::max(e_hi_up, t.mean_up), e_lo_up = std::min(e_lo_up, t.mean_up);
    e_hi_dn = std::max(e_hi_dn, t.mean_down), e_lo_dn = std::min(e_lo_dn, t.mean_down);
    m_hi = std::max(m_hi, t.mean), m_lo = std::min(m_lo, t.mean);
    a_hi_up = std::max(a_hi_up, t.mean_up + 2 * t.s_up), a_lo_up = std::min(a_lo_up, t.mean_up - 2 * t.s_up);
    a_hi_dn = std::max(a_hi_dn, t.mean_down + 2 * t.s_down), a_lo_dn = std::min(a_lo_dn, t.mean_down - 2 * t.s_down);
    e.targets.push_back(t);
  }
  e.B_mean = b_sum / static_cast<double>(m);
  e.E_up = e_hi_up - e_lo_up;
  e.E_down = e_hi_dn - e_lo_dn;
  e.E = std::max(e_hi_up, e_hi_dn) - std::min(e_lo_up, e_lo_dn);
  e.M = m_hi - m_lo;
  e.A_up = a_hi_up - a_lo_up;
  e.A_down = a_hi_dn - a_lo_dn;
  e.A = std::max(a_hi_up, a_hi_dn) - std::min(a_lo_up, a_lo_dn);
  return e;
}

}  // namespace mtcal
