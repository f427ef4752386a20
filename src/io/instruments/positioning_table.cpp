// Positioning tables as spreadsheets and scripts write them (io/instruments/iso230_files.hpp).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <optional>
#include <sstream>
#include <string_view>
#include <tuple>

#include <fmt/format.h>

#include "mtcal/io/instruments/iso230_files.hpp"
#include "mtcal/io/system/files.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/parse.hpp"

namespace mtcal {
namespace {

constexpr std::string_view kMinus = "\xE2\x88\x92";  // U+2212 MINUS SIGN
constexpr std::string_view kUp = "\xE2\x86\x91";     // U+2191 ↑
constexpr std::string_view kDown = "\xE2\x86\x93";   // U+2193 ↓

std::string unquote(std::string s) {
  s = trim(s);
  if (s.size() >= 2 && s.front() == '"' && s.back() == '"') s = trim(s.substr(1, s.size() - 2));
  return s;
}

std::vector<std::string> split(const std::string& line, char delim) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (true) {
    const auto end = line.find(delim, start);
    out.push_back(unquote(line.substr(start, end == std::string::npos ? std::string::npos : end - start)));
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return out;
}

enum class Role { Target, Run, Direction, Measured, Deviation, Other };

// The column's role from its name, and the unit in brackets after it ("deviation [um]").
std::pair<Role, std::string> role_of(const std::string& header) {
  std::string name = header, unit;
  for (const auto& [open, close] : {std::pair{'[', ']'}, std::pair{'(', ')'}}) {
    const auto o = name.rfind(open);
    if (o != std::string::npos && name.back() == close) {
      unit = trim(name.substr(o + 1, name.size() - o - 2));
      name = trim(name.substr(0, o));
      break;
    }
  }
  std::string key;
  for (char c : to_lower(name))
    if (std::isalnum(static_cast<unsigned char>(c))) key += c;
  static const std::map<std::string, Role> roles = {{"target", Role::Target},
                                                    {"targetposition", Role::Target},
                                                    {"position", Role::Target},
                                                    {"nominal", Role::Target},
                                                    {"nominalposition", Role::Target},
                                                    {"setpoint", Role::Target},
                                                    {"tgt", Role::Target},
                                                    {"run", Role::Run},
                                                    {"runno", Role::Run},
                                                    {"runnumber", Role::Run},
                                                    {"cycle", Role::Run},
                                                    {"pass", Role::Run},
                                                    {"direction", Role::Direction},
                                                    {"dir", Role::Direction},
                                                    {"measured", Role::Measured},
                                                    {"measuredposition", Role::Measured},
                                                    {"actual", Role::Measured},
                                                    {"actualposition", Role::Measured},
                                                    {"reading", Role::Measured},
                                                    {"deviation", Role::Deviation},
                                                    {"positionaldeviation", Role::Deviation},
                                                    {"dev", Role::Deviation},
                                                    {"error", Role::Deviation},
                                                    {"positionerror", Role::Deviation}};
  const auto it = roles.find(key);
  return {it == roles.end() ? Role::Other : it->second, unit};
}

// +1 up, -1 down, 0 unknown.
int direction_of(const std::string& cell) {
  const std::string c = to_lower(trim(cell));
  if (c == "up" || c == "+" || c == "fwd" || c == "forward" || c == "pos" || c == "positive" || c == "+1" || c == kUp)
    return 1;
  if (c == "down" || c == "-" || c == kMinus || c == "bwd" || c == "backward" || c == "neg" || c == "negative" ||
      c == "-1" || c == kDown)
    return -1;
  return 0;
}

// A number as a spreadsheet writes it: decimal comma where ',' does not separate cells, U+2212
// as the minus sign.
std::optional<double> number(std::string cell, char delim) {
  if (cell.rfind(kMinus, 0) == 0) cell = "-" + cell.substr(kMinus.size());
  if (delim != ',' && cell.find('.') == std::string::npos && std::count(cell.begin(), cell.end(), ',') == 1)
    std::replace(cell.begin(), cell.end(), ',', '.');
  return parse_number(cell);
}

}  // namespace

PositioningRuns parse_positioning_csv(const std::string& text, const std::string& source, const std::string& unit,
                                      const std::string& target_unit) {
  const bool bom = text.rfind("\xEF\xBB\xBF", 0) == 0;
  std::istringstream in(bom ? text.substr(3) : text);
  std::string line;
  int lineno = 0, header_line = 0;
  char delim = ',', forced_delim = 0;
  std::vector<std::string> names;
  std::map<Role, std::size_t> col;
  PositioningRuns r;
  r.source = source;
  r.unit = unit;
  r.target_unit = target_unit;
  // target value -> direction -> run -> value
  std::map<double, std::map<int, std::map<long, double>>> data;
  std::map<std::pair<double, int>, long> next_run;
  while (std::getline(in, line)) {
    ++lineno;
    const std::string s = trim(line);
    if (s.empty() || s[0] == '#') continue;
    if (header_line == 0 && !forced_delim && s.size() == 5 && s.rfind("sep=", 0) == 0) {
      forced_delim = s[4];  // a spreadsheet's "sep=;" line before the header
      continue;
    }
    if (header_line == 0) {
      delim = forced_delim                        ? forced_delim
              : s.find('\t') != std::string::npos ? '\t'
              : s.find(';') != std::string::npos  ? ';'
                                                  : ',';
      names = split(s, delim);
      std::string value_unit, tgt_unit;
      for (std::size_t k = 0; k < names.size(); ++k) {
        if (names[k].empty()) throw InputError({source, lineno, ""}, "empty column name in the header");
        const auto [role, u] = role_of(names[k]);
        if (role == Role::Other) {
          r.warnings.push_back(
              fmt::format("{}:{}: column '{}' is not used by the evaluation", source, lineno, printable(names[k])));
          continue;
        }
        if (col.count(role))
          throw InputError({source, lineno, names[k]}, fmt::format("column '{}' means the same as column '{}'",
                                                                   printable(names[k]), printable(names[col[role]])));
        col[role] = k;
        if (!u.empty() && role == Role::Target) tgt_unit = u;
        if (!u.empty() && (role == Role::Measured || role == Role::Deviation)) value_unit = u;
      }
      if (!col.count(Role::Target))
        throw InputError({source, lineno, ""},
                         "missing the target column (a header naming target, position, nominal or setpoint)");
      if (col.count(Role::Measured) == col.count(Role::Deviation))
        throw InputError({source, lineno, ""},
                         col.count(Role::Measured)
                             ? "both a measured and a deviation column: expected one of them"
                             : "missing the value column (a header naming measured, actual, deviation or error)");
      r.deviations = col.count(Role::Deviation) > 0;
      if (!value_unit.empty()) r.unit = value_unit;
      if (!tgt_unit.empty()) r.target_unit = tgt_unit;
      if (!r.deviations && !r.target_unit.empty() && r.target_unit != r.unit)
        throw InputError({source, lineno, names[col[Role::Target]]},
                         fmt::format("mixed units: targets in {}, measured positions in {} (measured positions must "
                                     "be in the targets' unit)",
                                     printable(r.target_unit), printable(r.unit)));
      if (!col.count(Role::Direction))
        r.warnings.push_back(
            fmt::format("{}:{}: no direction column: every run is taken as approaching in + "
                        "(a unidirectional test)",
                        source, lineno));
      header_line = lineno;
      continue;
    }
    const auto cells = split(s, delim);
    if (cells.size() != names.size())
      throw InputError({source, lineno, ""},
                       fmt::format("expected {} cells (one per header column), found {}", names.size(), cells.size()));
    auto num = [&](Role role) {
      const std::size_t k = col.at(role);
      const auto v = number(cells[k], delim);
      if (!v) throw InputError({source, lineno, names[k]}, "expected a number, found '" + printable(cells[k]) + "'");
      return *v;
    };
    const double target = num(Role::Target);
    const double value = num(r.deviations ? Role::Deviation : Role::Measured);
    int dir = 1;
    if (col.count(Role::Direction)) {
      const std::size_t k = col.at(Role::Direction);
      dir = direction_of(cells[k]);
      if (dir == 0)
        throw InputError({source, lineno, names[k]},
                         "expected up, down, +, -, fwd, bwd, forward, backward, pos, neg, \u2191 or \u2193, found '" +
                             printable(cells[k]) + "'");
    }
    long run = 0;
    if (col.count(Role::Run)) {
      const double v = num(Role::Run);
      if (v != std::floor(v) || std::abs(v) > 1e9)
        throw InputError({source, lineno, names[col.at(Role::Run)]},
                         "expected a whole run number, found '" + printable(cells[col.at(Role::Run)]) + "'");
      run = static_cast<long>(v);
    } else {
      run = ++next_run[{target, dir}];
    }
    auto& runs = data[target][dir];
    if (runs.count(run))
      throw InputError({source, lineno, col.count(Role::Run) ? names[col.at(Role::Run)] : names[col.at(Role::Target)]},
                       fmt::format("run {} of target {:g} ({}) given twice", run, target, dir > 0 ? "up" : "down"));
    runs[run] = value;
  }
  if (header_line == 0) throw InputError({source, 0, ""}, "no header line naming the columns");
  if (data.empty()) throw InputError({source, header_line, ""}, "no data rows after the header");
  for (auto& [t, dirs] : data) {
    r.targets.push_back(t);
    std::vector<double> up, down;
    for (const auto& [run, v] : dirs[1]) up.push_back(v);
    for (const auto& [run, v] : dirs[-1]) down.push_back(v);
    r.up.push_back(std::move(up));
    r.down.push_back(std::move(down));
  }
  return r;
}

PositioningRuns read_positioning_csv(const std::string& path, const std::string& unit, const std::string& target_unit) {
  return parse_positioning_csv(read_text_file(path, "positioning file"), path, unit, target_unit);
}

}  // namespace mtcal
