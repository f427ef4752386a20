// Renishaw LaserXL / CARTO ASCII exports of a laser test: linear (.rtl) and rotary (.rta) runs.
#pragma once

#include <string>

#include "mtcal/evaluation/iso230_2.hpp"
#include "mtcal/evaluation/metadata.hpp"

namespace mtcal {

// One laser test as its file gives it (docs/instrument-files.md): the runs as deviations per
// target (targets in mm or deg, deviations in um, or arcsec for a rotary test, unless the header
// says other units), the test's kind and axis, and every metadata line (machine, serial number,
// date, environment, equipment) in runs.metadata as "SECTION/key".
struct LaserFile {
  PositioningRuns runs;
  std::string kind;       // "linear", "rotary", "straightness" or "angular"
  std::string axis;       // the USER-TEXT Axis (upper case), empty if not given
  std::string component;  // the ISO 230-1 error the deviations are, when the file names it (Error: EYX)
  bool bidirectional = true;
};

// Sections HEADER::, TARGET DATA:: (Target-count:, Targets :), USER-TEXT::, RUNS:: (Run-count:),
// DEVIATIONS:: (Run Target Data: then rows "run target deviation"), ENVIRONMENT::, EQUIPMENT::.
// Runs alternate direction: odd runs approach in the order of the targets, even runs against it
// (RUNS:: Direction: unidirectional makes every run go in the targets' order). An unknown
// section or key is kept as metadata with a warning. Throws InputError with file, line and field
// for a missing mandatory field, a Target-count other than the number of targets, a run that
// lacks a target or has one twice, a run or target number out of range, a cell that is not a
// number, and units that do not go together. rotary: the .rta defaults (deg, arcsec).
LaserFile parse_laser_file(const std::string& text, const std::string& source, bool rotary);
// By extension: .rta rotary, anything else linear (a HEADER Type: line overrides both).
LaserFile read_laser_file(const std::string& path);
// The .rtl / .rta extension, or a line "HEADER::" near the top.
bool looks_like_laser(const std::string& path);

// The ISO 230-1 motion error a laser file measured, when it says so: its Error: line, else a
// linear test of axis X -> EXX, a rotary test of axis C -> ECC. Empty when the file does not say
// (a straightness or angular test without Error:, or no Axis:).
std::string laser_error_name(const LaserFile& file);

// The acceptance-report fields a laser file's header states (docs/instrument-files.md, "Report
// metadata"), from runs.metadata ("SECTION/key" pairs): USER-TEXT (or HEADER) Machine -> machine,
// Serial -> serial, Owner/Customer -> owner, Location -> location, Operator -> operator, Date ->
// date, Axis -> axis; ENVIRONMENT Air / Machine / Material temperature -> temperature_air /
// _machine / _material, Temperature -> temperature, Humidity -> humidity; EQUIPMENT Laser (or
// Instrument) -> instrument, its Serial -> instrument_serial, Calibration date / Calibration
// certificate -> calibration_date / calibration_certificate, any other equipment line (a
// compensator, sensors) appended to instrument as "key value". Keys are matched without regard
// to case; a key met twice keeps its first value; empty values are skipped. The caller merges
// the result under what the user typed (ReportMetadata::fill_missing_from).
ReportMetadata laser_report_metadata(const PositioningRuns& runs);

}  // namespace mtcal
