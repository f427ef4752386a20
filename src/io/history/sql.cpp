// The history store's schema, migrations and queries, shared by the SQLite and PostgreSQL backends.
#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <ctime>
#include <random>
#include <map>
#include <set>
#include <tuple>
#include <unordered_map>
#include <unordered_set>

#include <unistd.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "internal.hpp"
#include "mtcal/io/json/json.hpp"

namespace mtcal::history_detail {

namespace {

using nlohmann::ordered_json;

// Schema migrations in order: migration i brings the store from version i to version i + 1.
// {T} is the byte-wise sorted text type (text_type()). A released migration is never edited: a
// change of schema is a new entry (docs/history.md, "Schema versions").
struct Migration {
  const char* description;
  std::vector<const char*> statements;
};

const std::vector<Migration>& migrations() {
  static const std::vector<Migration> kMigrations{
      {"records, parameters, figures, events",
       {"CREATE TABLE records (id {T} PRIMARY KEY, machine_name {T} NOT NULL, machine_serial {T} NOT NULL, "
        "command {T} NOT NULL, recorded_at {T} NOT NULL, measured_at {T} NOT NULL, metadata TEXT NOT NULL, "
        "inputs TEXT NOT NULL, result_json TEXT NOT NULL, content_hash {T} NOT NULL UNIQUE)",
        "CREATE INDEX records_machine_time ON records (machine_name, measured_at, recorded_at)",
        "CREATE TABLE parameters (record_id {T} NOT NULL REFERENCES records (id) ON DELETE CASCADE, "
        "position INTEGER NOT NULL, machine_name {T} NOT NULL, measured_at {T} NOT NULL, recorded_at {T} NOT NULL, "
        "name {T} NOT NULL, value DOUBLE PRECISION NOT NULL, uncertainty DOUBLE PRECISION, unit TEXT NOT NULL, "
        "PRIMARY KEY (record_id, position))",
        "CREATE INDEX parameters_series ON parameters (machine_name, name, measured_at)",
        "CREATE INDEX parameters_fleet ON parameters (name, machine_name, measured_at)",
        "CREATE TABLE figures (record_id {T} NOT NULL REFERENCES records (id) ON DELETE CASCADE, "
        "position INTEGER NOT NULL, machine_name {T} NOT NULL, measured_at {T} NOT NULL, recorded_at {T} NOT NULL, "
        "name {T} NOT NULL, value DOUBLE PRECISION NOT NULL, uncertainty DOUBLE PRECISION, unit TEXT NOT NULL, "
        "PRIMARY KEY (record_id, position))",
        "CREATE INDEX figures_series ON figures (machine_name, name, measured_at)",
        "CREATE INDEX figures_fleet ON figures (name, machine_name, measured_at)",
        "CREATE TABLE events (id {T} PRIMARY KEY, machine {T} NOT NULL, date {T} NOT NULL, kind TEXT NOT NULL, "
        "note TEXT NOT NULL)",
        "CREATE INDEX events_machine_date ON events (machine, date)"}},
      // The fleet-wide "latest value per machine" query read 120,000 rows per parameter (about
      // 1 s): a table of each machine's latest value per parameter and figure, kept by every
      // write, makes it 1,000 rows. Filled from the stored values.
      {"latest_values: each machine's latest value of every parameter and figure",
       {"CREATE TABLE latest_values (kind {T} NOT NULL, name {T} NOT NULL, machine_name {T} NOT NULL, "
        "record_id {T} NOT NULL, measured_at {T} NOT NULL, recorded_at {T} NOT NULL, value DOUBLE PRECISION NOT NULL, "
        "uncertainty DOUBLE PRECISION, unit TEXT NOT NULL, PRIMARY KEY (kind, name, machine_name))",
        "CREATE INDEX latest_values_record ON latest_values (record_id)",
        "INSERT INTO latest_values (kind, name, machine_name, record_id, measured_at, recorded_at, value, uncertainty, "
        "unit) SELECT 'parameter', name, machine_name, record_id, measured_at, recorded_at, value, uncertainty, unit "
        "FROM (SELECT name, machine_name, record_id, measured_at, recorded_at, value, uncertainty, unit, ROW_NUMBER() "
        "OVER (PARTITION BY name, machine_name ORDER BY measured_at DESC, recorded_at DESC, record_id DESC) AS rn "
        "FROM parameters) AS t WHERE rn = 1",
        "INSERT INTO latest_values (kind, name, machine_name, record_id, measured_at, recorded_at, value, uncertainty, "
        "unit) SELECT 'figure', name, machine_name, record_id, measured_at, recorded_at, value, uncertainty, unit "
        "FROM (SELECT name, machine_name, record_id, measured_at, recorded_at, value, uncertainty, unit, ROW_NUMBER() "
        "OVER (PARTITION BY name, machine_name ORDER BY measured_at DESC, recorded_at DESC, record_id DESC) AS rn "
        "FROM figures) AS t WHERE rn = 1"}},
      // mtcal serve (docs/serve.md): its users, their sessions and who wrote which record or event.
      // New tables only: a store of version 2 reads as before.
      {"users, sessions, audit (the accounts of mtcal serve), latest_records, machine_intervals",
       {"CREATE TABLE users (name {T} PRIMARY KEY, role {T} NOT NULL, password_hash TEXT NOT NULL, "
        "created_at {T} NOT NULL)",
        "CREATE TABLE sessions (id_hash {T} PRIMARY KEY, user_name {T} NOT NULL REFERENCES users (name) ON DELETE "
        "CASCADE, csrf_token {T} NOT NULL, created_at {T} NOT NULL, expires_at {T} NOT NULL)",
        "CREATE INDEX sessions_expiry ON sessions (expires_at)",
        "CREATE TABLE audit (id {T} PRIMARY KEY, at {T} NOT NULL, user_name {T} NOT NULL, action {T} NOT NULL, "
        "object_id {T} NOT NULL, detail TEXT NOT NULL)",
        "CREATE INDEX audit_object ON audit (object_id)",
        // The fleet page's "latest calibration per machine and command" was a window query over
        // every record (3 s for 120,000 on a loaded 2-core machine): kept by every write instead.
        "CREATE TABLE latest_records (machine_name {T} NOT NULL, command {T} NOT NULL, record_id {T} NOT NULL, "
        "measured_at {T} NOT NULL, recorded_at {T} NOT NULL, n INTEGER NOT NULL, PRIMARY KEY (machine_name, command))",
        "INSERT INTO latest_records (machine_name, command, record_id, measured_at, recorded_at, n) SELECT "
        "machine_name, command, id, measured_at, recorded_at, n FROM (SELECT machine_name, command, id, measured_at, "
        "recorded_at, COUNT(*) OVER (PARTITION BY machine_name, command) AS n, ROW_NUMBER() OVER (PARTITION BY "
        "machine_name, command ORDER BY measured_at DESC, recorded_at DESC, id DESC) AS rn FROM records) AS t WHERE "
        "rn = 1",
        // A calibration interval per machine (the fleet's overdue column), set by an admin.
        "CREATE TABLE machine_intervals (machine_name {T} PRIMARY KEY, days INTEGER NOT NULL, set_by {T} NOT NULL, "
        "set_at {T} NOT NULL)"}},
      // mtcal serve's fleet ranking kept the fits of machines whose latest record and count per
      // command had not changed, which a removal and an older record between two pages leave
      // alike: a revision per machine, raised by every write of its records, is the key instead.
      // Filled with the count of each machine's records.
      {"machine_revisions: a revision per machine, raised by every write of its records",
       {"CREATE TABLE machine_revisions (machine_name {T} PRIMARY KEY, revision BIGINT NOT NULL)",
        "INSERT INTO machine_revisions (machine_name, revision) SELECT machine_name, COUNT(*) FROM records GROUP BY "
        "machine_name"}},
      // A record's compensation (mtcal serve) needs the machine file and parameter files it was
      // computed from, which the records' inputs name by SHA-256 only: their text, once per
      // content. Stores of version 4 hold none (their records say so when asked).
      {"model_files: the machine and parameter files of recorded results, by SHA-256",
       {"CREATE TABLE model_files (sha256 {T} PRIMARY KEY, kind {T} NOT NULL, content TEXT NOT NULL)"}},
      // A record's report (mtcal serve's record page) is drawn from its measurements and the
      // command's options: the measurement files go into model_files (kind "measurements"), the
      // options into the record. Records of version 5 have none ('' : the page says so).
      {"invocation: how the command of a record ran; model_files also hold measurement files",
       {"ALTER TABLE records ADD COLUMN invocation TEXT NOT NULL DEFAULT ''"}},
  };
  return kMigrations;
}

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (std::size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size()))
    s.replace(at, from.size(), to);
  return s;
}

const std::string& text_of(const std::optional<std::string>& cell) {
  static const std::string kEmpty;
  return cell ? *cell : kEmpty;
}

std::optional<double> optional_double(const std::optional<std::string>& cell) {
  if (!cell) return std::nullopt;
  return parse_double_text(*cell);
}

SqlParam optional_param(const std::optional<double>& v) {
  if (!v) return nullptr;
  return *v;
}

constexpr const char* kRecordColumns =
    "id, machine_name, machine_serial, command, recorded_at, measured_at, metadata, inputs, result_json, content_hash, "
    "invocation";
constexpr const char* kOrder = "measured_at, recorded_at, id";

}  // namespace

std::string double_text(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

double parse_double_text(const std::string& text) {
  double v = 0;
  const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
  if (r.ec != std::errc() || r.ptr != text.data() + text.size())
    throw StoreError("the history store holds '" + printable(text) + "' where a number was expected");
  return v;
}

std::string new_id() {
  // Per thread a generator seeded from the system's entropy, the clock and the address of a
  // local, seeded again in a forked child (it would repeat its parent's sequence): ids of
  // concurrent writers do not collide (64 random bits; the id is the primary key, so a collision
  // would fail the transaction, never overwrite).
  thread_local std::mt19937_64 gen;
  thread_local pid_t seeded_in = 0;
  if (seeded_in != ::getpid()) {
    seeded_in = ::getpid();
    std::random_device rd;
    int local = 0;
    std::seed_seq seq{rd(),
                      rd(),
                      rd(),
                      rd(),
                      static_cast<unsigned>(std::chrono::steady_clock::now().time_since_epoch().count()),
                      static_cast<unsigned>(reinterpret_cast<std::uintptr_t>(&local)),
                      static_cast<unsigned>(seeded_in)};
    gen.seed(seq);
  }
  return fmt::format("{:016x}", gen());
}

std::string now_utc() {
  const auto now = std::chrono::system_clock::now();
  const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() % 1000;
  const std::time_t t = std::chrono::system_clock::to_time_t(now);
  std::tm tm{};
  gmtime_r(&t, &tm);
  return fmt::format("{:04}-{:02}-{:02}T{:02}:{:02}:{:02}.{:03}Z", tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday,
                     tm.tm_hour, tm.tm_min, tm.tm_sec, ms);
}

std::string metadata_to_json(const std::map<std::string, std::string>& m) {
  ordered_json j = ordered_json::object();
  for (const auto& [k, v] : m) j[k] = v;
  return json_text(j);
}

std::map<std::string, std::string> metadata_from_json(const std::string& text) {
  std::map<std::string, std::string> m;
  const auto j = ordered_json::parse(text, nullptr, false);
  if (!j.is_object()) throw StoreError("the history store holds metadata that is not a JSON object");
  for (const auto& [k, v] : j.items()) {
    if (!v.is_string()) throw StoreError("the history store holds metadata '" + printable(k) + "' that is not text");
    m[k] = v.get<std::string>();
  }
  return m;
}

std::string inputs_to_json(const std::vector<InputHash>& in) {
  ordered_json j = ordered_json::array();
  for (const auto& i : in) j.push_back({{"path", i.path}, {"sha256", i.sha256}});
  return json_text(j);
}

std::vector<InputHash> inputs_from_json(const std::string& text) {
  std::vector<InputHash> out;
  const auto j = ordered_json::parse(text, nullptr, false);
  if (!j.is_array()) throw StoreError("the history store holds inputs that are not a JSON array");
  for (const auto& e : j) {
    if (!e.is_object() || !e.contains("path") || !e.contains("sha256") || !e["path"].is_string() ||
        !e["sha256"].is_string())
      throw StoreError("the history store holds an input without text 'path' and 'sha256'");
    out.push_back({e["path"].get<std::string>(), e["sha256"].get<std::string>()});
  }
  return out;
}

std::string content_hash(const CalibrationRecord& r) {
  ordered_json j = ordered_json::array();
  j.push_back(r.command);
  j.push_back(r.machine_name);
  j.push_back(r.machine_serial);
  j.push_back(r.measured_at);
  ordered_json meta = ordered_json::object();
  for (const auto& [k, v] : r.metadata) meta[k] = v;
  j.push_back(meta);
  ordered_json in = ordered_json::array();
  for (const auto& i : r.inputs) in.push_back(i.sha256);
  j.push_back(in);
  auto unc = [](const std::optional<double>& u) { return u ? ordered_json(*u) : ordered_json(nullptr); };
  ordered_json ps = ordered_json::array();
  for (const auto& p : r.parameters) ps.push_back({p.name, p.value, unc(p.uncertainty), p.unit});
  j.push_back(ps);
  ordered_json fs = ordered_json::array();
  for (const auto& f : r.figures) fs.push_back({f.name, f.value, unc(f.uncertainty), f.unit});
  j.push_back(fs);
  j.push_back(r.result_json);
  return sha256_hex(json_text(j));
}

void check_record(const CalibrationRecord& r) {
  const std::string where = r.id.empty() ? std::string("record") : "record " + r.id;
  auto bad = [&](const std::string& field, const std::string& what) { throw InputError({where, 0, field}, what); };
  if (r.machine_name.empty()) bad("machine_name", "expected the machine's name, found none");
  if (r.command.empty()) bad("command", "expected the command that produced the result, found none");
  if (!r.measured_at.empty() && !is_iso8601(r.measured_at))
    bad("measured_at",
        "expected an ISO 8601 date (2026-11-25 or 2026-11-25T10:30:00Z), found '" + printable(r.measured_at) + "'");
  if (!r.recorded_at.empty() && !is_iso8601(r.recorded_at))
    bad("recorded_at", "expected an ISO 8601 date-time, found '" + printable(r.recorded_at) + "'");
  for (const auto& p : r.parameters) {
    if (p.name.empty()) bad("parameters", "expected a parameter name, found an empty one");
    if (!std::isfinite(p.value) || (p.uncertainty && !std::isfinite(*p.uncertainty)))
      bad("parameters", "parameter " + p.name + ": expected finite numbers");
  }
  for (const auto& f : r.figures) {
    if (f.name.empty()) bad("figures", "expected a figure name, found an empty one");
    if (!std::isfinite(f.value) || (f.uncertainty && !std::isfinite(*f.uncertainty)))
      bad("figures", "figure " + f.name + ": expected finite numbers");
  }
  // The store's text is UTF-8 (PostgreSQL's text columns refuse anything else; the JSON lines
  // export is JSON): record_from_result makes a command's text so (json_text's U+FFFD).
  auto utf8 = [&](const std::string& field, const std::string& text) {
    if (!is_utf8(text))
      bad(field, "expected UTF-8 text, found '" + printable(text) + "'");
  };
  for (const auto& [field, text] : {std::pair<const char*, const std::string&>{"machine_name", r.machine_name},
                                    {"machine_serial", r.machine_serial},
                                    {"command", r.command},
                                    {"result_json", r.result_json},
                                    {"invocation", r.invocation}})
    utf8(field, text);
  for (const auto& [k, v] : r.metadata) {
    utf8("metadata", k);
    utf8("metadata " + k, v);
  }
  for (const auto& i : r.inputs) utf8("inputs", i.path);
  for (const auto& p : r.parameters) {
    utf8("parameters", p.name);
    utf8("parameters", p.unit);
  }
  for (const auto& f : r.figures) {
    utf8("figures", f.name);
    utf8("figures", f.unit);
  }
  for (const auto& i : r.inputs)
    if (i.sha256.size() != 64 || i.sha256.find_first_not_of("0123456789abcdef") != std::string::npos)
      bad("inputs", "input " + printable(i.path) + ": expected 64 lowercase hex digits of SHA-256, found '" +
                        printable(i.sha256) + "'");
}

void check_model_file(const ModelFile& f, const std::string& where) {
  const std::string what = "model file " + printable(f.sha256.substr(0, 64));
  if (f.kind != "machine" && f.kind != "parameters" && f.kind != "measurements")
    throw InputError({where, 0, "kind"},
                     what + ": expected the kind machine, parameters or measurements, found '" + printable(f.kind) + "'");
  if (!is_utf8(f.content)) throw InputError({where, 0, "content"}, what + ": expected UTF-8 text");
  const std::string h = sha256_hex(f.content);
  if (f.sha256 != h)
    throw InputError({where, 0, "sha256"}, what + ": expected the SHA-256 of its content, " + h +
                                               " (the content was changed, or the hash is not its own)");
}

void check_event(const Event& e) {
  const std::string where = e.id.empty() ? std::string("event") : "event " + e.id;
  if (e.machine.empty()) throw InputError({where, 0, "machine"}, "expected the machine's name, found none");
  for (const auto& [field, text] : {std::pair<const char*, const std::string&>{"machine", e.machine}, {"note", e.note}})
    if (!is_utf8(text))
      throw InputError({where, 0, field}, "expected UTF-8 text, found '" + printable(text) + "'");
  if (!is_iso8601(e.date))
    throw InputError({where, 0, "date"}, "expected an ISO 8601 date (2026-11-25 or 2026-11-25T10:30:00Z), found '" +
                                             printable(e.date) + "'");
}

// ---- SqlHistoryStore ------------------------------------------------------------------------

void SqlHistoryStore::migrate() {
  auto current = [&] {
    if (!table_exists("schema_version")) return 0;
    const auto rows = query("SELECT MAX(version) FROM schema_version");
    return rows.empty() || !rows[0][0] ? 0 : std::stoi(*rows[0][0]);
  };
  const int target = static_cast<int>(migrations().size());
  if (target != kHistorySchemaVersion) throw StoreError("mtcal's schema migrations and its schema version disagree");
  int v = current();
  if (v == target) return;
  begin_write();
  try {
    lock_for_migration();
    v = current();  // another process may have migrated meanwhile
    if (v > target)
      throw StoreError(fmt::format("{}: the store has schema version {}, newer than this program's {} (upgrade mtcal)",
                                   describe(), v, target));
    if (v == 0)
      exec("CREATE TABLE IF NOT EXISTS schema_version (version INTEGER NOT NULL PRIMARY KEY, applied_at " +
           text_type() + " NOT NULL, description TEXT NOT NULL)");
    for (int i = v; i < target; ++i) {
      for (const char* s : migrations()[static_cast<std::size_t>(i)].statements)
        exec(replace_all(s, "{T}", text_type()));
      exec("INSERT INTO schema_version (version, applied_at, description) VALUES ($1, $2, $3)",
           {static_cast<long long>(i + 1), now_utc(),
            std::string(migrations()[static_cast<std::size_t>(i)].description)});
    }
    commit();
  } catch (...) {
    rollback();
    throw;
  }
}

int SqlHistoryStore::schema_version() {
  const auto rows = query("SELECT MAX(version) FROM schema_version");
  return rows.empty() || !rows[0][0] ? 0 : std::stoi(*rows[0][0]);
}

void SqlHistoryStore::insert_rows(const std::string& head, std::size_t columns, const std::vector<SqlParam>& values,
                                  const std::string& tail) {
  // Multi-row INSERTs of at most 500 rows: a bulk import costs statements by the hundred rows,
  // within SQLite's 32766 and PostgreSQL's 65535 parameters per statement.
  const std::size_t rows = values.size() / columns;
  constexpr std::size_t kChunk = 500;
  for (std::size_t first = 0; first < rows; first += kChunk) {
    const std::size_t n = std::min(kChunk, rows - first);
    std::string sql = head + " VALUES ";
    std::size_t k = 1;
    for (std::size_t r = 0; r < n; ++r) {
      sql += r ? ",(" : "(";
      for (std::size_t c = 0; c < columns; ++c) sql += fmt::format("{}${}", c ? "," : "", k++);
      sql += ")";
    }
    sql += tail;
    const auto begin = values.begin() + static_cast<std::ptrdiff_t>(first * columns);
    exec(sql, std::vector<SqlParam>(begin, begin + static_cast<std::ptrdiff_t>(n * columns)));
  }
}

std::vector<std::string> SqlHistoryStore::record_all(std::vector<CalibrationRecord> records, std::vector<Event> evs,
                                                     std::vector<std::size_t>* skipped, std::vector<ModelFile> files) {
  return write_all(std::move(records), std::move(evs), skipped, nullptr, files);
}

std::optional<ModelFile> SqlHistoryStore::model_file(const std::string& sha256) {
  const auto rows = query("SELECT sha256, kind, content FROM model_files WHERE sha256 = $1", {sha256});
  if (rows.empty()) return std::nullopt;
  return ModelFile{text_of(rows[0][0]), text_of(rows[0][1]), text_of(rows[0][2])};
}

std::vector<ModelFile> SqlHistoryStore::model_files() {
  std::vector<ModelFile> out;
  for (const auto& row : query("SELECT sha256, kind, content FROM model_files ORDER BY sha256"))
    out.push_back({text_of(row[0]), text_of(row[1]), text_of(row[2])});
  return out;
}

std::vector<std::string> SqlHistoryStore::write_all(std::vector<CalibrationRecord> records, std::vector<Event> evs,
                                                    std::vector<std::size_t>* skipped, const std::string* author,
                                                    const std::vector<ModelFile>& model_files) {
  const std::string now = now_utc();
  for (const auto& f : model_files) check_model_file(f, "model file");
  for (auto& r : records) {
    check_record(r);
    if (r.recorded_at.empty()) r.recorded_at = now;
    if (r.measured_at.empty()) r.measured_at = r.recorded_at;
    if (r.id.empty()) r.id = new_id();
    const std::string h = content_hash(r);
    if (!r.content_hash.empty() && r.content_hash != h)
      throw InputError({"record " + r.id, 0, "content_hash"},
                       "expected the content hash " + h + " of the record's content, found " +
                           printable(r.content_hash) + " (the record was changed after it was stored)");
    r.content_hash = h;
  }
  for (auto& e : evs) {
    check_event(e);
    if (e.id.empty()) e.id = new_id();
  }
  std::vector<std::string> ids(records.size());
  if (skipped) skipped->clear();
  begin_write();
  try {
    // Records: those whose content hash (or id) is stored already are skipped by ON CONFLICT;
    // RETURNING names the ones inserted, whose parameters and figures then follow.
    std::unordered_set<std::string> inserted;
    {
      std::unordered_set<std::string> seen;
      std::vector<SqlParam> values;
      for (const auto& r : records) {
        if (!seen.insert(r.content_hash).second) continue;
        for (SqlParam v : {SqlParam(r.id), SqlParam(r.machine_name), SqlParam(r.machine_serial), SqlParam(r.command),
                           SqlParam(r.recorded_at), SqlParam(r.measured_at), SqlParam(metadata_to_json(r.metadata)),
                           SqlParam(inputs_to_json(r.inputs)), SqlParam(r.result_json), SqlParam(r.content_hash),
                           SqlParam(r.invocation)})
          values.push_back(std::move(v));
      }
      constexpr std::size_t kCols = 11, kChunk = 200;
      const std::size_t rows = values.size() / kCols;
      for (std::size_t first = 0; first < rows; first += kChunk) {
        const std::size_t n = std::min(kChunk, rows - first);
        std::string sql = std::string("INSERT INTO records (") + kRecordColumns + ") VALUES ";
        std::size_t k = 1;
        for (std::size_t r = 0; r < n; ++r) {
          sql += r ? ",(" : "(";
          for (std::size_t c = 0; c < kCols; ++c) sql += fmt::format("{}${}", c ? "," : "", k++);
          sql += ")";
        }
        sql += " ON CONFLICT DO NOTHING RETURNING id";
        const auto begin = values.begin() + static_cast<std::ptrdiff_t>(first * kCols);
        for (const auto& row : query(sql, std::vector<SqlParam>(begin, begin + static_cast<std::ptrdiff_t>(n * kCols))))
          inserted.insert(text_of(row[0]));
      }
    }
    std::vector<SqlParam> params, figs;
    std::vector<bool> fresh(records.size(), false);  // inserted now (an import may repeat a stored id)
    for (std::size_t i = 0; i < records.size(); ++i) {
      const auto& r = records[i];
      if (!inserted.erase(r.id)) {  // skipped: a duplicate (or the second of two equal ones here)
        const auto existing = find_by_content_hash(r.content_hash);
        if (!existing)
          throw StoreError("record " + r.id + " cannot be stored: the id is taken by a record of other content");
        ids[i] = *existing;
        if (skipped) skipped->push_back(i);
        continue;
      }
      ids[i] = r.id;
      fresh[i] = true;
      long long pos = 0;
      for (const auto& p : r.parameters)
        for (SqlParam v : {SqlParam(r.id), SqlParam(pos++), SqlParam(r.machine_name), SqlParam(r.measured_at),
                           SqlParam(r.recorded_at), SqlParam(p.name), SqlParam(p.value), optional_param(p.uncertainty),
                           SqlParam(p.unit)})
          params.push_back(std::move(v));
      pos = 0;
      for (const auto& f : r.figures)
        for (SqlParam v : {SqlParam(r.id), SqlParam(pos++), SqlParam(r.machine_name), SqlParam(r.measured_at),
                           SqlParam(r.recorded_at), SqlParam(f.name), SqlParam(f.value), optional_param(f.uncertainty),
                           SqlParam(f.unit)})
          figs.push_back(std::move(v));
    }
    constexpr const char* kValueColumns =
        " (record_id, position, machine_name, measured_at, recorded_at, name, value, uncertainty, unit)";
    insert_rows(std::string("INSERT INTO parameters") + kValueColumns, 9, params);
    insert_rows(std::string("INSERT INTO figures") + kValueColumns, 9, figs);
    // Each machine's latest value per name: the newest of this batch per key (one row per key and
    // statement, as PostgreSQL's ON CONFLICT DO UPDATE requires; keys in order, so that
    // concurrent writers lock them in the same order), replacing the stored one only if newer.
    std::map<std::tuple<std::string, std::string, std::string>, std::vector<SqlParam>> newest;
    auto offer = [&](const char* kind, const CalibrationRecord& r, const std::string& name, double value,
                     const std::optional<double>& u, const std::string& unit) {
      auto& slot = newest[{kind, name, r.machine_name}];
      if (!slot.empty()) {
        const auto& m = std::get<std::string>(slot[4]);
        const auto& rec = std::get<std::string>(slot[5]);
        const auto& id = std::get<std::string>(slot[3]);
        if (std::tie(r.measured_at, r.recorded_at, r.id) <= std::tie(m, rec, id)) return;
      }
      slot = {std::string(kind), name,  r.machine_name,    r.id, r.measured_at,
              r.recorded_at,     value, optional_param(u), unit};
    };
    for (std::size_t i = 0; i < records.size(); ++i) {
      if (ids[i] != records[i].id) continue;  // skipped
      for (const auto& p : records[i].parameters)
        offer("parameter", records[i], p.name, p.value, p.uncertainty, p.unit);
      for (const auto& f : records[i].figures) offer("figure", records[i], f.name, f.value, f.uncertainty, f.unit);
    }
    std::vector<SqlParam> latest_rows;
    for (auto& [key, row] : newest)
      for (auto& v : row) latest_rows.push_back(std::move(v));
    insert_rows(
        "INSERT INTO latest_values (kind, name, machine_name, record_id, measured_at, recorded_at, value, "
        "uncertainty, unit)",
        9, latest_rows,
        " ON CONFLICT (kind, name, machine_name) DO UPDATE SET record_id = excluded.record_id, measured_at = "
        "excluded.measured_at, recorded_at = excluded.recorded_at, value = excluded.value, uncertainty = "
        "excluded.uncertainty, unit = excluded.unit WHERE excluded.measured_at > latest_values.measured_at OR "
        "(excluded.measured_at = latest_values.measured_at AND (excluded.recorded_at > "
        "latest_values.recorded_at OR (excluded.recorded_at = latest_values.recorded_at AND excluded.record_id "
        "> latest_values.record_id)))");
    // Each machine's latest record per command and the count: one row per key of this batch.
    std::map<std::pair<std::string, std::string>, std::pair<const CalibrationRecord*, long long>> per_kind;
    for (std::size_t i = 0; i < records.size(); ++i) {
      if (!fresh[i]) continue;  // skipped
      const auto& r = records[i];
      auto& slot = per_kind[{r.machine_name, r.command}];
      if (!slot.first || std::tie(r.measured_at, r.recorded_at, r.id) >
                             std::tie(slot.first->measured_at, slot.first->recorded_at, slot.first->id))
        slot.first = &r;
      ++slot.second;
    }
    // Each machine's revision, raised by the number of its records written now (machines in
    // order, as above, so that concurrent writers lock their rows in the same order).
    std::map<std::string, long long> written;
    for (const auto& [key, v] : per_kind) written[key.first] += v.second;
    std::vector<SqlParam> revision_rows;
    for (const auto& [machine, n] : written)
      for (SqlParam x : {SqlParam(machine), SqlParam(n)}) revision_rows.push_back(std::move(x));
    insert_rows("INSERT INTO machine_revisions (machine_name, revision)", 2, revision_rows,
                " ON CONFLICT (machine_name) DO UPDATE SET revision = machine_revisions.revision + excluded.revision");
    std::vector<SqlParam> kind_rows;
    for (const auto& [key, v] : per_kind)
      for (SqlParam x : {SqlParam(key.first), SqlParam(key.second), SqlParam(v.first->id),
                         SqlParam(v.first->measured_at), SqlParam(v.first->recorded_at), SqlParam(v.second)})
        kind_rows.push_back(std::move(x));
    constexpr const char* kNewer =
        "(excluded.measured_at > latest_records.measured_at OR (excluded.measured_at = latest_records.measured_at AND "
        "(excluded.recorded_at > latest_records.recorded_at OR (excluded.recorded_at = latest_records.recorded_at AND "
        "excluded.record_id > latest_records.record_id))))";
    insert_rows("INSERT INTO latest_records (machine_name, command, record_id, measured_at, recorded_at, n)", 6,
                kind_rows,
                fmt::format(" ON CONFLICT (machine_name, command) DO UPDATE SET n = latest_records.n + excluded.n, "
                            "record_id = CASE WHEN {0} THEN excluded.record_id ELSE latest_records.record_id END, "
                            "measured_at = CASE WHEN {0} THEN excluded.measured_at ELSE latest_records.measured_at END, "
                            "recorded_at = CASE WHEN {0} THEN excluded.recorded_at ELSE latest_records.recorded_at END",
                            kNewer));
    std::vector<SqlParam> ev;
    for (const auto& e : evs)
      for (SqlParam v : {SqlParam(e.id), SqlParam(e.machine), SqlParam(e.date),
                         SqlParam(std::string(to_string(e.kind))), SqlParam(e.note)})
        ev.push_back(std::move(v));
    insert_rows("INSERT INTO events (id, machine, date, kind, note)", 5, ev, " ON CONFLICT DO NOTHING");
    // Model files once per content (sorted and unique: one row per key and statement, keys in
    // order as above); a stored one is kept.
    std::map<std::string, const ModelFile*> files;
    for (const auto& f : model_files) files.emplace(f.sha256, &f);
    std::vector<SqlParam> file_rows;
    for (const auto& [sha, f] : files)
      for (SqlParam v : {SqlParam(f->sha256), SqlParam(f->kind), SqlParam(f->content)}) file_rows.push_back(std::move(v));
    insert_rows("INSERT INTO model_files (sha256, kind, content)", 3, file_rows, " ON CONFLICT DO NOTHING");
    if (author) {
      std::vector<SqlParam> rows;
      auto audit_row = [&](const char* action, const std::string& id, std::string detail) {
        for (SqlParam v : {SqlParam(new_id()), SqlParam(now), SqlParam(*author), SqlParam(std::string(action)),
                           SqlParam(id), SqlParam(std::move(detail))})
          rows.push_back(std::move(v));
      };
      for (std::size_t i = 0; i < records.size(); ++i)
        if (fresh[i]) audit_row("record", ids[i], records[i].command + " " + records[i].machine_name);
      for (const auto& e : evs) audit_row("event", e.id, std::string(to_string(e.kind)) + " " + e.machine);
      insert_rows("INSERT INTO audit (id, at, user_name, action, object_id, detail)", 6, rows);
    }
    commit();
  } catch (...) {
    rollback();
    throw;
  }
  return ids;
}

std::string SqlHistoryStore::record_by(CalibrationRecord r, const std::string& user, std::vector<ModelFile> model_files) {
  std::vector<CalibrationRecord> one;
  one.push_back(std::move(r));
  return write_all(std::move(one), {}, nullptr, &user, model_files).front();
}

std::string SqlHistoryStore::add_event_by(Event e, const std::string& user) {
  check_event(e);
  if (e.id.empty()) e.id = new_id();
  const std::string id = e.id;
  write_all({}, {std::move(e)}, nullptr, &user);
  return id;
}

std::vector<AuditEntry> SqlHistoryStore::audit(const std::string& object_id) {
  std::vector<AuditEntry> out;
  const auto rows = object_id.empty()
                        ? query("SELECT id, at, user_name, action, object_id, detail FROM audit ORDER BY at, id")
                        : query("SELECT id, at, user_name, action, object_id, detail FROM audit WHERE object_id = $1 "
                                "ORDER BY at, id",
                                {object_id});
  for (const auto& row : rows)
    out.push_back({text_of(row[0]), text_of(row[1]), text_of(row[2]), text_of(row[3]), text_of(row[4]),
                   text_of(row[5])});
  return out;
}

std::vector<LatestCalibration> SqlHistoryStore::latest_calibrations() {
  std::vector<LatestCalibration> out;
  const auto rows = query(
      "SELECT machine_name, command, record_id, measured_at, n FROM latest_records ORDER BY machine_name, command");
  for (const auto& row : rows)
    out.push_back({text_of(row[0]), text_of(row[1]), text_of(row[2]), text_of(row[3]), std::stoll(text_of(row[4]))});
  return out;
}

void SqlHistoryStore::set_machine_interval(const std::string& machine, int days, const std::string& user) {
  if (machine.empty()) throw InputError({"interval", 0, "machine"}, "expected a machine name, found none");
  if (days < 0)
    throw InputError({"interval", 0, "days"}, "expected a number of days >= 0 (0: the default), found " +
                                                  std::to_string(days));
  const std::string now = now_utc();
  begin_write();
  try {
    if (days == 0)
      exec("DELETE FROM machine_intervals WHERE machine_name = $1", {machine});
    else
      exec("INSERT INTO machine_intervals (machine_name, days, set_by, set_at) VALUES ($1, $2, $3, $4) ON CONFLICT "
           "(machine_name) DO UPDATE SET days = excluded.days, set_by = excluded.set_by, set_at = excluded.set_at",
           {machine, static_cast<long long>(days), user, now});
    exec("INSERT INTO audit (id, at, user_name, action, object_id, detail) VALUES ($1, $2, $3, $4, $5, $6)",
         {new_id(), now, user, std::string("interval"), machine,
          days == 0 ? std::string("default interval") : std::to_string(days) + " days"});
    commit();
  } catch (...) {
    rollback();
    throw;
  }
}

std::vector<MachineInterval> SqlHistoryStore::machine_intervals() {
  std::vector<MachineInterval> out;
  for (const auto& row : query("SELECT machine_name, days, set_by, set_at FROM machine_intervals ORDER BY machine_name"))
    out.push_back({text_of(row[0]), static_cast<int>(std::stoll(text_of(row[1]))), text_of(row[2]), text_of(row[3])});
  return out;
}

std::vector<MachineRevision> SqlHistoryStore::machine_revisions() {
  std::vector<MachineRevision> out;
  for (const auto& row : query("SELECT machine_name, revision FROM machine_revisions ORDER BY machine_name"))
    out.push_back({text_of(row[0]), std::stoll(text_of(row[1]))});
  return out;
}

void SqlHistoryStore::put_user(const UserAccount& u) {
  if (u.name.empty()) throw InputError({"user", 0, "name"}, "expected a user name, found none");
  begin_write();
  try {
    exec("INSERT INTO users (name, role, password_hash, created_at) VALUES ($1, $2, $3, $4) ON CONFLICT (name) DO "
         "UPDATE SET role = excluded.role, password_hash = excluded.password_hash",
         {u.name, u.role, u.password_hash, u.created_at.empty() ? now_utc() : u.created_at});
    commit();
  } catch (...) {
    rollback();
    throw;
  }
}

std::optional<UserAccount> SqlHistoryStore::find_user(const std::string& name) {
  const auto rows = query("SELECT name, role, password_hash, created_at FROM users WHERE name = $1", {name});
  if (rows.empty()) return std::nullopt;
  return UserAccount{text_of(rows[0][0]), text_of(rows[0][1]), text_of(rows[0][2]), text_of(rows[0][3])};
}

std::vector<UserAccount> SqlHistoryStore::users() {
  std::vector<UserAccount> out;
  for (const auto& row : query("SELECT name, role, password_hash, created_at FROM users ORDER BY name"))
    out.push_back({text_of(row[0]), text_of(row[1]), text_of(row[2]), text_of(row[3])});
  return out;
}

void SqlHistoryStore::put_session(const SessionEntry& s) {
  begin_write();
  try {
    exec("INSERT INTO sessions (id_hash, user_name, csrf_token, created_at, expires_at) VALUES ($1, $2, $3, $4, $5)",
         {s.id_hash, s.user, s.csrf_token, s.created_at.empty() ? now_utc() : s.created_at, s.expires_at});
    commit();
  } catch (...) {
    rollback();
    throw;
  }
}

std::optional<SessionEntry> SqlHistoryStore::find_session(const std::string& id_hash, const std::string& now) {
  const auto rows = query(
      "SELECT id_hash, user_name, csrf_token, created_at, expires_at FROM sessions WHERE id_hash = $1 AND expires_at > "
      "$2",
      {id_hash, now});
  if (rows.empty()) return std::nullopt;
  return SessionEntry{text_of(rows[0][0]), text_of(rows[0][1]), text_of(rows[0][2]), text_of(rows[0][3]),
                      text_of(rows[0][4])};
}

bool SqlHistoryStore::remove_session(const std::string& id_hash) {
  begin_write();
  try {
    const long long n = exec("DELETE FROM sessions WHERE id_hash = $1", {id_hash});
    commit();
    return n > 0;
  } catch (...) {
    rollback();
    throw;
  }
}

long long SqlHistoryStore::remove_expired_sessions(const std::string& now) {
  begin_write();
  try {
    const long long n = exec("DELETE FROM sessions WHERE expires_at <= $1", {now});
    commit();
    return n;
  } catch (...) {
    rollback();
    throw;
  }
}

std::string SqlHistoryStore::record(CalibrationRecord r) {
  std::vector<CalibrationRecord> one;
  one.push_back(std::move(r));
  return record_all(std::move(one), {}, nullptr).front();
}

bool SqlHistoryStore::remove(const std::string& id) {
  begin_write();
  try {
    const auto machine = query("SELECT machine_name, command FROM records WHERE id = $1", {id});
    exec("DELETE FROM parameters WHERE record_id = $1", {id});
    exec("DELETE FROM figures WHERE record_id = $1", {id});
    const long long n = exec("DELETE FROM records WHERE id = $1", {id});
    // The latest values this record was: taken from the machine's other records.
    if (n > 0 && exec("DELETE FROM latest_values WHERE record_id = $1", {id}) > 0)
      for (const std::string kind : {"parameter", "figure"})
        exec(fmt::format(
                 "INSERT INTO latest_values (kind, name, machine_name, record_id, measured_at, recorded_at, value, "
                 "uncertainty, unit) SELECT $1, name, machine_name, record_id, measured_at, recorded_at, value, "
                 "uncertainty, unit FROM (SELECT name, machine_name, record_id, measured_at, recorded_at, value, "
                 "uncertainty, unit, ROW_NUMBER() OVER (PARTITION BY name ORDER BY measured_at DESC, recorded_at DESC, "
                 "record_id DESC) AS rn FROM {} WHERE machine_name = $2 AND name NOT IN (SELECT name FROM "
                 "latest_values WHERE kind = $3 AND machine_name = $4)) AS t WHERE rn = 1",
                 kind == "parameter" ? "parameters" : "figures"),
             {kind, text_of(machine.at(0)[0]), kind, text_of(machine.at(0)[0])});
    if (n > 0) {
      // The machine's latest record of this command and the count, from the records left.
      const std::string m = text_of(machine.at(0)[0]), c = text_of(machine.at(0)[1]);
      exec("DELETE FROM latest_records WHERE machine_name = $1 AND command = $2", {m, c});
      exec("INSERT INTO latest_records (machine_name, command, record_id, measured_at, recorded_at, n) SELECT "
           "machine_name, command, id, measured_at, recorded_at, (SELECT COUNT(*) FROM records WHERE machine_name = $1 "
           "AND command = $2) FROM records WHERE machine_name = $3 AND command = $4 ORDER BY measured_at DESC, "
           "recorded_at DESC, id DESC LIMIT 1",
           {m, c, m, c});
      exec("INSERT INTO machine_revisions (machine_name, revision) VALUES ($1, 1) ON CONFLICT (machine_name) DO UPDATE "
           "SET revision = machine_revisions.revision + 1",
           {m});
    }
    commit();
    return n > 0;
  } catch (...) {
    rollback();
    throw;
  }
}

std::vector<CalibrationRecord> SqlHistoryStore::load_records(const std::string& where,
                                                             const std::vector<SqlParam>& params) {
  const std::string cond = where.empty() ? "" : " WHERE " + where;
  std::vector<CalibrationRecord> out;
  std::unordered_map<std::string, std::size_t> index;
  for (const auto& row :
       query(std::string("SELECT ") + kRecordColumns + " FROM records" + cond + " ORDER BY " + kOrder, params)) {
    CalibrationRecord r;
    r.id = text_of(row[0]);
    r.machine_name = text_of(row[1]);
    r.machine_serial = text_of(row[2]);
    r.command = text_of(row[3]);
    r.recorded_at = text_of(row[4]);
    r.measured_at = text_of(row[5]);
    r.metadata = metadata_from_json(text_of(row[6]));
    r.inputs = inputs_from_json(text_of(row[7]));
    r.result_json = text_of(row[8]);
    r.content_hash = text_of(row[9]);
    r.invocation = text_of(row[10]);
    index[r.id] = out.size();
    out.push_back(std::move(r));
  }
  if (out.empty()) return out;
  for (const char* table : {"parameters", "figures"}) {
    const std::string sql = fmt::format(
        "SELECT v.record_id, v.name, v.value, v.uncertainty, v.unit FROM {} v WHERE v.record_id IN "
        "(SELECT id FROM records{}) ORDER BY v.record_id, v.position",
        table, cond);
    for (const auto& row : query(sql, params)) {
      const auto it = index.find(text_of(row[0]));
      if (it == index.end()) continue;
      auto& r = out[it->second];
      if (table[0] == 'p')
        r.parameters.push_back(
            {text_of(row[1]), parse_double_text(text_of(row[2])), optional_double(row[3]), text_of(row[4])});
      else
        r.figures.push_back(
            {text_of(row[1]), parse_double_text(text_of(row[2])), text_of(row[4]), optional_double(row[3])});
    }
  }
  return out;
}

std::vector<CalibrationRecord> SqlHistoryStore::list(const RecordFilter& f) {
  std::string where;
  std::vector<SqlParam> params;
  auto add = [&](const std::string& cond, std::string value) {
    params.emplace_back(std::move(value));
    where += (where.empty() ? "" : " AND ") + fmt::format(fmt::runtime(cond), params.size());
  };
  if (!f.machine.empty()) add("machine_name = ${}", f.machine);
  if (!f.command.empty()) add("command = ${}", f.command);
  if (!f.from.empty()) add("measured_at >= ${}", f.from);
  // A date as the end includes that day's date-times ('~' sorts after 'T' and the digits).
  if (!f.to.empty()) add("measured_at <= ${}", f.to.size() == 10 ? f.to + "~" : f.to);
  return load_records(where, params);
}

std::optional<CalibrationRecord> SqlHistoryStore::get(const std::string& id) {
  auto r = load_records("id = $1", {id});
  if (r.empty()) return std::nullopt;
  return std::move(r.front());
}

std::optional<std::string> SqlHistoryStore::find_by_content_hash(const std::string& h) {
  const auto rows = query("SELECT id FROM records WHERE content_hash = $1", {h});
  if (rows.empty()) return std::nullopt;
  return text_of(rows[0][0]);
}

std::vector<std::string> SqlHistoryStore::machines() {
  std::vector<std::string> out;
  for (const auto& row : query("SELECT DISTINCT machine_name FROM records ORDER BY machine_name"))
    out.push_back(text_of(row[0]));
  return out;
}

std::vector<SeriesSample> SqlHistoryStore::series(const char* table, const std::string& machine,
                                                  const std::string& name) {
  std::vector<SeriesSample> out;
  const std::string sql = fmt::format(
      "SELECT measured_at, value, uncertainty, record_id, unit FROM {} WHERE machine_name = $1 AND name = $2 "
      "ORDER BY measured_at, recorded_at, record_id",
      table);
  for (const auto& row : query(sql, {machine, name}))
    out.push_back({text_of(row[0]), parse_double_text(text_of(row[1])), optional_double(row[2]), text_of(row[3]),
                   text_of(row[4])});
  return out;
}

std::vector<SeriesSample> SqlHistoryStore::parameter_series(const std::string& machine, const std::string& parameter) {
  return series("parameters", machine, parameter);
}
std::vector<SeriesSample> SqlHistoryStore::figure_series(const std::string& machine, const std::string& figure) {
  return series("figures", machine, figure);
}

std::vector<LatestValue> SqlHistoryStore::latest(const char* kind, const std::string& name) {
  std::vector<LatestValue> out;
  const std::string sql =
      "SELECT machine_name, measured_at, value, uncertainty, record_id, unit FROM latest_values WHERE kind = $1 AND "
      "name = $2 ORDER BY machine_name";
  for (const auto& row : query(sql, {std::string(kind), name}))
    out.push_back({text_of(row[0]),
                   {text_of(row[1]), parse_double_text(text_of(row[2])), optional_double(row[3]), text_of(row[4]),
                    text_of(row[5])}});
  return out;
}

std::vector<LatestValue> SqlHistoryStore::latest_parameter(const std::string& parameter) {
  return latest("parameter", parameter);
}
std::vector<LatestValue> SqlHistoryStore::latest_figure(const std::string& figure) { return latest("figure", figure); }

std::string SqlHistoryStore::add_event(Event e) {
  check_event(e);
  if (e.id.empty()) e.id = new_id();
  begin_write();
  try {
    exec("INSERT INTO events (id, machine, date, kind, note) VALUES ($1, $2, $3, $4, $5)",
         {e.id, e.machine, e.date, std::string(to_string(e.kind)), e.note});
    commit();
  } catch (...) {
    rollback();
    throw;
  }
  return e.id;
}

std::vector<Event> SqlHistoryStore::events(const std::string& machine) {
  std::vector<Event> out;
  const auto rows =
      machine.empty()
          ? query("SELECT id, machine, date, kind, note FROM events ORDER BY date, id")
          : query("SELECT id, machine, date, kind, note FROM events WHERE machine = $1 ORDER BY date, id", {machine});
  for (const auto& row : rows) {
    const auto kind = parse_event_kind(text_of(row[3]));
    if (!kind)
      throw StoreError("the history store holds an event of unknown kind '" + printable(text_of(row[3])) + "'");
    out.push_back({text_of(row[0]), text_of(row[1]), text_of(row[2]), *kind, text_of(row[4])});
  }
  return out;
}

}  // namespace mtcal::history_detail

namespace mtcal {

std::unique_ptr<HistoryStore> open_history_store(const std::string& connection) {
  if (connection.empty())
    throw InputError({"history store", 0, ""}, "expected a store (a file or a connection string), found none");
  if (connection.rfind("postgresql://", 0) == 0 || connection.rfind("postgres://", 0) == 0)
    return history_detail::open_postgres_store(connection);
  if (connection.rfind("postgresql:", 0) == 0) return history_detail::open_postgres_store(connection.substr(11));
  if (connection.rfind("sqlite:", 0) == 0) return history_detail::open_sqlite_store(connection.substr(7));
  return history_detail::open_sqlite_store(connection);
}

}  // namespace mtcal
