// The calibration history in the command: --record on result commands, `mtcal history ...`.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "common.hpp"
#include "mtcal/io/history/store.hpp"

namespace mtcal::cli {

// Global --record [STORE] and --no-record (before or after the command's name).
void add_record_options(CLI::App& app);
// Whether this run records its result: --record given, or the configuration's record: always,
// and not --no-record.
bool recording();

// A result command's JSON: noted for recording, printed when json_out. Returns json_out, so
// that a command writes `if (emit_json(j, o.json_out)) return 0;` and goes on to its text.
bool emit_json(Json j, bool json_out);
// The files the command reads (check_outputs passes them) and the model's machine name (load()).
void note_inputs(const std::vector<std::string>& inputs);
void note_machine(const std::string& name);
// The machine file and parameter files (-m, --params) the model was loaded from (load()): their
// text is stored with the recorded result (schema version 5), once per content.
void note_model_files(const std::string& machine, const std::vector<std::string>& params);
// The measurement file a command's report is drawn from and how the command ran (its options
// as {"command_line", "options", "report_metadata"}): stored with the recorded result (schema
// version 6), so that the report can be made again from the store (report/recorded.hpp).
void note_report_source(const std::string& measurements, Json invocation);

// Before the command runs, when recording: checks the --record value and opens the store
// (created or migrated), so that a bad store fails first, as one line, before any work.
void prepare_recording();
// Stores the noted result of `command` when recording (one transaction), and says so on stderr
// ("mtcal: recorded ID in STORE"). Called after the command ran and before its output files
// appear; returns the new record's id (nullopt when not recording or a duplicate).
// Throws when recording was asked for and the command noted no result.
std::optional<std::string> record_result(const std::string& command);
// Takes a record out again (the command's outputs failed after it was recorded).
void unrecord(const std::string& id);

// The store of a history command: `given` (its --store), else $MTCAL_HISTORY, else the
// configuration file's history.store. InputError naming all three when none is set.
std::unique_ptr<HistoryStore> open_cli_store(const std::string& given);
// The configuration file in use: $MTCAL_CONFIG, else $XDG_CONFIG_HOME/mtcal/config.yaml, else
// ~/.config/mtcal/config.yaml.
std::string config_path();

// `mtcal history` and its subcommands list, show, import, export, event add. history_app() is
// the `history` command, for more subcommands (diff, trend, rank) to be added to it.
std::vector<Command> add_history_commands(CLI::App& app);
CLI::App* history_app();

}  // namespace mtcal::cli
