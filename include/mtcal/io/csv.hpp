// Numeric CSV tables with a header row, read with located errors.
#pragma once

#include <string>
#include <vector>

namespace mtcal {

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
