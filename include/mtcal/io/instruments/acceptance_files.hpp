// Acceptance-report inputs: the metadata YAML and the tolerance YAML, and the tolerances as history bands.
#pragma once

#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "mtcal/evaluation/tolerance.hpp"
#include "mtcal/history/analysis.hpp"
#include "mtcal/evaluation/metadata.hpp"

namespace mtcal {

// A metadata file: one YAML map of known keys (metadata_fields()) to scalar values, e.g.
//   machine: HU40T
//   serial: "4711"
//   date: 2026-11-24
//   temperature_air: 20.2 °C
// Throws InputError (file, line, key) for anything else.
ReportMetadata parse_report_metadata(std::string_view yaml_text, const std::string& source);
ReportMetadata read_report_metadata(const std::string& path);

// A tolerance file (docs/reports.md):
//   unit: um              # um (default) or mm: the unit of every value below
//   iso230-2:             # per axis (as in --meta axis=X); "any" for axes not listed
//     X: {A: 16, E: 10, M: 8, R: 6, B: 4}
//     any: {A: 25}
//   iso230-4: {G: 15, F: 10, H: 8}
//   volumetric: {VA: 30}
// Values are converted to µm. Throws InputError (file, line, key) for an unknown section,
// quantity or unit, a value that is not a number >= 0.
struct ToleranceFile {
  std::map<std::string, Tolerances> iso230_2;  // axis name (or "any") -> limits
  Tolerances iso230_4, volumetric;
  // The ISO 230-2 limits of this axis, else those of "any", else none.
  Tolerances iso230_2_for(const std::string& axis) const;
};
ToleranceFile parse_tolerance_file(std::string_view yaml_text, const std::string& source);
ToleranceFile read_tolerance_file(const std::string& path);

// The limits of a tolerance file (docs/reports.md) as bands of the figures record_from_result
// names (docs/history.md): ISO 230-2 quantity Q of axis X limits figure "Q_X" (the section "any"
// every axis in `axes` the file does not list, and "Q" recorded without an axis), value <= limit;
// ISO 230-4 G limits G_b, G_cw, G_ccw, F limits |F_max| and |F_min|, H limits H; volumetric VA
// limits va, VAx va_x .... Values in µm, as the file's were converted.
std::map<std::string, ToleranceBand> history_figure_bands(const ToleranceFile& f, const std::vector<std::string>& axes);

}  // namespace mtcal
