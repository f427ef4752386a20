// The calibration history store: results and events of machines kept in SQLite or PostgreSQL.
#pragma once

#include <cstddef>
#include <iosfwd>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mtcal/history/record.hpp"
#include "mtcal/io/system/sha256.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {

// A database could not be opened, read or written (the message names the store and the
// database's own message).
class StoreError : public Error {
 public:
  using Error::Error;
};

// What import_jsonl did.
struct ImportSummary {
  std::size_t records = 0, events = 0;  // added
  std::size_t model_files = 0;          // added (not stored before)
  std::vector<std::string> skipped;     // "line N: duplicate of record ID (content hash H)"
};

// Accounts of `mtcal serve` (schema version 3; docs/serve.md). A user's role is "viewer",
// "engineer" or "admin"; password_hash is what the server's KDF wrote (never the password).
struct UserAccount {
  std::string name, role, password_hash, created_at;
};
// A login session: the SHA-256 of its cookie value (the value itself is never stored), its CSRF
// token and when it expires (ISO 8601 UTC, compared as text).
struct SessionEntry {
  std::string id_hash, user, csrf_token, created_at, expires_at;
};
// Who wrote what: one row per record or event written through the server (action "record",
// "event"), in the same transaction as the write.
struct AuditEntry {
  std::string id, at, user, action, object_id, detail;
};
// A machine's calibration interval: `mtcal serve` shows its calibrations as overdue this many
// days after the latest of a kind (an admin sets it; machines without one use the server's
// default). set_by/set_at: who set it and when.
struct MachineInterval {
  std::string machine;
  int days = 0;
  std::string set_by, set_at;
};
// A machine's latest calibration by one command: the fleet's "last calibration per kind".
struct LatestCalibration {
  std::string machine, command, record_id, measured_at;
  long long count = 0;  // records of this machine and command
};

// A file a recorded result was computed from, kept once by the SHA-256 of its content (the key
// the records' inputs name): a machine file or a parameter file (schema version 5), so that a
// record's model can be made again (mtcal serve's "write compensation" of a record), or its
// measurements (schema version 6: iso230-2's positioning runs, ballbar's trace), so that the command's
// report can be made again (report/recorded.hpp).
struct ModelFile {
  std::string sha256;   // of content: 64 lowercase hex digits
  std::string kind;     // "machine", "parameters" or "measurements"
  std::string content;  // the file's text, UTF-8
  friend bool operator==(const ModelFile&, const ModelFile&) = default;
};

// A machine's revision: a number that every write of its records (record, import, remove) raises
// in the same transaction, never lowered or reused. Two reads that give a machine the same
// revision saw the same records of it: what was computed from them may be kept (mtcal serve's
// fleet ranking, also across server processes on one PostgreSQL store). Events do not change it.
struct MachineRevision {
  std::string machine;
  long long revision = 0;
  bool operator==(const MachineRevision&) const = default;
};

// A history store. Every write is one transaction: it happens completely or not at all.
// Concurrent writers (processes or threads, each with its own store object) lose nothing.
// One object is not meant to be shared between threads.
class HistoryStore {
 public:
  virtual ~HistoryStore() = default;

  // Stores r in one transaction and returns its id. Fills id (when empty: a new unique id),
  // recorded_at (when empty: now, UTC), measured_at (when empty: recorded_at) and content_hash.
  // Throws StoreError; InputError for a record without machine_name or command, or with a bad
  // date.
  virtual std::string record(CalibrationRecord r) = 0;
  // Removes a record (a command whose outputs failed after recording); false if there was none.
  virtual bool remove(const std::string& id) = 0;

  // Records in measured_at order (then recorded_at, id).
  virtual std::vector<CalibrationRecord> list(const RecordFilter& filter = {}) = 0;
  virtual std::optional<CalibrationRecord> get(const std::string& id) = 0;
  // The record with this content hash, if one is stored.
  virtual std::optional<std::string> find_by_content_hash(const std::string& content_hash) = 0;
  // Machine names, sorted.
  virtual std::vector<std::string> machines() = 0;

  // A parameter (ISO 230 name) or figure of one machine in measured_at order.
  virtual std::vector<SeriesSample> parameter_series(const std::string& machine, const std::string& parameter) = 0;
  virtual std::vector<SeriesSample> figure_series(const std::string& machine, const std::string& figure) = 0;
  // Per machine that has it, the latest (by measured_at) value of a parameter / figure, by machine.
  virtual std::vector<LatestValue> latest_parameter(const std::string& parameter) = 0;
  virtual std::vector<LatestValue> latest_figure(const std::string& figure) = 0;

  // Events: added in one transaction; listed in date order (machine empty: all machines).
  virtual std::string add_event(Event e) = 0;
  virtual std::vector<Event> events(const std::string& machine = {}) = 0;

  // Writes that name their author: the record / event and its audit row in one transaction.
  // A duplicate record (same content hash) returns the stored id and adds no audit row.
  // model_files: stored with it as record_all stores them.
  virtual std::string record_by(CalibrationRecord r, const std::string& user, std::vector<ModelFile> model_files = {}) = 0;
  virtual std::string add_event_by(Event e, const std::string& user) = 0;
  // The audit rows in time order; object_id non-empty: those of one record or event.
  virtual std::vector<AuditEntry> audit(const std::string& object_id = {}) = 0;
  // Per machine and command the latest record (measured_at, then recorded_at, id) and the count.
  virtual std::vector<LatestCalibration> latest_calibrations() = 0;
  // Sets (days > 0) or removes (days == 0) a machine's calibration interval, with an audit row
  // (action "interval") naming the user, in one transaction. InputError for an empty machine
  // name or days < 0. machine_intervals: every set interval, by machine.
  virtual void set_machine_interval(const std::string& machine, int days, const std::string& user) = 0;
  virtual std::vector<MachineInterval> machine_intervals() = 0;
  // Every machine that ever had a record, by name, with its revision (schema version 4).
  virtual std::vector<MachineRevision> machine_revisions() = 0;
  // The stored model file of this SHA-256, if any; every stored one, by SHA-256 (schema version 5).
  virtual std::optional<ModelFile> model_file(const std::string& sha256) = 0;
  virtual std::vector<ModelFile> model_files() = 0;

  // Accounts (names compared byte-wise). put_user inserts or replaces a user's role and hash.
  virtual void put_user(const UserAccount& u) = 0;
  virtual std::optional<UserAccount> find_user(const std::string& name) = 0;
  virtual std::vector<UserAccount> users() = 0;
  // Sessions: find_session returns one that has not expired at `now` (ISO 8601 UTC text);
  // remove_session ends one; remove_expired_sessions the ones expired at `now`.
  virtual void put_session(const SessionEntry& s) = 0;
  virtual std::optional<SessionEntry> find_session(const std::string& id_hash, const std::string& now) = 0;
  virtual bool remove_session(const std::string& id_hash) = 0;
  virtual long long remove_expired_sessions(const std::string& now) = 0;

  // The schema version of the open store (kHistorySchemaVersion after opening).
  virtual int schema_version() = 0;
  // "sqlite:/path/to/file" or "postgresql://host:port/db" (without a password).
  virtual std::string describe() const = 0;

  // Many records (and events) in ONE transaction: bulk import, benchmarks. Records whose
  // content hash is stored already (or repeated within `records`) are skipped and their
  // indices returned in `skipped` when given. model_files are stored in the same transaction,
  // each content once (one already stored under its SHA-256 is kept, even when the records are
  // duplicates); InputError for one whose SHA-256 is not its content's, of another kind than
  // "machine", "parameters" or "measurements", or not UTF-8.
  virtual std::vector<std::string> record_all(std::vector<CalibrationRecord> records, std::vector<Event> events = {},
                                              std::vector<std::size_t>* skipped = nullptr,
                                              std::vector<ModelFile> model_files = {}) = 0;
};

// The schema this program writes (docs/history.md lists the versions and their migrations).
inline constexpr int kHistorySchemaVersion = 6;

// Opens (creating it when absent, migrating it to kHistorySchemaVersion) the store named by
// connection: "postgresql://..." or "postgres://..." (libpq URI; also "postgresql:" followed by
// a libpq key=value string) for PostgreSQL, "sqlite:PATH" or a plain PATH for SQLite.
// Throws StoreError when it cannot be opened, InputError for an empty connection string.
std::unique_ptr<HistoryStore> open_history_store(const std::string& connection);

// Export: one JSON object per line, records in list() order, then events, then the model files
// by SHA-256, each with "type": "record", "event" or "model_file" ({"sha256", "kind",
// "content"}). The same store exports to the same bytes (every field in a fixed order).
void export_jsonl(HistoryStore& store, std::ostream& out);
// Import of what export_jsonl wrote, in one transaction: ids, recorded_at and content hashes
// kept; a record whose content hash is stored already is skipped (listed in the summary); an
// event whose id is stored already is skipped; a model file is stored unless its SHA-256 is.
// Throws InputError naming `source` and the line for a malformed line (a model file whose
// content is not its SHA-256's included), and imports nothing then.
ImportSummary import_jsonl(HistoryStore& store, std::istream& in, const std::string& source);

// JSON of one record / event as export_jsonl writes it (without the "type" key), and back
// (InputError located at where/line for a missing or mistyped field).
std::string record_to_json_line(const CalibrationRecord& r);
std::string event_to_json_line(const Event& e);

// A record built from a command's result JSON (what `mtcal CMD --json` prints): parameters and
// figures are taken from the keys each command documents (docs/history.md, "What is recorded").
// machine_name/serial/measured_at from metadata ("machine", "serial", "date") when present, else
// from the result's "machine" key. Throws InputError located at source for text that is not a
// JSON object.
CalibrationRecord record_from_result(const std::string& command, const std::string& result_json,
                                     const std::map<std::string, std::string>& metadata, std::vector<InputHash> inputs,
                                     const std::string& source = "result");

}  // namespace mtcal
