// Numeric CSV tables with a header row, read with located errors.
#pragma once

#include <string>
#include <vector>

namespace mtcal {

// A CSV table of text cells: the first non-comment line names the columns (none empty, none
// twice); '#' lines and blank lines are skipped; a UTF-8 byte order mark is ignored; every row
// has one cell per column. The numeric table and the other readers build on it.
struct TextTable {
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> rows;
  std::vector<int> lines;  // 1-based source line of each row
  int header_line = 0;

  int column(const std::string& name) const;  // index, or -1
  // The indices of exactly these columns, in this order: InputError naming the header line for
  // a column that is not one of them or one that is missing.
  std::vector<std::size_t> require_columns(const std::vector<std::string>& names, const std::string& source) const;
};
TextTable parse_text_csv(const std::string& text, const std::string& source);
TextTable read_text_csv(const std::string& path, const std::string& what = "CSV file");

struct CsvTable {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;  // every row has columns.size() values
  std::vector<int> lines;                 // 1-based source line of each row

  // Index of a column by exact name, or -1.
  int column(const std::string& name) const;
};

// Reads a comma-separated file whose first non-comment line names the columns. Lines starting
// with '#' and blank lines are skipped. Every value must be a finite number. Throws InputError
// naming file, line and column.
CsvTable read_csv(const std::string& path);
CsvTable parse_csv(const std::string& text, const std::string& source);

}  // namespace mtcal
