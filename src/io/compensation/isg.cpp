#include "mtcal/io/compensation/isg.hpp"

#include <fmt/format.h>

namespace mtcal {

TargetOutput isg_output(const IsgCompensation& c) {
  TargetOutput out;
  out.summary = c.summary;
  std::string text =
      "// Written by mtcal compensate --format isg: ISO 230-1/-7 errors (e = actual - nominal) of the machine model,\n"
      "// values in mm and rad, arguments in mm and deg (TF5280 Volumetric Compensation, ISG CSV format).\n";
  bool first = true;
  auto block = [&](std::string header, const std::vector<std::string>& rows) {
    if (!first) text += "#\n";
    first = false;
    text += header + "\n";
    for (const auto& r : rows) text += r + "\n";
  };
  if (!c.position_errors.empty()) {
    std::string header, row;
    for (const auto& [name, value] : c.position_errors) {
      header += (header.empty() ? "" : " ") + name;
      row += (row.empty() ? "" : " ") + fmt::format("{:.12g}", value);
    }
    block("// position errors\n" + header, {row});
  }
  for (const auto& t : c.tables) {
    std::string header = fmt::format("// component errors of {}\n{}", t.axis, t.axis);
    for (const auto& n : t.names) header += " " + n;
    std::vector<std::string> rows;
    for (std::size_t i = 0; i < t.position.size(); ++i) {
      std::string row = fmt::format("{:.9f}", t.position[i]);
      for (const auto& v : t.values) row += fmt::format(" {:.12g}", v[i]);
      rows.push_back(std::move(row));
    }
    block(header, rows);
  }
  out.files.push_back({"volcomp.csv", std::move(text)});
  return out;
}

}  // namespace mtcal
