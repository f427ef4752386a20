// Readers and writers of the acceptance tests' measurement files (io/instruments/iso230_files.hpp).
#include "mtcal/io/instruments/iso230_files.hpp"
#include "mtcal/util/units.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <map>
#include <optional>
#include <string_view>
#include <numbers>
#include <sstream>
#include <tuple>

#include <fmt/format.h>

#include "mtcal/io/text/csv.hpp"
#include "mtcal/io/system/files.hpp"
#include "mtcal/io/instruments/laser_files.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/parse.hpp"

namespace mtcal {
namespace {


constexpr std::array<const char*, 4> kColumns = {"method", "test", "parameter", "value"};

// Splits one line into cells. The numeric reader (io/csv) has no use for quotes, but names of
// tests and parameters written by spreadsheets may carry them: a cell may be wrapped in double
// quotes, with "" standing for one quote inside, so that it can hold commas.
std::vector<std::string> split_cells(const std::string& line, const SourceLocation& where) {
  std::vector<std::string> cells;
  std::size_t i = 0;
  while (true) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    std::string cell;
    if (i < line.size() && line[i] == '"') {
      ++i;
      bool closed = false;
      while (i < line.size()) {
        if (line[i] == '"') {
          if (i + 1 < line.size() && line[i + 1] == '"') {
            cell += '"';
            i += 2;
            continue;
          }
          ++i;
          closed = true;
          break;
        }
        cell += line[i++];
      }
      if (!closed) throw InputError(where, "a quoted cell is not closed (expected a closing '\"' on the same line)");
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
      if (i < line.size() && line[i] != ',')
        throw InputError(where, fmt::format("unexpected '{}' after a quoted cell (expected ',')", line[i]));
    } else {
      const auto end = line.find(',', i);
      cell = trim(line.substr(i, end == std::string::npos ? std::string::npos : end - i));
      i = end == std::string::npos ? line.size() : end;
    }
    cells.push_back(std::move(cell));
    if (i >= line.size()) break;
    ++i;  // the comma; a line ending in ',' has an empty last cell
    if (i == line.size()) {
      cells.emplace_back();
      break;
    }
  }
  return cells;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ",") + x;
  return s;
}

}  // namespace

namespace {

// A key of an ISO 230-2 .dat file, NAME[i] or NAME[i,j] (NAME of A-Z and _): scanned by hand,
// linear in the key's length (a std::regex here recursed once per character and overflowed the
// stack on a 50 KB key). Indices are limited to 9 digits, so that they fit a long everywhere.
struct IndexedKey {
  std::string name;
  long i = 0;
  std::optional<long> j;
};

std::optional<long> scan_index(std::string_view s, std::size_t& k) {
  const std::size_t start = k;
  long v = 0;
  while (k < s.size() && s[k] >= '0' && s[k] <= '9') {
    if (k - start == 9) return std::nullopt;
    v = v * 10 + (s[k] - '0');
    ++k;
  }
  if (k == start) return std::nullopt;
  return v;
}

std::optional<IndexedKey> scan_indexed_key(std::string_view s) {
  std::size_t k = 0;
  while (k < s.size() && ((s[k] >= 'A' && s[k] <= 'Z') || s[k] == '_')) ++k;
  if (k == 0 || k >= s.size() || s[k] != '[') return std::nullopt;
  IndexedKey key;
  key.name = std::string(s.substr(0, k));
  ++k;
  const auto i = scan_index(s, k);
  if (!i) return std::nullopt;
  key.i = *i;
  if (k < s.size() && s[k] == ',') {
    ++k;
    key.j = scan_index(s, k);
    if (!key.j) return std::nullopt;
  }
  if (k + 1 != s.size() || s[k] != ']') return std::nullopt;
  return key;
}

}  // namespace

namespace {

// A key of the .dat layout as a name: letters, digits and '_', optionally followed by indices in
// brackets (the form of the keys the evaluation uses, and of the data keys other tools add).
bool plain_key(std::string_view k) {
  std::size_t i = 0;
  while (i < k.size() && (std::isalnum(static_cast<unsigned char>(k[i])) || k[i] == '_')) ++i;
  if (i == 0) return false;
  if (i == k.size()) return true;
  if (k[i] != '[' || k.back() != ']') return false;
  for (++i; i + 1 < k.size(); ++i)
    if (!std::isdigit(static_cast<unsigned char>(k[i])) && k[i] != ',' && k[i] != ' ') return false;
  return true;
}

}  // namespace

PositioningRuns read_positioning_dat(const std::string& path) {
  return parse_positioning_dat(read_text_file(path, "positioning file"), path);
}

PositioningRuns parse_positioning_dat(const std::string& text, const std::string& path) {
  std::istringstream in(text);
  std::string line;
  int lineno = 0;
  std::map<long, double> targets;
  std::map<long, std::map<long, double>> fwd, bwd;
  std::string unit = "mm";
  PositioningRuns r;
  std::map<std::string, std::pair<int, int>> unknown;  // key name -> first line, count
  std::vector<std::string> unknown_order;
  while (std::getline(in, line)) {
    ++lineno;
    const std::string s = trim(line.substr(0, line.find('#')));
    if (s.empty()) continue;
    const auto eq = s.find('=');
    if (eq == std::string::npos)
      throw InputError({path, lineno, ""}, "expected KEY=VALUE, found '" + printable(s) + "'");
    const std::string key = trim(s.substr(0, eq)), value = trim(s.substr(eq + 1));
    if (key == "UNIT") {
      if (value.empty() || printable(value, 16) != value)
        throw InputError({path, lineno, key},
                         "expected a unit name such as mm or um, found '" + printable(value) + "'");
      unit = value;
      continue;
    }
    if (key == "CYCLES" || key == "POSITIONS") continue;  // implied by the data
    const auto m = scan_indexed_key(key);
    const std::string name = m ? m->name : key.substr(0, key.find('['));
    const bool known = name == "TGT_DATA" || name == "REF_DATA_FWD" || name == "REF_DATA_BWD";
    if (!known) {
      // Keys of other tools (TEST_DATA, REF_PV, TEST_PV, TGT_SET_PV, DEC ...): kept, not used.
      if (!plain_key(key))
        throw InputError({path, lineno, printable(key)},
                         "expected a key of letters, digits and '_' (with [i] or [i,j] indices), found '" +
                             printable(key) + "'");
      r.metadata.emplace_back(key, printable(value, 200));
      auto [it, fresh] = unknown.try_emplace(name, lineno, 0);
      if (fresh) unknown_order.push_back(name);
      ++it->second.second;
      continue;
    }
    if (!m)
      throw InputError({path, lineno, printable(key)}, "expected " + name + (name == "TGT_DATA" ? "[i]" : "[i,j]") +
                                                           " with indices of at most 9 digits, found '" +
                                                           printable(key) + "'");
    const auto v = parse_number(value);
    if (!v) throw InputError({path, lineno, key}, "expected a number, found '" + printable(value) + "'");
    const long i = m->i;
    if (name == "TGT_DATA" && !m->j) {
      if (targets.count(i)) throw InputError({path, lineno, key}, "given twice");
      targets[i] = *v;
    } else if (name != "TGT_DATA" && m->j) {
      auto& dst = name == "REF_DATA_FWD" ? fwd : bwd;
      const long j = *m->j;
      if (dst[i].count(j)) throw InputError({path, lineno, key}, "given twice");
      dst[i][j] = *v;
    } else {
      throw InputError({path, lineno, key},
                       "expected " + name + (name == "TGT_DATA" ? "[i]" : "[i,j]") + ", found '" + key + "'");
    }
  }
  for (const auto& n : unknown_order) {
    const auto [first, count] = unknown.at(n);
    r.warnings.push_back(fmt::format("{}:{}: key {} ({} line{}) is not used by the evaluation; kept as metadata", path,
                                     first, n, count, count == 1 ? "" : "s"));
  }
  if (targets.empty()) throw InputError({path, 0, "TGT_DATA"}, "no targets (expected TGT_DATA[i]=... lines)");
  r.source = path;
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
    if (!targets.count(i))
      throw InputError({path, 0, fmt::format("REF_DATA_FWD[{},...]", i)}, "no TGT_DATA for this target");
  for (const auto& [i, runs] : bwd)
    if (!targets.count(i))
      throw InputError({path, 0, fmt::format("REF_DATA_BWD[{},...]", i)}, "no TGT_DATA for this target");
  return r;
}

namespace {

bool has_extension(const std::string& path, std::string_view ext) {
  if (path.size() < ext.size()) return false;
  for (std::size_t i = 0; i < ext.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(path[path.size() - ext.size() + i])) != ext[i]) return false;
  return true;
}

// Which reader a file goes to when its extension or the format decides; Content: its text decides.
enum class PositioningForm { Laser, Dat, Content };
PositioningForm positioning_form(const std::string& path, const std::string& format) {
  if (format == "laser" || (format == "auto" && (has_extension(path, ".rtl") || has_extension(path, ".rta"))))
    return PositioningForm::Laser;
  if (format == "dat" || (format == "auto" && has_extension(path, ".dat"))) return PositioningForm::Dat;
  return PositioningForm::Content;
}

}  // namespace

PositioningRuns read_positioning_file(const std::string& path, const std::string& format, const std::string& unit,
                                      const std::string& target_unit) {
  // One read, named as the reader it goes to names it (read_laser_file: "laser file").
  const char* what = positioning_form(path, format) == PositioningForm::Laser ? "laser file" : "positioning file";
  return parse_positioning_file(read_text_file(path, what), path, format, unit, target_unit);
}

PositioningRuns parse_positioning_file(const std::string& text, const std::string& path, const std::string& format,
                                       const std::string& unit, const std::string& target_unit) {
  switch (positioning_form(path, format)) {
    case PositioningForm::Laser:
      return parse_laser_file(text, path, path.ends_with(".rta")).runs;  // rotary as read_laser_file decides
    case PositioningForm::Dat:
      return parse_positioning_dat(text, path);
    case PositioningForm::Content:
      break;
  }
  // The content decides: a section line is a laser export, a TGT_DATA[ key the .dat form.
  if (format == "auto" && text.substr(0, 4096).find("HEADER::") != std::string::npos)
    return parse_laser_file(text, path, false).runs;
  if (format == "auto" && text.find("TGT_DATA[") != std::string::npos) return parse_positioning_dat(text, path);
  return parse_positioning_csv(text, path, unit, target_unit);
}

BallbarTrace read_ballbar_csv(const std::string& path) {
  return parse_ballbar_csv(read_text_file(path, "ballbar trace"), path);
}

BallbarTrace parse_ballbar_csv(const std::string& text, const std::string& path) {
  const TextTable t = parse_text_csv(text, path);
  const auto c = t.require_columns({"direction", "angle_deg", "radius_mm"}, path);
  std::vector<TracePoint> out;
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    const auto& cells = t.rows[r];
    const int lineno = t.lines[r];
    TracePoint p;
    const std::string d = to_lower(cells[c[0]]);
    if (d == "cw")
      p.direction = CircleDirection::CW;
    else if (d == "ccw")
      p.direction = CircleDirection::CCW;
    else
      throw InputError({path, lineno, "direction"}, "expected cw or ccw, found '" + cells[c[0]] + "'");
    const auto a = parse_number(cells[c[1]]);
    if (!a) throw InputError({path, lineno, "angle_deg"}, "expected a number, found '" + cells[c[1]] + "'");
    const auto radius = parse_number(cells[c[2]]);
    if (!radius || !(*radius > 0))
      throw InputError({path, lineno, "radius_mm"}, "expected a length > 0, found '" + cells[c[2]] + "'");
    p.angle = *a * kRadPerDeg;
    p.radius = *radius;
    out.push_back(p);
  }
  return {path, out};
}

std::string ballbar_csv(const std::vector<TracePoint>& trace) {
  std::string s = "direction,angle_deg,radius_mm\n";
  for (const auto& p : trace)
    s += fmt::format("{},{:.6f},{:.9f}\n", p.direction == CircleDirection::CW ? "cw" : "ccw",
                     p.angle * 180 / std::numbers::pi, p.radius);
  return s;
}

void write_ballbar_csv(const std::string& path, const std::vector<TracePoint>& trace) {
  write_file_atomically(path, ballbar_csv(trace));
}

ComparisonData parse_comparison_csv(const std::string& text, const std::string& source) {
  // Spreadsheets often start their CSV exports with a UTF-8 byte order mark.
  const bool bom = text.rfind("\xEF\xBB\xBF", 0) == 0;
  std::istringstream in(bom ? text.substr(3) : text);
  std::string line;
  int lineno = 0;
  std::array<std::size_t, 4> col{};  // position of method, test, parameter, value in a row
  std::size_t ncols = 0;
  std::vector<std::string> methods;
  ComparisonData data;
  std::map<std::tuple<std::size_t, std::string, std::string>, int> seen;  // -> line
  while (std::getline(in, line)) {
    ++lineno;
    const std::string s = trim(line);
    if (s.empty() || s[0] == '#') continue;
    auto cells = split_cells(s, {source, lineno, ""});
    if (ncols == 0) {
      std::vector<std::string> expected(kColumns.begin(), kColumns.end());
      std::vector<std::string> sorted_cells = cells, sorted_expected = expected;
      std::sort(sorted_cells.begin(), sorted_cells.end());
      std::sort(sorted_expected.begin(), sorted_expected.end());
      if (sorted_cells != sorted_expected)
        throw InputError({source, lineno, ""},
                         "expected the header 'method,test,parameter,value' (columns in any order, no others), "
                         "found '" +
                             join(cells) + "'");
      for (std::size_t k = 0; k < kColumns.size(); ++k)
        col[k] = static_cast<std::size_t>(std::find(cells.begin(), cells.end(), kColumns[k]) - cells.begin());
      ncols = cells.size();
      continue;
    }
    if (cells.size() != ncols)
      throw InputError({source, lineno, ""}, fmt::format("expected {} cells (method, test, parameter, value), found {}",
                                                         ncols, cells.size()));
    for (std::size_t k = 0; k < 3; ++k)
      if (cells[col[k]].empty()) throw InputError({source, lineno, kColumns[k]}, "empty cell (expected a name)");
    const std::string& method = cells[col[0]];
    auto m = std::find(methods.begin(), methods.end(), method);
    if (m == methods.end()) {
      if (methods.size() == 2)
        throw InputError({source, lineno, "method"},
                         fmt::format("a third method '{}' (expected exactly two methods: '{}' and '{}')", method,
                                     methods[0], methods[1]));
      methods.push_back(method);
      m = methods.end() - 1;
    }
    const auto v = parse_number(cells[col[3]]);
    if (!v) throw InputError({source, lineno, "value"}, "expected a finite number, found '" + cells[col[3]] + "'");
    ComparisonValue cv;
    cv.method = static_cast<std::size_t>(m - methods.begin());
    cv.test = cells[col[1]];
    cv.parameter = cells[col[2]];
    cv.value = *v;
    cv.line = lineno;
    const auto [it, inserted] = seen.emplace(std::make_tuple(cv.method, cv.test, cv.parameter), lineno);
    if (!inserted)
      throw InputError({source, lineno, ""}, fmt::format("method '{}', test '{}', parameter '{}' is given twice "
                                                         "(first on line {})",
                                                         method, cv.test, cv.parameter, it->second));
    data.values.push_back(std::move(cv));
  }
  if (ncols == 0) throw InputError({source, 0, ""}, "no header line (expected 'method,test,parameter,value')");
  if (methods.size() != 2)
    throw InputError({source, 0, "method"},
                     methods.empty() ? std::string("no data rows (expected values of exactly two methods)")
                                     : "only one method, '" + methods[0] + "' (expected exactly two methods)");
  data.source = source;
  data.methods = {methods[0], methods[1]};
  return data;
}

ComparisonData read_comparison_csv(const std::string& path) {
  return parse_comparison_csv(read_text_file(path, "comparison CSV file"), path);
}

}  // namespace mtcal
