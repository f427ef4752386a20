// Method comparison: reads the long "method,test,parameter,value" table and computes per-parameter statistics.
#include "mtcal/evaluation/compare.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <tuple>

#include <fmt/format.h>

#include "mtcal/io/files.hpp"
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

// Mean and sample standard deviation of v (n >= 1); the deviation is exactly 0 for equal
// values, which the two-pass formula could leave at a rounding residue.
std::pair<double, std::optional<double>> mean_stdev(const std::vector<double>& v) {
  const double n = static_cast<double>(v.size());
  double sum = 0;
  for (double x : v) sum += x;
  const double mean = sum / n;
  if (v.size() < 2) return {mean, std::nullopt};
  if (std::all_of(v.begin(), v.end(), [&](double x) { return x == v.front(); })) return {v.front(), 0.0};
  double ss = 0;
  for (double x : v) ss += (x - mean) * (x - mean);
  return {mean, std::sqrt(ss / (n - 1))};
}

// Pearson r of paired values; absent below 3 pairs or when either side is constant (r is then
// 0/0, not a measure of agreement).
std::optional<double> pearson(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() < 3) return std::nullopt;
  auto constant = [](const std::vector<double>& v) {
    return std::all_of(v.begin(), v.end(), [&](double x) { return x == v.front(); });
  };
  if (constant(a) || constant(b)) return std::nullopt;
  const double ma = mean_stdev(a).first, mb = mean_stdev(b).first;
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  if (!(saa > 0) || !(sbb > 0)) return std::nullopt;
  return std::clamp(sab / std::sqrt(saa * sbb), -1.0, 1.0);
}

}  // namespace

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
                         "found '" + join(cells) + "'");
      for (std::size_t k = 0; k < kColumns.size(); ++k)
        col[k] = static_cast<std::size_t>(std::find(cells.begin(), cells.end(), kColumns[k]) - cells.begin());
      ncols = cells.size();
      continue;
    }
    if (cells.size() != ncols)
      throw InputError({source, lineno, ""},
                       fmt::format("expected {} cells (method, test, parameter, value), found {}", ncols, cells.size()));
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
  data.methods = {methods[0], methods[1]};
  return data;
}

ComparisonData read_comparison_csv(const std::string& path) {
  return parse_comparison_csv(read_text_file(path, "comparison CSV file"), path);
}

MethodComparison compare_methods(const ComparisonData& data) {
  MethodComparison out;
  out.methods = data.methods;
  // Per parameter in order of first appearance, per method, its (test, value) pairs in file order.
  struct Series {
    std::string name;
    std::array<std::vector<std::pair<std::string, double>>, 2> by_method;
  };
  std::vector<Series> series;
  std::map<std::string, std::size_t> index;
  for (const auto& v : data.values) {
    const auto [it, inserted] = index.emplace(v.parameter, series.size());
    if (inserted) series.push_back({v.parameter, {}});
    series[it->second].by_method[v.method].emplace_back(v.test, v.value);
  }

  ComparisonSummary& sum = out.summary;
  for (const auto& s : series) {
    ParameterComparison p;
    p.name = s.name;
    for (std::size_t k = 0; k < 2; ++k) {
      std::vector<double> values;
      for (const auto& tv : s.by_method[k]) values.push_back(tv.second);
      p.stats[k].n = values.size();
      if (!values.empty()) std::tie(p.stats[k].mean, p.stats[k].stdev) = mean_stdev(values);
    }
    const auto& a = p.stats[0];
    const auto& b = p.stats[1];
    if (a.mean && b.mean) p.abs_diff = std::abs(*a.mean - *b.mean);
    if (a.stdev && b.stdev) p.overlap = *p.abs_diff <= *a.stdev + *b.stdev;
    std::vector<double> pa, pb;
    for (const auto& [test, value] : s.by_method[0]) {
      const auto& other = s.by_method[1];
      const auto hit = std::find_if(other.begin(), other.end(), [&test = test](const auto& tv) { return tv.first == test; });
      if (hit == other.end()) continue;
      pa.push_back(value);
      pb.push_back(hit->second);
    }
    p.paired = pa.size();
    p.pearson_r = pearson(pa, pb);

    ++sum.parameters;
    if (a.n > 0 && b.n > 0)
      ++sum.both_methods;
    else
      sum.one_method_only.push_back(p.name);
    if (p.overlap) ++(*p.overlap ? sum.overlap : sum.no_overlap);
    if (p.pearson_r) {
      ++sum.with_correlation;
      if (std::abs(*p.pearson_r) >= kStrongCorrelation) ++sum.strong_correlation;
      if (*p.pearson_r >= kStrongCorrelation) ++sum.strong_positive;
      if (*p.pearson_r <= -kStrongCorrelation) ++sum.strong_negative;
    }
    out.parameters.push_back(std::move(p));
  }
  return out;
}

}  // namespace mtcal
