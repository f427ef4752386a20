// Calibration history records: one result of one command on one machine, and the events between.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mtcal {

// An input file of a recorded result and its content's SHA-256 (FIPS 180-4), lowercase hex.
struct InputHash {
  std::string path;    // as the command was given it
  std::string sha256;  // 64 hex digits
  friend bool operator==(const InputHash&, const InputHash&) = default;
};

// One identified or estimated model parameter of a result, by its ISO 230 name (EXX, EC0Y,
// EX0C ...), in the unit the result states it in.
struct RecordedParameter {
  std::string name;
  double value = 0;
  std::optional<double> uncertainty;  // standard uncertainty (k = 1), same unit, where the result has one
  std::string unit;                   // "mm", "um", "rad", "urad", "um/m" ...
  friend bool operator==(const RecordedParameter&, const RecordedParameter&) = default;
};

// One evaluation figure of a result: ISO 230-2 A, E, M, R, B for an axis ("A_X", "E_X"), ISO 230-4
// circular deviation ("G"), volumetric accuracy ("VA"), circularity ...
struct RecordedFigure {
  std::string name;
  double value = 0;
  std::string unit;
  std::optional<double> uncertainty;  // where the result states one (ISO 230-9 estimates)
  friend bool operator==(const RecordedFigure&, const RecordedFigure&) = default;
};

// One recorded result. Built by the recording program from the command's result JSON, the test
// metadata and its inputs; the store assigns id (when empty) and recorded_at (when empty) and
// computes content_hash.
struct CalibrationRecord {
  std::string id;                               // store-unique; assigned by record() when empty
  std::string machine_name;                     // metadata "machine", else the machine model's name
  std::string machine_serial;                   // metadata "serial"; may be empty
  std::string command;                          // "iso230-2", "identify", "ballbar", "volumetric" ...
  std::string recorded_at;                      // ISO 8601 UTC, "2026-11-25T03:04:05Z": when it was stored
  std::string measured_at;                      // ISO 8601 (date or date-time): metadata "date", else recorded_at
  std::map<std::string, std::string> metadata;  // the acceptance metadata (evaluation/metadata.hpp keys)
  std::vector<InputHash> inputs;
  std::vector<RecordedParameter> parameters;
  std::vector<RecordedFigure> figures;
  std::string result_json;   // the command's full --json output, compact
  std::string content_hash;  // SHA-256 of the inputs' hashes and the result: duplicates share it
  // How the command ran, for its report made again from the store (schema version 6): a JSON
  // object {"command_line", "options"} that the recording command writes (docs/history.md,
  // "Measurement files"); empty when unknown (older records, imports, uploads). Not part of
  // content_hash: the same result recorded twice is one record.
  std::string invocation;
  friend bool operator==(const CalibrationRecord&, const CalibrationRecord&) = default;
};

// Something that happened to a machine between calibrations; a trend report draws it on its time line.
enum class EventKind { CompensationLoaded, Crash, Repair, Other };
// "compensation-loaded", "crash", "repair", "other".
std::string_view to_string(EventKind k);
// The kind of "crash" ...; nullopt for an unknown name.
std::optional<EventKind> parse_event_kind(std::string_view name);

struct Event {
  std::string id;  // assigned by the store when empty
  std::string machine;
  std::string date;  // ISO 8601 date or date-time
  EventKind kind = EventKind::Other;
  std::string note;
  friend bool operator==(const Event&, const Event&) = default;
};

// One point of a time series: a parameter or figure of a machine at one calibration.
struct SeriesSample {
  std::string time;  // measured_at
  double value = 0;
  std::optional<double> uncertainty;
  std::string record_id;
  std::string unit;
};

// The latest value of a parameter or figure on one machine (fleet-wide queries).
struct LatestValue {
  std::string machine;
  SeriesSample sample;
};

// Filter of HistoryStore::list: empty strings match everything; from/to compare with measured_at
// as ISO 8601 text (inclusive; a date "2026-01-01" as `to` includes that day's date-times).
struct RecordFilter {
  std::string machine;
  std::string command;
  std::string from, to;
};

// Checks that text is an ISO 8601 date "YYYY-MM-DD" or date-time "YYYY-MM-DDThh:mm[:ss[.f]][Z|±hh:mm]".
bool is_iso8601(std::string_view text);

}  // namespace mtcal
