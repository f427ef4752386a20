#include "mtcal/io/csv.hpp"
#include "mtcal/io/files.hpp"

#include <cmath>
#include <sstream>

#include "mtcal/util/errors.hpp"
#include "mtcal/util/parse.hpp"

namespace mtcal {
namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ',')) out.push_back(trim(cell));
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

}  // namespace

int CsvTable::column(const std::string& name) const {
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i] == name) return static_cast<int>(i);
  return -1;
}

CsvTable parse_csv(const std::string& text, const std::string& source) {
  CsvTable t;
  // Spreadsheets often start their CSV exports with a UTF-8 byte order mark.
  const bool bom = text.rfind("\xEF\xBB\xBF", 0) == 0;
  std::istringstream in(bom ? text.substr(3) : text);
  std::string line;
  int lineno = 0;
  bool header = false;
  while (std::getline(in, line)) {
    ++lineno;
    const std::string s = trim(line);
    if (s.empty() || s[0] == '#') continue;
    auto cells = split(s);
    if (!header) {
      for (const auto& c : cells) {
        if (c.empty()) throw InputError({source, lineno, ""}, "empty column name in the header");
        if (t.column(c) >= 0) throw InputError({source, lineno, c}, "duplicated column '" + c + "'");
        t.columns.push_back(c);
      }
      header = true;
      continue;
    }
    if (cells.size() != t.columns.size())
      throw InputError({source, lineno, ""}, "expected " + std::to_string(t.columns.size()) +
                                                 " values (one per header column), found " +
                                                 std::to_string(cells.size()));
    std::vector<double> row;
    for (std::size_t i = 0; i < cells.size(); ++i) {
      const auto v = parse_number(cells[i]);
      if (!v)
        throw InputError({source, lineno, t.columns[i]},
                         "expected a finite number, found '" + cells[i] + "'");
      row.push_back(*v);
    }
    t.rows.push_back(std::move(row));
    t.lines.push_back(lineno);
  }
  if (!header) throw InputError({source, 0, ""}, "no header line naming the columns");
  return t;
}

CsvTable read_csv(const std::string& path) { return parse_csv(read_text_file(path, "CSV file"), path); }

}  // namespace mtcal
