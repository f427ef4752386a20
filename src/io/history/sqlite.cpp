// The history store in one SQLite file: WAL journal, busy timeout, write transactions that take
// the write lock at their start.
#include <sqlite3.h>

#include <chrono>
#include <thread>
#include <unordered_map>

#include <fmt/format.h>

#include "internal.hpp"

namespace mtcal::history_detail {

namespace {

class SqliteStore final : public SqlHistoryStore {
 public:
  explicit SqliteStore(std::string path) : path_(std::move(path)) {
    const int rc =
        sqlite3_open_v2(path_.c_str(), &db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_NOMUTEX, nullptr);
    if (rc != SQLITE_OK) {
      const std::string msg = db_ ? sqlite3_errmsg(db_) : sqlite3_errstr(rc);
      sqlite3_close(db_);
      throw StoreError(describe() + ": cannot open the history store: " + msg);
    }
    try {
      // A writer waits up to 60 s for another's transaction (a bulk import of 100,000 records
      // takes seconds) before it reports the store busy.
      sqlite3_busy_timeout(db_, 60'000);
      // WAL: readers do not block the writer nor it them; synchronous=FULL: a committed record
      // survives a power cut (one fsync of the log per transaction).
      set_wal_journal();
      exec_plain("PRAGMA synchronous=FULL");
      exec_plain("PRAGMA foreign_keys=ON");
      migrate();
    } catch (...) {
      close();
      throw;
    }
  }
  ~SqliteStore() override { close(); }
  SqliteStore(const SqliteStore&) = delete;
  SqliteStore& operator=(const SqliteStore&) = delete;

  std::string describe() const override { return "sqlite:" + path_; }

 protected:
  long long exec(const std::string& sql, const std::vector<SqlParam>& params) override {
    sqlite3_stmt* s = prepare(sql, params);
    int rc;
    while ((rc = sqlite3_step(s)) == SQLITE_ROW) {
    }
    finish(s, rc, sql);
    return sqlite3_changes64(db_);
  }

  std::vector<SqlRow> query(const std::string& sql, const std::vector<SqlParam>& params) override {
    sqlite3_stmt* s = prepare(sql, params);
    std::vector<SqlRow> rows;
    int rc;
    const int n = sqlite3_column_count(s);
    while ((rc = sqlite3_step(s)) == SQLITE_ROW) {
      SqlRow row(static_cast<std::size_t>(n));
      for (int c = 0; c < n; ++c) {
        switch (sqlite3_column_type(s, c)) {
          case SQLITE_NULL: break;
          case SQLITE_FLOAT: row[static_cast<std::size_t>(c)] = double_text(sqlite3_column_double(s, c)); break;
          default: {
            const auto* text = reinterpret_cast<const char*>(sqlite3_column_text(s, c));
            row[static_cast<std::size_t>(c)] =
                std::string(text ? text : "", static_cast<std::size_t>(sqlite3_column_bytes(s, c)));
          }
        }
      }
      rows.push_back(std::move(row));
    }
    finish(s, rc, sql);
    return rows;
  }

  void begin_write() override { exec_plain("BEGIN IMMEDIATE"); }
  void commit() override { exec_plain("COMMIT"); }
  void rollback() noexcept override {
    if (!sqlite3_get_autocommit(db_)) sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
  }
  std::string text_type() const override { return "TEXT"; }
  bool table_exists(const std::string& name) override {
    return !query("SELECT name FROM sqlite_master WHERE type = 'table' AND name = $1", {name}).empty();
  }

 private:
  void close() noexcept {
    for (auto& [sql, s] : statements_) sqlite3_finalize(s);
    statements_.clear();
    sqlite3_close(db_);
    db_ = nullptr;
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw StoreError(fmt::format("{}: {}: {}", describe(), what, sqlite3_errmsg(db_)));
  }

  // Switching a new file to WAL takes an exclusive lock, and SQLite answers SQLITE_BUSY at once
  // there instead of calling the busy handler (seen when two processes open a new store together:
  // "database is locked"). So the switch is retried for the busy timeout's 60 s; once the file is
  // in WAL mode (the mode persists in the file) no lock is needed.
  void set_wal_journal() {
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    for (;;) {
      char* err = nullptr;
      const int rc = sqlite3_exec(db_, "PRAGMA journal_mode=WAL", nullptr, nullptr, &err);
      const std::string msg = err ? err : "unknown error";
      sqlite3_free(err);
      if (rc == SQLITE_OK) return;
      if ((rc & 0xff) != SQLITE_BUSY && (rc & 0xff) != SQLITE_LOCKED)
        throw StoreError(fmt::format("{}: PRAGMA journal_mode=WAL: {}", describe(), msg));
      if (std::chrono::steady_clock::now() > until)
        throw StoreError(fmt::format("{}: PRAGMA journal_mode=WAL: {} for 60 s", describe(), msg));
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  }

  void exec_plain(const char* sql) {
    char* err = nullptr;
    if (sqlite3_exec(db_, sql, nullptr, nullptr, &err) != SQLITE_OK) {
      const std::string msg = err ? err : "unknown error";
      sqlite3_free(err);
      throw StoreError(fmt::format("{}: {}: {}", describe(), sql, msg));
    }
  }

  // Prepared statements are kept by their text: a record is a handful of the same statements.
  sqlite3_stmt* prepare(const std::string& sql, const std::vector<SqlParam>& params) {
    sqlite3_stmt*& s = statements_[sql];
    if (!s && sqlite3_prepare_v3(db_, sql.c_str(), static_cast<int>(sql.size()), SQLITE_PREPARE_PERSISTENT, &s,
                                 nullptr) != SQLITE_OK) {
      statements_.erase(sql);
      fail("cannot prepare '" + sql.substr(0, 80) + "'");
    }
    sqlite3_reset(s);
    sqlite3_clear_bindings(s);
    for (std::size_t i = 0; i < params.size(); ++i) {
      // $N parameters are named "$N" in SQLite; each appears once per statement here.
      const int at = sqlite3_bind_parameter_index(s, fmt::format("${}", i + 1).c_str());
      if (at == 0) fail(fmt::format("statement has no parameter ${}", i + 1));
      int rc = SQLITE_OK;
      if (std::holds_alternative<std::nullptr_t>(params[i]))
        rc = sqlite3_bind_null(s, at);
      else if (const auto* t = std::get_if<std::string>(&params[i]))
        rc = sqlite3_bind_text64(s, at, t->data(), t->size(), SQLITE_STATIC, SQLITE_UTF8);
      else if (const auto* d = std::get_if<double>(&params[i]))
        rc = sqlite3_bind_double(s, at, *d);
      else
        rc = sqlite3_bind_int64(s, at, std::get<long long>(params[i]));
      if (rc != SQLITE_OK) fail("cannot bind a parameter");
    }
    return s;
  }

  void finish(sqlite3_stmt* s, int rc, const std::string& sql) {
    if (rc != SQLITE_DONE) {
      const std::string msg = sqlite3_errmsg(db_);
      sqlite3_reset(s);
      throw StoreError(fmt::format("{}: '{}': {}", describe(), sql.substr(0, 80), msg));
    }
    sqlite3_reset(s);
  }

  std::string path_;
  sqlite3* db_ = nullptr;
  std::unordered_map<std::string, sqlite3_stmt*> statements_;
};

}  // namespace

std::unique_ptr<HistoryStore> open_sqlite_store(const std::string& path) {
  if (path.empty()) throw InputError({"history store", 0, ""}, "expected a SQLite file after 'sqlite:', found none");
  return std::make_unique<SqliteStore>(path);
}

}  // namespace mtcal::history_detail
