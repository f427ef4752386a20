// The history store in a PostgreSQL database (libpq): the same schema and queries as SQLite.
#include <libpq-fe.h>

#include <memory>

#include <fmt/format.h>

#include "internal.hpp"

namespace mtcal::history_detail {

namespace {

struct ResultDeleter {
  void operator()(PGresult* r) const noexcept { PQclear(r); }
};
using Result = std::unique_ptr<PGresult, ResultDeleter>;

// The connection string without a password (for messages and describe()).
std::string without_password(const std::string& conninfo) {
  std::string out = conninfo;
  // URI form: postgresql://user:secret@host/db
  const auto scheme = out.find("://");
  if (scheme != std::string::npos) {
    const auto at = out.find('@', scheme + 3);
    const auto colon = out.find(':', scheme + 3);
    if (at != std::string::npos && colon != std::string::npos && colon < at)
      out.replace(colon + 1, at - colon - 1, "***");
  }
  // key=value form and URI query parameters: password=...
  for (auto p = out.find("password="); p != std::string::npos; p = out.find("password=", p + 1)) {
    const auto end = out.find_first_of(" &", p);
    out.replace(p + 9, (end == std::string::npos ? out.size() : end) - p - 9, "***");
  }
  return out;
}

class PostgresStore final : public SqlHistoryStore {
 public:
  explicit PostgresStore(const std::string& conninfo) : name_(without_password(conninfo)) {
    conn_ = PQconnectdb(conninfo.c_str());
    if (!conn_ || PQstatus(conn_) != CONNECTION_OK) {
      const std::string msg = conn_ ? PQerrorMessage(conn_) : "out of memory";
      PQfinish(conn_);
      conn_ = nullptr;
      throw StoreError(describe() + ": cannot connect to the history store: " + trim(msg));
    }
    try {
      // Times and names compare as bytes (COLLATE "C" in the schema); notices (CREATE TABLE IF
      // NOT EXISTS ...) stay off the terminal.
      PQsetNoticeProcessor(
          conn_, [](void*, const char*) {}, nullptr);
      exec("SET client_min_messages = warning", {});
      migrate();
    } catch (...) {
      PQfinish(conn_);
      conn_ = nullptr;
      throw;
    }
  }
  ~PostgresStore() override { PQfinish(conn_); }
  PostgresStore(const PostgresStore&) = delete;
  PostgresStore& operator=(const PostgresStore&) = delete;

  std::string describe() const override { return name_; }

 protected:
  long long exec(const std::string& sql, const std::vector<SqlParam>& params) override {
    const Result r = run(sql, params);
    const char* n = PQcmdTuples(r.get());
    return n && *n ? std::stoll(n) : 0;
  }

  std::vector<SqlRow> query(const std::string& sql, const std::vector<SqlParam>& params) override {
    const Result r = run(sql, params);
    std::vector<SqlRow> rows;
    const int n = PQntuples(r.get()), cols = PQnfields(r.get());
    rows.reserve(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      SqlRow row(static_cast<std::size_t>(cols));
      for (int c = 0; c < cols; ++c)
        if (!PQgetisnull(r.get(), i, c))
          row[static_cast<std::size_t>(c)] =
              std::string(PQgetvalue(r.get(), i, c), static_cast<std::size_t>(PQgetlength(r.get(), i, c)));
      rows.push_back(std::move(row));
    }
    return rows;
  }

  void begin_write() override { exec("BEGIN", {}); }
  void commit() override { exec("COMMIT", {}); }
  void rollback() noexcept override {
    if (conn_ && PQtransactionStatus(conn_) != PQTRANS_IDLE) PQclear(PQexec(conn_, "ROLLBACK"));
  }
  // One migration at a time per database: a lock held to the end of the transaction (the key is
  // any constant that this program alone uses: "mtcal" in ASCII).
  void lock_for_migration() override { exec("SELECT pg_advisory_xact_lock(469853495660)", {}); }
  std::string text_type() const override { return "TEXT COLLATE \"C\""; }
  bool table_exists(const std::string& name) override {
    const auto rows = query("SELECT to_regclass($1) IS NOT NULL", {name});
    return !rows.empty() && rows[0][0] && *rows[0][0] == "t";
  }

 private:
  static std::string trim(std::string s) {
    while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
    return s;
  }

  Result run(const std::string& sql, const std::vector<SqlParam>& params) {
    // Every parameter as text: doubles in their shortest exact form, so that nothing is lost;
    // the server infers the types from the statement.
    std::vector<std::string> texts(params.size());
    std::vector<const char*> values(params.size(), nullptr);
    for (std::size_t i = 0; i < params.size(); ++i) {
      if (std::holds_alternative<std::nullptr_t>(params[i])) continue;
      if (const auto* t = std::get_if<std::string>(&params[i]))
        texts[i] = *t;
      else if (const auto* d = std::get_if<double>(&params[i]))
        texts[i] = double_text(*d);
      else
        texts[i] = std::to_string(std::get<long long>(params[i]));
      values[i] = texts[i].c_str();
    }
    Result r(
        PQexecParams(conn_, sql.c_str(), static_cast<int>(params.size()), nullptr, values.data(), nullptr, nullptr, 0));
    const auto status = r ? PQresultStatus(r.get()) : PGRES_FATAL_ERROR;
    if (status != PGRES_COMMAND_OK && status != PGRES_TUPLES_OK)
      throw StoreError(fmt::format("{}: '{}': {}", describe(), sql.substr(0, 80), trim(PQerrorMessage(conn_))));
    return r;
  }

  std::string name_;
  PGconn* conn_ = nullptr;
};

}  // namespace

std::unique_ptr<HistoryStore> open_postgres_store(const std::string& conninfo) {
  return std::make_unique<PostgresStore>(conninfo);
}

}  // namespace mtcal::history_detail
