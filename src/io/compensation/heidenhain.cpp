#include "mtcal/io/compensation/heidenhain.hpp"

#include <fmt/format.h>

namespace mtcal {

namespace {

// TNC tables are fixed-width: each column as wide as its header field, values left-aligned with
// their sign, as the control's table editor shows them.
constexpr int kNr = 6, kPos = 16, kValue = 16;

std::string signed_number(double v, int decimals) {
  std::string s = fmt::format("{:+.{}f}", v, decimals);
  if (s == fmt::format("-{:.{}f}", 0.0, decimals)) s[0] = '+';  // no "-0.000"
  return s;
}

}  // namespace

TargetOutput heidenhain_output(const HeidenhainCompensation& c) {
  TargetOutput out;
  out.summary = c.summary;
  std::string cma_header = fmt::format("{:<{}}{:<{}}", "NR", kNr, "ACTIVE", 8);
  std::string cma_row = fmt::format("{:<{}}{:<{}}", 0, kNr, "*", 8);
  std::string readme =
      "HEIDENHAIN nonlinear axis-error compensation, written by mtcal compensate --format heidenhain.\n"
      "\n"
      "Files:\n";
  for (const auto& t : c.tables) {
    const std::string name = fmt::format("{}.COM", t.axis);
    std::string text = fmt::format("BEGIN {} MM\n", name);
    std::string header = fmt::format("{:<{}}{:<{}}", "NR", kNr, "AXISPOS", kPos);
    for (const char col : t.columns) header += fmt::format("{:<{}}", std::string(1, col), kValue);
    while (!header.empty() && header.back() == ' ') header.pop_back();
    text += header + "\n";
    for (std::size_t i = 0; i < t.position.size(); ++i) {
      std::string line = fmt::format("{:<{}}{:<{}}", i, kNr, signed_number(t.position[i], 6), kPos);
      for (const auto& v : t.values) line += fmt::format("{:<{}}", signed_number(v[i], 9), kValue);
      while (!line.empty() && line.back() == ' ') line.pop_back();
      text += line + "\n";
    }
    text += "[END]\n";
    out.files.push_back({name, std::move(text)});
    cma_header += fmt::format("{:<{}}", std::string(1, t.axis), kValue);
    cma_row += fmt::format("{:<{}}", name, kValue);
    readme += fmt::format(
        "  {}: compensation values of axes {} as functions of the {} position (AXISPOS, mm from the\n"
        "         machine datum), {} points\n",
        name, t.columns, t.axis, t.position.size());
  }
  while (!cma_header.empty() && cma_header.back() == ' ') cma_header.pop_back();
  while (!cma_row.empty() && cma_row.back() == ' ') cma_row.pop_back();
  out.files.push_back({"config.cma", "BEGIN config.cma\n" + cma_header + "\n" + cma_row + "\n[END]\n"});
  readme +=
      "  config.cma: one active line (ACTIVE *) assigning each *.COM to its argument axis:\n"
      "         [axis of a *.COM column] = F(axis of the *.CMA column it is entered in).\n"
      "\n"
      "Numbers: the ERROR e = actual - nominal of the tool point along each column's axis, in mm; the control is\n"
      "assumed to move the axis by -value. This sign is NOT confirmed by a public HEIDENHAIN document: it MUST BE\n"
      "CHECKED ON THE CONTROL (activate, move to a table point with a large value, compare with a measurement).\n"
      "A column of another axis holds that axis's error caused by this axis's motion (straightness, sag), less\n"
      "its value at the reference position; only the mean of both directions is written (no BACKLASH column).\n"
      "\n"
      "Loading: copy the *.COM files and config.cma to the control (PLC partition, as the machine's existing\n"
      "compensation tables); rename the columns to the axis keys of CfgAxes/axisList if they differ; enable the\n"
      "nonlinear axis-error compensation in the machine configuration and select the active *.CMA line; restart.\n"
      "Check the column widths against a table the control itself wrote: the table editor may round the values.\n";
  out.files.push_back({"README.txt", std::move(readme)});
  return out;
}

}  // namespace mtcal
