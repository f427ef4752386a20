#include "mtcal/io/text/csv.hpp"
#include "mtcal/io/system/files.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "mtcal/util/errors.hpp"
#include "mtcal/util/parse.hpp"

namespace mtcal {
namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ',')) out.push_back(trim(cell));
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

}  // namespace

int TextTable::column(const std::string& name) const {
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i] == name) return static_cast<int>(i);
  return -1;
}

std::vector<std::size_t> TextTable::require_columns(const std::vector<std::string>& names,
                                                    const std::string& source) const {
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
  for (const auto& c : columns)
    if (std::find(names.begin(), names.end(), c) == names.end())
      throw InputError({source, header_line, c}, "unknown column '" + printable(c) + "' (expected " + list + ")");
  std::vector<std::size_t> idx;
  for (const auto& n : names) {
    const int c = column(n);
    if (c < 0)
      throw InputError({source, header_line, ""}, "missing column '" + printable(n) + "' (expected " + list + ")");
    idx.push_back(static_cast<std::size_t>(c));
  }
  return idx;
}

TextTable parse_text_csv(const std::string& text, const std::string& source) {
  TextTable t;
  // Spreadsheets often start their CSV exports with a UTF-8 byte order mark.
  const bool bom = text.rfind("\xEF\xBB\xBF", 0) == 0;
  std::istringstream in(bom ? text.substr(3) : text);
  std::string line;
  int lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    const std::string s = trim(line);
    if (s.empty() || s[0] == '#') continue;
    auto cells = split(s);
    if (t.header_line == 0) {
      for (const auto& c : cells) {
        if (c.empty()) throw InputError({source, lineno, ""}, "empty column name in the header");
        if (t.column(c) >= 0) throw InputError({source, lineno, c}, "duplicated column '" + printable(c) + "'");
        t.columns.push_back(c);
      }
      t.header_line = lineno;
      continue;
    }
    if (cells.size() != t.columns.size())
      throw InputError({source, lineno, ""}, "expected " + std::to_string(t.columns.size()) +
                                                 " values (one per header column), found " +
                                                 std::to_string(cells.size()));
    t.rows.push_back(std::move(cells));
    t.lines.push_back(lineno);
  }
  if (t.header_line == 0) throw InputError({source, 0, ""}, "no header line naming the columns");
  return t;
}

TextTable read_text_csv(const std::string& path, const std::string& what) {
  return parse_text_csv(read_text_file(path, what), path);
}

int CsvTable::column(const std::string& name) const {
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i] == name) return static_cast<int>(i);
  return -1;
}

CsvTable parse_csv(const std::string& text, const std::string& source) {
  const TextTable text_table = parse_text_csv(text, source);
  CsvTable t;
  t.columns = text_table.columns;
  t.lines = text_table.lines;
  for (std::size_t r = 0; r < text_table.rows.size(); ++r) {
    std::vector<double> row;
    for (std::size_t i = 0; i < text_table.columns.size(); ++i) {
      const std::string& cell = text_table.rows[r][i];
      const auto v = parse_number(cell);
      if (!v)
        throw InputError({source, text_table.lines[r], t.columns[i]},
                         "expected a finite number, found '" + printable(cell) + "'");
      row.push_back(*v);
    }
    t.rows.push_back(std::move(row));
  }
  return t;
}

CsvTable read_csv(const std::string& path) { return parse_csv(read_text_file(path, "CSV file"), path); }

}  // namespace mtcal
