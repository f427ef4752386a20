// Pieces the history store's backends share: the content hash, ids, times and the SQL layer.
#pragma once

#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "mtcal/io/history/store.hpp"

namespace mtcal::history_detail {

// SHA-256 over what identifies a result: command, machine, measured_at, metadata, the inputs'
// hashes (not their paths), parameters, figures and the result JSON. recorded_at and id are not
// part of it, so that the same result recorded twice or re-imported is known as a duplicate.
std::string content_hash(const CalibrationRecord& r);
// A new random record / event id: 16 lowercase hex digits.
std::string new_id();
// Now, UTC, "2026-11-25T03:04:05.123Z".
std::string now_utc();
// Checks a record before it is stored (InputError naming the record and field).
void check_record(const CalibrationRecord& r);
void check_event(const Event& e);
// InputError located at `where` for a model file whose sha256 is not its content's, whose kind
// is not "machine" or "parameters", or whose content is not UTF-8.
void check_model_file(const ModelFile& f, const std::string& where);
// JSON text of a record's metadata / inputs (as stored in their columns), and back.
std::string metadata_to_json(const std::map<std::string, std::string>& m);
std::map<std::string, std::string> metadata_from_json(const std::string& text);
std::string inputs_to_json(const std::vector<InputHash>& in);
std::vector<InputHash> inputs_from_json(const std::string& text);
// Shortest text that reads back as the same double (std::to_chars), and its reading.
std::string double_text(double v);
double parse_double_text(const std::string& text);

// A statement parameter: NULL, text, a double or an integer.
using SqlParam = std::variant<std::nullptr_t, std::string, double, long long>;
// A result row: a cell is nullopt for SQL NULL, else its text (doubles as double_text).
using SqlRow = std::vector<std::optional<std::string>>;

// The history store over any SQL database with $1-style parameters, ON CONFLICT DO NOTHING,
// RETURNING and window functions (SQLite >= 3.35, PostgreSQL >= 9.5): every query and the schema
// are the same for both (docs/history.md).
class SqlHistoryStore : public HistoryStore {
 public:
  std::string record(CalibrationRecord r) override;
  bool remove(const std::string& id) override;
  std::vector<CalibrationRecord> list(const RecordFilter& filter) override;
  std::optional<CalibrationRecord> get(const std::string& id) override;
  std::optional<std::string> find_by_content_hash(const std::string& content_hash) override;
  std::vector<std::string> machines() override;
  std::vector<SeriesSample> parameter_series(const std::string& machine, const std::string& parameter) override;
  std::vector<SeriesSample> figure_series(const std::string& machine, const std::string& figure) override;
  std::vector<LatestValue> latest_parameter(const std::string& parameter) override;
  std::vector<LatestValue> latest_figure(const std::string& figure) override;
  std::string add_event(Event e) override;
  std::vector<Event> events(const std::string& machine) override;
  int schema_version() override;
  std::string record_by(CalibrationRecord r, const std::string& user, std::vector<ModelFile> model_files = {}) override;
  std::string add_event_by(Event e, const std::string& user) override;
  std::vector<AuditEntry> audit(const std::string& object_id) override;
  std::vector<LatestCalibration> latest_calibrations() override;
  void set_machine_interval(const std::string& machine, int days, const std::string& user) override;
  std::vector<MachineInterval> machine_intervals() override;
  std::vector<MachineRevision> machine_revisions() override;
  std::optional<ModelFile> model_file(const std::string& sha256) override;
  std::vector<ModelFile> model_files() override;
  void put_user(const UserAccount& u) override;
  std::optional<UserAccount> find_user(const std::string& name) override;
  std::vector<UserAccount> users() override;
  void put_session(const SessionEntry& s) override;
  std::optional<SessionEntry> find_session(const std::string& id_hash, const std::string& now) override;
  bool remove_session(const std::string& id_hash) override;
  long long remove_expired_sessions(const std::string& now) override;
  // The base's defaults (a call on this type takes them too).
  std::vector<std::string> record_all(std::vector<CalibrationRecord> records, std::vector<Event> events = {},
                                      std::vector<std::size_t>* skipped = nullptr,
                                      std::vector<ModelFile> model_files = {}) override;

 protected:
  // Runs a statement; returns the number of rows it changed.
  virtual long long exec(const std::string& sql, const std::vector<SqlParam>& params = {}) = 0;
  virtual std::vector<SqlRow> query(const std::string& sql, const std::vector<SqlParam>& params = {}) = 0;
  // A write transaction that holds the database's write lock from its start (SQLite: BEGIN
  // IMMEDIATE, so that two writers never deadlock upgrading a read lock).
  virtual void begin_write() = 0;
  virtual void commit() = 0;
  virtual void rollback() noexcept = 0;
  // Serialises concurrent migrations of one database (PostgreSQL: a transaction advisory lock);
  // called inside the migration's transaction.
  virtual void lock_for_migration() {}
  // The column type of text that sorts byte-wise (ISO 8601 times, names): SQLite's TEXT sorts
  // so (BINARY); PostgreSQL's would follow the database's locale without COLLATE "C".
  virtual std::string text_type() const = 0;
  virtual bool table_exists(const std::string& name) = 0;
  // Creates or upgrades the schema to kHistorySchemaVersion; call once connected.
  void migrate();

 private:
  std::vector<SeriesSample> series(const char* table, const std::string& machine, const std::string& name);
  std::vector<LatestValue> latest(const char* kind, const std::string& name);
  void insert_rows(const std::string& head, std::size_t columns, const std::vector<SqlParam>& values,
                   const std::string& tail = {});
  // record_all, with an audit row per inserted record and event when author is given.
  std::vector<std::string> write_all(std::vector<CalibrationRecord> records, std::vector<Event> events,
                                     std::vector<std::size_t>* skipped, const std::string* author,
                                     const std::vector<ModelFile>& model_files = {});
  std::vector<CalibrationRecord> load_records(const std::string& where, const std::vector<SqlParam>& params);
};

std::unique_ptr<HistoryStore> open_sqlite_store(const std::string& path);
std::unique_ptr<HistoryStore> open_postgres_store(const std::string& conninfo);

}  // namespace mtcal::history_detail
