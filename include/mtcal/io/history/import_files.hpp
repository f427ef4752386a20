// The files `history import` records one by one: a command's result JSON (the command named or told from its keys), or
// an instrument file of positioning runs evaluated to ISO 230-2.
#pragma once

#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "mtcal/history/record.hpp"
#include "mtcal/io/history/store.hpp"
#include "mtcal/io/json/json.hpp"

namespace mtcal {

// The command a result JSON came from, by the keys its --json documents (docs/history.md):
// "iso230-2", "ballbar", "volumetric" or "identify"; "" when the keys fit none of them.
std::string result_command(const Json& result);

// The record of one file, as `mtcal history import FILE` stores it (the file's SHA-256 its input):
// - a command's result JSON (what `mtcal CMD --json` prints): recorded as that command's result,
//   `command` naming it, or, when empty, told from its keys (result_command);
// - else an instrument file of positioning runs (a laser file, the table or .dat forms; read
//   as `mtcal iso230-2` reads it, in mm), evaluated to ISO 230-2 with the file header's metadata.
// `metadata` wins over what the file says. Throws InputError located at path for JSON that is not
// an object, and RequestError (causes "command" / "machine") for a result whose command cannot be
// told from its keys or that names no machine.
CalibrationRecord record_from_file(const std::string& path, const std::string& command,
                                   const std::map<std::string, std::string>& metadata);

// What `mtcal history import FILE...` stored: the records of the result and instrument files (in
// the order given), then what the JSON-lines exports (*.jsonl) held.
struct HistoryImport {
  std::vector<CalibrationRecord> records;  // of the result and instrument files
  std::vector<std::string> origin;         // the file of each record
  std::vector<std::string> ids;            // each record's id (the stored one for a duplicate)
  std::vector<std::size_t> duplicates;     // indices into records stored already (same content hash)
  std::vector<std::string> skipped;        // "FILE: why" per record not stored
  std::size_t added = 0, events = 0;       // records and events added
  std::size_t model_files = 0;             // model files added (of JSON-lines exports)
};

// Imports files into store: every result or instrument file read first (record_from_file with
// command and metadata; a bad one throws before anything is stored) and its records stored in one
// transaction after the JSON-lines files (import_jsonl: ids kept, records stored already skipped).
HistoryImport import_files(HistoryStore& store, const std::vector<std::string>& files, const std::string& command,
                           const std::map<std::string, std::string>& metadata);

// A model file of a recorded result as the store keeps it (docs/history.md, "Model files"): its
// text and SHA-256, kind "machine", "parameters" or "measurements" (its measurements, schema
// version 6; capped as every text file read, input_limits().text); nullopt when the text is not UTF-8 (the store
// keeps text only). Throws InputError when the file cannot be read. `mtcal CMD --record` and
// Python's HistoryStore.record keep the machine file and parameter files the result was made with.
std::optional<ModelFile> read_model_file(const std::string& kind, const std::string& path);

// {"store", "records_added", "events_added", "model_files_added", "skipped", "records": [{"file",
// "id"}]}: `history import --json` (store: the store's description).
Json to_json(const HistoryImport& r, const std::string& store);

}  // namespace mtcal
