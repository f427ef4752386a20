// The calibration history store (issue 19) on SQLite and on a real PostgreSQL server: records,
// queries, events, atomicity, concurrent writers, JSON-lines export/import, bad input.
#include <sys/wait.h>
#include <unistd.h>

#include <sqlite3.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <tuple>

#include <gtest/gtest.h>

#include <libpq-fe.h>

#include "mtcal/io/history/config.hpp"
#include "mtcal/io/history/queries.hpp"
#include "mtcal/io/history/store.hpp"
#include "mtcal/io/json/history_json.hpp"
#include "pg_server.hpp"
#include "temp_dir.hpp"

using namespace mtcal;
namespace fs = std::filesystem;

namespace {

mtcal::testing::PgServer& pg() { return mtcal::testing::shared_pg_server(); }

using mtcal::testing::TempDir;

std::atomic<int> g_db{0};

CalibrationRecord sample(const std::string& machine, const std::string& date, double exx, int n = 0) {
  CalibrationRecord r;
  r.machine_name = machine;
  r.machine_serial = "SN-" + machine;
  r.command = "identify";
  r.measured_at = date;
  r.metadata = {{"operator", "A. Smith"}, {"temperature", "20.1 °C"}, {"date", date}};
  r.inputs = {{"plan.csv", sha256_hex("plan " + std::to_string(n))}};
  r.parameters = {{"EXX", exx, 0.25, "um"}, {"EC0Y", 1e-5 * n, std::nullopt, "rad"}};
  r.figures = {{"VA", 10 + exx, "um", std::nullopt}};
  r.result_json = R"({"n":)" + std::to_string(n) + "}";
  return r;
}

}  // namespace

// ---- SHA-256 against the standard's examples --------------------------------------------------

TEST(Sha256, Fips180Examples) {
  // FIPS 180-2 appendix B.1, B.2, B.3 and the empty message (NIST CSRC example values).
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(sha256_hex(std::string(1'000'000, 'a')),
            "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  // 55, 56 and 64 bytes: the padding's boundary cases (one block, two blocks).
  EXPECT_EQ(sha256_hex(std::string(55, 'a')), "9f4390f8d30c2dd92ec9f095b65e2b9ae9b0a925a5258e241c9f1e910f734318");
  EXPECT_EQ(sha256_hex(std::string(56, 'a')), "b35439a4ac6f0948b6d6f9e3c6af0f5f590ce20f1bde7090ef7970686ec6738a");
  EXPECT_EQ(sha256_hex(std::string(64, 'a')), "ffe054fe7ae0cb6dc65c3af9b61d5209f439851db43d0ba5997337df154668eb");
}

TEST(Sha256, FileMatchesBytesAndMissingFileIsAnError) {
  TempDir d;
  const auto p = (d.path / "f.bin").string();
  std::string bytes(200'000, '\0');
  for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<char>(i * 7);
  std::ofstream(p, std::ios::binary) << bytes;
  EXPECT_EQ(sha256_file(p), sha256_hex(bytes));
  EXPECT_THROW(sha256_file((d.path / "none").string()), InputError);
}

TEST(History, Iso8601) {
  for (const char* ok : {"2026-11-25", "2024-02-29", "2026-11-25T10:30Z", "2026-11-25T10:30:05Z",
                         "2026-11-25T10:30:05.123Z", "2026-11-25T10:30:05+01:00", "2026-11-25T23:59:60Z"})
    EXPECT_TRUE(is_iso8601(ok)) << ok;
  for (const char* bad : {"", "2026", "25.11.2026", "2026-13-01", "2026-02-30", "2025-02-29", "2026-11-25T24:00Z",
                          "2026-11-25 10:30", "2026-11-25T10:30:05.Z", "2026-11-25T10:30:05+1", "2026-11-25x"})
    EXPECT_FALSE(is_iso8601(bad)) << bad;
}

TEST(History, EventKindNames) {
  for (auto k : {EventKind::CompensationLoaded, EventKind::Crash, EventKind::Repair, EventKind::Other})
    EXPECT_EQ(parse_event_kind(to_string(k)), k);
  EXPECT_EQ(to_string(EventKind::CompensationLoaded), "compensation-loaded");
  EXPECT_FALSE(parse_event_kind("Crash"));
}

// ---- both backends ----------------------------------------------------------------------------

class Store : public ::testing::TestWithParam<std::string> {
 protected:
  // A fresh, empty store of the backend under test.
  std::string fresh() {
    if (GetParam() == "sqlite") return "sqlite:" + (dir_.path / ("s" + std::to_string(g_db++) + ".db")).string();
    if (!pg().available()) return {};
    return pg().create_database("t" + std::to_string(::getpid()) + "_" + std::to_string(g_db++));
  }
  void SetUp() override {
    if (GetParam() == "postgresql" && !pg().available()) GTEST_SKIP() << "PostgreSQL tests skipped: " << pg().why();
    conn_ = fresh();
    store_ = open_history_store(conn_);
  }
  TempDir dir_;
  std::string conn_;
  std::unique_ptr<HistoryStore> store_;
};

TEST_P(Store, RecordGetListRoundTrip) {
  EXPECT_EQ(store_->schema_version(), kHistorySchemaVersion);
  auto r = sample("M1", "2026-03-01", 1.5, 1);
  r.parameters[0].value = 0.1 + 0.2;  // 0.30000000000000004: every bit must survive
  r.figures[0].value = 1e-300;
  const std::string id = store_->record(r);
  ASSERT_EQ(id.size(), 16u);
  const auto got = store_->get(id);
  ASSERT_TRUE(got);
  EXPECT_EQ(got->machine_name, "M1");
  EXPECT_EQ(got->machine_serial, "SN-M1");
  EXPECT_EQ(got->measured_at, "2026-03-01");
  EXPECT_TRUE(is_iso8601(got->recorded_at)) << got->recorded_at;
  EXPECT_EQ(got->metadata, r.metadata);
  EXPECT_EQ(got->inputs, r.inputs);
  EXPECT_EQ(got->parameters, r.parameters);
  EXPECT_EQ(got->figures, r.figures);
  EXPECT_EQ(got->result_json, r.result_json);
  EXPECT_EQ(got->content_hash.size(), 64u);
  EXPECT_FALSE(store_->get("nope"));
  // The same content again is a duplicate: the stored record's id, nothing added.
  EXPECT_EQ(store_->record(r), id);
  EXPECT_EQ(store_->list().size(), 1u);
  EXPECT_EQ(store_->find_by_content_hash(got->content_hash), id);
}

TEST_P(Store, ListFiltersAndOrders) {
  store_->record(sample("M2", "2026-05-01T08:00:00Z", 2, 1));
  store_->record(sample("M1", "2026-02-01", 1, 2));
  store_->record(sample("M1", "2026-01-15T12:00:00Z", 3, 3));
  store_->record(sample("M1", "2026-01-15", 4, 4));
  const auto all = store_->list();
  ASSERT_EQ(all.size(), 4u);
  std::vector<std::string> times;
  for (const auto& r : all) times.push_back(r.measured_at);
  EXPECT_EQ(times,
            (std::vector<std::string>{"2026-01-15", "2026-01-15T12:00:00Z", "2026-02-01", "2026-05-01T08:00:00Z"}));
  EXPECT_EQ(store_->list({"M1", "", "", ""}).size(), 3u);
  EXPECT_EQ(store_->list({"M1", "", "2026-01-16", ""}).size(), 1u);
  // A date as the end includes that day's times.
  EXPECT_EQ(store_->list({"", "", "", "2026-01-15"}).size(), 2u);
  EXPECT_EQ(store_->list({"", "iso230-2", "", ""}).size(), 0u);
  EXPECT_EQ(store_->machines(), (std::vector<std::string>{"M1", "M2"}));
}

TEST_P(Store, SeriesAndFleetLatest) {
  store_->record(sample("M1", "2026-03-01", 3.0, 1));
  store_->record(sample("M1", "2026-01-01", 1.0, 2));
  store_->record(sample("M1", "2026-02-01", 2.0, 3));
  store_->record(sample("M2", "2025-12-01", 7.0, 4));
  const auto s = store_->parameter_series("M1", "EXX");
  ASSERT_EQ(s.size(), 3u);
  EXPECT_EQ(s[0].time, "2026-01-01");
  EXPECT_EQ(s[0].value, 1.0);
  EXPECT_EQ(s[2].value, 3.0);
  EXPECT_EQ(s[1].uncertainty, 0.25);
  EXPECT_EQ(s[1].unit, "um");
  EXPECT_FALSE(store_->parameter_series("M1", "EC0Y")[0].uncertainty);
  const auto f = store_->figure_series("M1", "VA");
  ASSERT_EQ(f.size(), 3u);
  EXPECT_EQ(f[1].value, 12.0);
  const auto latest = store_->latest_parameter("EXX");
  ASSERT_EQ(latest.size(), 2u);
  EXPECT_EQ(latest[0].machine, "M1");
  EXPECT_EQ(latest[0].sample.value, 3.0);
  EXPECT_EQ(latest[0].sample.time, "2026-03-01");
  EXPECT_EQ(latest[1].machine, "M2");
  EXPECT_EQ(latest[1].sample.value, 7.0);
  EXPECT_EQ(store_->latest_figure("VA")[1].sample.value, 17.0);
  EXPECT_TRUE(store_->latest_figure("nothing").empty());
  // An older calibration recorded later does not replace the latest; removing the latest brings
  // back the one before.
  store_->record(sample("M1", "2025-06-01", 9.0, 5));
  EXPECT_EQ(store_->latest_parameter("EXX")[0].sample.value, 3.0);
  const auto newest = store_->record(sample("M1", "2026-04-01", 4.0, 6));
  EXPECT_EQ(store_->latest_parameter("EXX")[0].sample.value, 4.0);
  EXPECT_TRUE(store_->remove(newest));
  EXPECT_EQ(store_->latest_parameter("EXX")[0].sample.value, 3.0);
  EXPECT_EQ(store_->latest_figure("VA")[0].sample.value, 13.0);
  // In one batch, the newest of a machine wins whatever the order.
  store_->record_all(
      {sample("M3", "2026-05-01", 5.0, 7), sample("M3", "2026-07-01", 7.0, 8), sample("M3", "2026-06-01", 6.0, 9)});
  EXPECT_EQ(store_->latest_parameter("EXX")[2].sample.value, 7.0);
}

TEST_P(Store, Events) {
  const auto a = store_->add_event({"", "M1", "2026-02-10", EventKind::Crash, "Z axis hit the vice"});
  store_->add_event({"", "M2", "2026-01-10", EventKind::Repair, ""});
  store_->add_event({"", "M1", "2026-01-05", EventKind::CompensationLoaded, "pitch table v2"});
  const auto m1 = store_->events("M1");
  ASSERT_EQ(m1.size(), 2u);
  EXPECT_EQ(m1[0].kind, EventKind::CompensationLoaded);
  EXPECT_EQ(m1[1].id, a);
  EXPECT_EQ(m1[1].note, "Z axis hit the vice");
  EXPECT_EQ(store_->events().size(), 3u);
  EXPECT_THROW(store_->add_event({"", "M1", "10.2.2026", EventKind::Other, ""}), InputError);
  EXPECT_THROW(store_->add_event({"", "", "2026-01-01", EventKind::Other, ""}), InputError);
}

TEST_P(Store, AFailingWriteRecordsNothing) {
  store_->record(sample("M0", "2026-01-01", 0, 0));
  // Checked before the transaction: a bad date in the third of three records.
  std::vector<CalibrationRecord> batch{sample("M1", "2026-01-01", 1, 1), sample("M1", "2026-02-01", 2, 2),
                                       sample("M1", "01/03/2026", 3, 3)};
  EXPECT_THROW(store_->record_all(batch), InputError);
  // Failing inside the database, after rows were written: the second record's id is the first's
  // while its content differs; the transaction is rolled back as a whole.
  batch[2].measured_at = "2026-03-01";
  batch[1].id = "0123456789abcdef";
  batch[2].id = "0123456789abcdef";
  EXPECT_THROW(store_->record_all(batch), StoreError);
  EXPECT_EQ(store_->list().size(), 1u);
  EXPECT_TRUE(store_->parameter_series("M1", "EXX").empty());
  EXPECT_TRUE(store_->figure_series("M1", "VA").empty());
  // A record without a machine or a command is refused.
  auto r = sample("", "2026-01-01", 1);
  EXPECT_THROW(store_->record(r), InputError);
  r = sample("M1", "2026-01-01", 1);
  r.command.clear();
  EXPECT_THROW(store_->record(r), InputError);
  r = sample("M1", "2026-01-01", 1);
  r.parameters[0].value = std::nan("");
  EXPECT_THROW(store_->record(r), InputError);
  EXPECT_EQ(store_->list().size(), 1u);
  // remove() takes a record and its values out.
  const auto id = store_->record(sample("M1", "2026-01-01", 1, 9));
  EXPECT_TRUE(store_->remove(id));
  EXPECT_FALSE(store_->remove(id));
  EXPECT_TRUE(store_->parameter_series("M1", "EXX").empty());
}

TEST_P(Store, ReopeningKeepsRecordsAndSchema) {
  store_->record(sample("M1", "2026-01-01", 1, 1));
  store_.reset();
  auto again = open_history_store(conn_);
  EXPECT_EQ(again->list().size(), 1u);
  EXPECT_EQ(again->schema_version(), kHistorySchemaVersion);
}

// Two processes, 1,000 records each, one transaction per record, at the same time: all 2,000 kept.
TEST_P(Store, TwoConcurrentWritersLoseNothing) {
  constexpr int kEach = 1000;
  store_.reset();
  std::vector<pid_t> children;
  for (int w = 0; w < 2; ++w) {
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      int rc = 0;
      try {
        auto s = open_history_store(conn_);
        for (int i = 0; i < kEach; ++i) s->record(sample("W" + std::to_string(w), "2026-01-01", i, w * kEach + i));
      } catch (const std::exception& e) {
        std::fprintf(stderr, "writer %d: %s\n", w, e.what());
        rc = 1;
      }
      std::fflush(stderr);
      ::_exit(rc);
    }
    children.push_back(pid);
  }
  for (const pid_t pid : children) {
    int status = 0;
    ::waitpid(pid, &status, 0);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "a writer failed";
  }
  auto s = open_history_store(conn_);
  EXPECT_EQ(s->list({"W0", "", "", ""}).size(), static_cast<std::size_t>(kEach));
  EXPECT_EQ(s->list({"W1", "", "", ""}).size(), static_cast<std::size_t>(kEach));
  EXPECT_EQ(s->parameter_series("W1", "EXX").size(), static_cast<std::size_t>(kEach));
}

TEST_P(Store, ExportImportIsLossless) {
  for (int i = 0; i < 30; ++i) {
    auto r = sample("M" + std::to_string(i % 3), "2026-01-" + std::string(i < 9 ? "0" : "") + std::to_string(i + 1),
                    0.1 * i + 1e-17, i);
    r.metadata["note"] = "line\nbreak \"quoted\" \xc2\xb5m";
    r.result_json = R"({"machine":"M","A":)" + std::to_string(i) + R"(,"list":[1,2.5e-300]})";
    store_->record(r);
  }
  store_->add_event({"", "M1", "2026-01-20", EventKind::Crash, "tab\there"});
  std::ostringstream first;
  export_jsonl(*store_, first);
  auto other = open_history_store(fresh());
  std::istringstream in(first.str());
  const auto summary = import_jsonl(*other, in, "export.jsonl");
  EXPECT_EQ(summary.records, 30u);
  EXPECT_EQ(summary.events, 1u);
  EXPECT_TRUE(summary.skipped.empty());
  std::ostringstream second;
  export_jsonl(*other, second);
  EXPECT_EQ(first.str(), second.str());
  EXPECT_EQ(other->list(), store_->list());
  // Importing again: every record a duplicate, reported with its line; nothing added.
  std::istringstream again(first.str());
  const auto dup = import_jsonl(*other, again, "export.jsonl");
  EXPECT_EQ(dup.records, 0u);
  EXPECT_EQ(dup.events, 0u);
  ASSERT_EQ(dup.skipped.size(), 30u);
  EXPECT_EQ(dup.skipped[0].rfind("line 1: duplicate of record ", 0), 0u) << dup.skipped[0];
  EXPECT_EQ(other->list().size(), 30u);
}

// mtcal serve's accounts (schema 3): users, sessions that expire, writes with their author in
// the audit; names full of SQL metacharacters are stored and found as text (bound parameters).
TEST_P(Store, AccountsSessionsAndAudit) {
  const std::string evil = "o'brien\"; DROP TABLE records; --";
  store_->put_user({evil, "engineer", "hash1", ""});
  store_->put_user({"ann", "admin", "hash2", ""});
  store_->put_user({evil, "viewer", "hash3", ""});  // replaces role and hash
  const auto u = store_->find_user(evil);
  ASSERT_TRUE(u);
  EXPECT_EQ(u->role, "viewer");
  EXPECT_EQ(u->password_hash, "hash3");
  EXPECT_FALSE(store_->find_user("o'brien"));
  EXPECT_EQ(store_->users().size(), 2u);

  store_->put_session({"h1", evil, "csrf1", "2026-01-01T00:00:00.000Z", "2026-01-02T00:00:00.000Z"});
  EXPECT_TRUE(store_->find_session("h1", "2026-01-01T12:00:00.000Z"));
  EXPECT_FALSE(store_->find_session("h1", "2026-01-02T00:00:00.000Z"));  // expired
  EXPECT_FALSE(store_->find_session("h1' OR '1'='1", "2026-01-01T12:00:00.000Z"));
  EXPECT_TRUE(store_->remove_session("h1"));
  EXPECT_FALSE(store_->find_session("h1", "2026-01-01T12:00:00.000Z"));
  store_->put_session({"h2", "ann", "c", "2026-01-01T00:00:00.000Z", "2026-01-02T00:00:00.000Z"});
  EXPECT_EQ(store_->remove_expired_sessions("2026-01-03T00:00:00.000Z"), 1);

  auto r = sample(evil, "2026-01-01", 1);
  const std::string id = store_->record_by(r, evil);
  EXPECT_EQ(store_->record_by(r, "ann"), id);  // a duplicate: no second audit row
  const std::string ev = store_->add_event_by({"", evil, "2026-01-05", EventKind::Crash, "<script>x</script>"}, "ann");
  const auto a = store_->audit();
  ASSERT_EQ(a.size(), 2u);
  EXPECT_EQ(a[0].user, evil);
  EXPECT_EQ(a[0].action, "record");
  EXPECT_EQ(a[0].object_id, id);
  EXPECT_EQ(a[1].user, "ann");
  EXPECT_EQ(a[1].object_id, ev);
  EXPECT_EQ(store_->audit(ev).size(), 1u);
  EXPECT_EQ(store_->machines(), std::vector<std::string>{evil});
  EXPECT_EQ(store_->events(evil).at(0).note, "<script>x</script>");

  store_->record(sample(evil, "2026-03-01", 2));
  store_->record(sample("M2", "2026-02-01", 3));
  const auto latest = store_->latest_calibrations();
  ASSERT_EQ(latest.size(), 2u);
  EXPECT_EQ(latest[0].machine, "M2");
  EXPECT_EQ(latest[1].machine, evil);
  EXPECT_EQ(latest[1].count, 2);
  EXPECT_EQ(latest[1].measured_at, "2026-03-01");
  // Removing the latest record brings back the one before it, and the count.
  ASSERT_TRUE(store_->remove(latest[1].record_id));
  const auto after = store_->latest_calibrations();
  ASSERT_EQ(after.size(), 2u);
  EXPECT_EQ(after[1].record_id, id);
  EXPECT_EQ(after[1].count, 1);
  ASSERT_TRUE(store_->remove(id));
  EXPECT_EQ(store_->latest_calibrations().size(), 1u);
}

// Runs SQL on the store's database behind the store's back (a test that takes a store back to
// an older schema): sqlite3 or libpq.
void raw_sql(const std::string& conn, const std::string& sql) {
  if (conn.rfind("sqlite:", 0) == 0) {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(conn.substr(7).c_str(), &db), SQLITE_OK);
    char* err = nullptr;
    const int rc = sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &err);
    EXPECT_EQ(rc, SQLITE_OK) << (err ? err : "") << ": " << sql;
    sqlite3_free(err);
    sqlite3_close(db);
    return;
  }
  PGconn* db = PQconnectdb(conn.c_str());
  ASSERT_EQ(PQstatus(db), CONNECTION_OK) << PQerrorMessage(db);
  PGresult* r = PQexec(db, sql.c_str());
  EXPECT_EQ(PQresultStatus(r), PGRES_COMMAND_OK) << PQerrorMessage(db) << ": " << sql;
  PQclear(r);
  PQfinish(db);
}

std::map<std::string, long long> revisions(HistoryStore& s) {
  std::map<std::string, long long> out;
  for (const auto& r : s.machine_revisions()) out[r.machine] = r.revision;
  return out;
}

// A machine's revision rises with every write of its records (a record, a batch by its count, a
// removal), not with events, duplicates or a removal of nothing; other machines' stay.
TEST_P(Store, MachineRevisionsRiseWithEveryWriteOfItsRecords) {
  EXPECT_TRUE(store_->machine_revisions().empty());
  const std::string first = store_->record(sample("M1", "2026-01-01", 1, 1));
  EXPECT_EQ(revisions(*store_), (std::map<std::string, long long>{{"M1", 1}}));
  store_->record_all({sample("M1", "2026-02-01", 2, 2), sample("M1", "2026-03-01", 3, 3), sample("M2", "2026-01-01", 1, 4)});
  EXPECT_EQ(revisions(*store_), (std::map<std::string, long long>{{"M1", 3}, {"M2", 1}}));
  store_->record(sample("M1", "2026-01-01", 1, 1));  // a duplicate: nothing written
  store_->add_event({"", "M1", "2026-02-15", EventKind::Repair, "spindle"});
  store_->add_event_by({"", "M2", "2026-02-15", EventKind::Crash, ""}, "ann");
  EXPECT_EQ(revisions(*store_), (std::map<std::string, long long>{{"M1", 3}, {"M2", 1}}));
  EXPECT_TRUE(store_->remove(first));
  EXPECT_FALSE(store_->remove(first));
  EXPECT_EQ(revisions(*store_), (std::map<std::string, long long>{{"M1", 4}, {"M2", 1}}));
  store_->record_by(sample("M2", "2026-04-01", 4, 5), "ann");
  EXPECT_EQ(revisions(*store_), (std::map<std::string, long long>{{"M1", 4}, {"M2", 2}}));
}

// A store of schema version 3 (before machine_revisions) gains the table, filled with each
// machine's count of records, and the next write raises it.
TEST_P(Store, MigrationFromVersion3FillsMachineRevisions) {
  store_->record_all({sample("M1", "2026-01-01", 1, 1), sample("M1", "2026-02-01", 2, 2), sample("M2", "2026-01-01", 1, 3)});
  const auto before = store_->list();
  store_.reset();
  raw_sql(conn_, "DROP TABLE machine_revisions");
  raw_sql(conn_, "DROP TABLE model_files");
  raw_sql(conn_, "ALTER TABLE records DROP COLUMN invocation");
  raw_sql(conn_, "DELETE FROM schema_version WHERE version >= 4");
  store_ = open_history_store(conn_);
  EXPECT_EQ(store_->schema_version(), kHistorySchemaVersion);
  EXPECT_EQ(store_->list(), before);
  EXPECT_EQ(revisions(*store_), (std::map<std::string, long long>{{"M1", 2}, {"M2", 1}}));
  store_->record(sample("M2", "2026-02-01", 2, 4));
  EXPECT_EQ(revisions(*store_), (std::map<std::string, long long>{{"M1", 2}, {"M2", 2}}));
}

// Model files (schema 5): stored with their records in one transaction, each content once
// (again with a duplicate record, again within one batch), refused when the hash is not the
// content's; carried by export/import as "model_file" lines (the same bytes again).
TEST_P(Store, ModelFilesAreKeptOncePerContentAndExported) {
  const std::string machine = "mtcal_machine: 1\nname: M1 \xc2\xb5\n", params = "mtcal_parameters: 1\nerrors: {}\n";
  const ModelFile m{sha256_hex(machine), "machine", machine}, p{sha256_hex(params), "parameters", params};
  auto r = sample("M1", "2026-01-01", 1, 1);
  r.inputs.insert(r.inputs.begin(), {{"m.yaml", m.sha256}, {"p.yaml", p.sha256}});
  std::vector<std::size_t> skipped;
  store_->record_all({r}, {}, &skipped, {m, p, m});
  store_->record_all({r}, {}, &skipped, {m, p});  // a duplicate record: nothing new
  EXPECT_EQ(skipped.size(), 1u);
  auto r2 = sample("M1", "2026-02-01", 2, 2);
  r2.inputs = r.inputs;
  store_->record_all({r2}, {}, nullptr, {p, m});
  std::vector<ModelFile> expected{m, p};
  std::sort(expected.begin(), expected.end(), [](const ModelFile& x, const ModelFile& y) { return x.sha256 < y.sha256; });
  EXPECT_EQ(store_->model_files(), expected);
  ASSERT_TRUE(store_->model_file(m.sha256));
  EXPECT_EQ(*store_->model_file(m.sha256), m);
  EXPECT_FALSE(store_->model_file(sha256_hex("other")));
  // A file whose hash is not its content's, or of another kind: refused, and the record with it.
  const auto before = store_->list().size();
  EXPECT_THROW(store_->record_all({sample("M2", "2026-01-01", 3, 3)}, {}, nullptr, {{m.sha256, "machine", params}}),
               InputError);
  EXPECT_THROW(store_->record_all({sample("M2", "2026-01-01", 3, 3)}, {}, nullptr, {{p.sha256, "plan", params}}),
               InputError);
  EXPECT_EQ(store_->list().size(), before);
  std::ostringstream first;
  export_jsonl(*store_, first);
  EXPECT_NE(first.str().find(R"({"type":"model_file","sha256":")" + std::min(m.sha256, p.sha256)), std::string::npos);
  auto other = open_history_store(fresh());
  std::istringstream in(first.str());
  EXPECT_EQ(import_jsonl(*other, in, "export.jsonl").model_files, 2u);
  std::ostringstream second;
  export_jsonl(*other, second);
  EXPECT_EQ(first.str(), second.str());
  std::istringstream again(first.str());
  EXPECT_EQ(import_jsonl(*other, again, "export.jsonl").model_files, 0u);
  EXPECT_EQ(other->model_files().size(), 2u);
}

// A store of schema version 4 (before model_files) gains the table, empty; its records read as
// before and the next record keeps its files.
TEST_P(Store, MigrationFromVersion4AddsModelFiles) {
  store_->record(sample("M1", "2026-01-01", 1, 1));
  const auto before = store_->list();
  store_.reset();
  raw_sql(conn_, "DROP TABLE model_files");
  raw_sql(conn_, "ALTER TABLE records DROP COLUMN invocation");
  raw_sql(conn_, "DELETE FROM schema_version WHERE version >= 5");
  store_ = open_history_store(conn_);
  EXPECT_EQ(store_->schema_version(), kHistorySchemaVersion);
  EXPECT_EQ(store_->list(), before);
  EXPECT_TRUE(store_->model_files().empty());
  const std::string text = "mtcal_parameters: 1\n";
  store_->record_all({sample("M1", "2026-02-01", 2, 2)}, {}, nullptr, {{sha256_hex(text), "parameters", text}});
  EXPECT_EQ(store_->model_files().size(), 1u);
}

// A store of schema version 5 (before invocations and measurement files) gains the column, its
// records read as before (no invocation); the next record keeps its invocation and measurement
// file, and both go through export and import unchanged.
TEST_P(Store, MigrationFromVersion5AddsInvocations) {
  store_->record(sample("M1", "2026-01-01", 1, 1));
  const auto before = store_->list();
  store_.reset();
  raw_sql(conn_, "ALTER TABLE records DROP COLUMN invocation");
  raw_sql(conn_, "DELETE FROM schema_version WHERE version = 6");
  store_ = open_history_store(conn_);
  EXPECT_EQ(store_->schema_version(), kHistorySchemaVersion);
  EXPECT_EQ(store_->list(), before);
  EXPECT_EQ(before[0].invocation, "");
  const std::string runs = "target,run,direction,deviation\n0,1,up,0.001\n";
  auto r = sample("M1", "2026-02-01", 2, 2);
  r.inputs = {{"runs.csv", sha256_hex(runs)}};
  r.invocation = R"({"command_line":"mtcal iso230-2 runs.csv --record"})";
  const auto id = store_->record_all({r}, {}, nullptr, {{sha256_hex(runs), "measurements", runs}})[0];
  EXPECT_EQ(store_->get(id)->invocation, r.invocation);
  EXPECT_EQ(store_->model_file(sha256_hex(runs))->kind, "measurements");
  std::ostringstream first;
  export_jsonl(*store_, first);
  // Only a record that has one carries the key: the older record's line is as version 5 wrote it.
  const std::string text = first.str();
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 3);
  ASSERT_NE(text.find("\"invocation\""), std::string::npos);
  EXPECT_EQ(text.find("\"invocation\""), text.rfind("\"invocation\""));
  auto other = open_history_store(fresh());
  std::istringstream in(first.str());
  EXPECT_EQ(import_jsonl(*other, in, "export.jsonl").model_files, 1u);
  EXPECT_EQ(other->get(id)->invocation, r.invocation);
  std::ostringstream second;
  export_jsonl(*other, second);
  EXPECT_EQ(first.str(), second.str());
  // Another kind than machine, parameters or measurements is refused.
  EXPECT_THROW(store_->record_all({}, {}, nullptr, {{sha256_hex(runs), "notes", runs}}), InputError);
}

// FleetRanker (mtcal serve's fleet page) gives what rank_store (history rank) gives after every
// kind of write, and fits again only the series of the machine whose records changed: a new
// record; an event (nothing); a removal and an older record between two calls, which leave the
// machine's latest record and count as they were; a write through another connection (another
// server process on the same store).
TEST_P(Store, FleetRankerIsRankStoreAfterEveryWrite) {
  for (int m = 1; m <= 3; ++m)
    for (int k = 0; k < 4; ++k)
      store_->record(sample("M" + std::to_string(m), "2026-0" + std::to_string(k + 1) + "-01", 0.5 * m + 0.3 * k * m, 10 * m + k));
  RankRequest request;
  request.tolerances = parse_history_tolerances({"EXX=6", "VA=20"});
  FleetRanker ranker(request, false);
  // The reference: rank_fleet of every series read now (EXX a parameter, |EXX| <= 6 um; VA a
  // figure, VA <= 20 um; in name order as history rank takes them), and history rank's own.
  const auto reference = [&] {
    std::vector<RankSeries> series;
    for (const auto& [name, figure, band] : {std::tuple{std::string("EXX"), false, ToleranceBand::symmetric(6)},
                                             std::tuple{std::string("VA"), true, ToleranceBand::at_most(20)}})
      for (const auto& l : figure ? store_->latest_figure(name) : store_->latest_parameter(name)) {
        const auto q = trend_from_series(
            name, figure, figure ? store_->figure_series(l.machine, name) : store_->parameter_series(l.machine, name), band);
        series.push_back({l.machine, name, q.unit, q.samples, band});
      }
    return to_json(rank_fleet(series));
  };
  const auto same = [&](const FleetRanker::Ranking& r) {
    const Json got = to_json(r.ranking);
    EXPECT_EQ(got, reference());
    return got == to_json(rank_store(*store_, request).ranking);
  };
  // `changed`: the machines whose entry may differ from the last ranking's; every other
  // machine's entry is the last one's but for its rank number.
  const auto kept_but_rank = [](const FleetRanker::Ranking& now, const FleetRanker::Ranking& last) {
    std::map<std::string, Json> before;
    for (const auto& m : last.ranking.machines) before[m.machine] = to_json(m);
    ASSERT_EQ(now.serial, last.serial + 1);
    for (const auto& m : now.ranking.machines) {
      if (std::binary_search(now.changed.begin(), now.changed.end(), m.machine)) continue;
      ASSERT_TRUE(before.count(m.machine)) << m.machine << " is new but not said to have changed";
      Json a = to_json(m), b = before[m.machine];
      a.erase("rank");
      b.erase("rank");
      EXPECT_EQ(a, b) << m.machine;
    }
  };
  const auto r1 = ranker.rank(*store_);
  EXPECT_TRUE(same(*r1));
  EXPECT_EQ(r1->fitted, 6u);  // 3 machines x (EXX, VA)
  EXPECT_EQ(r1->serial, 1u);
  EXPECT_EQ(r1->changed, (std::vector<std::string>{"M1", "M2", "M3"}));
  EXPECT_EQ(r1->ranking.machines.front().machine, "M3");
  EXPECT_EQ(ranker.rank(*store_), r1);  // nothing changed: the same ranking
  store_->add_event({"", "M2", "2026-03-15", EventKind::Repair, ""});
  EXPECT_EQ(ranker.rank(*store_), r1);  // events do not change a ranking
  // M1 drifts fast now: it ranks first; only its two series are read again.
  store_->record(sample("M1", "2026-05-01", 5.5, 15));
  const auto r2 = ranker.rank(*store_);
  EXPECT_TRUE(same(*r2));
  EXPECT_EQ(r2->fitted, 2u);
  EXPECT_EQ(r2->ranking.machines.front().machine, "M1");
  EXPECT_EQ(r2->changed, std::vector<std::string>{"M1"});
  kept_but_rank(*r2, *r1);
  // M3: one record removed and an older one of another value added, so its latest record and
  // count are as before: the ranking still follows.
  const auto m3 = store_->list({"M3", "", "", ""});
  ASSERT_EQ(m3.size(), 4u);
  const auto before = to_json(r2->ranking);
  ASSERT_TRUE(store_->remove(m3[1].id));
  store_->record(sample("M3", "2026-02-15", 0.1, 99));
  const auto r3 = ranker.rank(*store_);
  EXPECT_TRUE(same(*r3));
  EXPECT_EQ(r3->fitted, 2u);
  EXPECT_NE(to_json(r3->ranking), before);
  EXPECT_EQ(r3->changed, std::vector<std::string>{"M3"});
  kept_but_rank(*r3, *r2);
  // Another connection writes (another server on this store).
  auto other = open_history_store(conn_);
  other->record(sample("M2", "2026-06-01", 9.0, 77));
  const auto r4 = ranker.rank(*store_);
  EXPECT_TRUE(same(*r4));
  EXPECT_EQ(r4->fitted, 2u);
  EXPECT_EQ(r4->ranking.machines.front().machine, "M2");
  EXPECT_EQ(r4->changed, std::vector<std::string>{"M2"});
  kept_but_rank(*r4, *r3);
  // A new machine: its series read, the others kept.
  other->record(sample("M4", "2026-06-01", 1.0, 88));
  const auto r5 = ranker.rank(*store_);
  EXPECT_TRUE(same(*r5));
  EXPECT_EQ(r5->fitted, 2u);
  EXPECT_EQ(r5->ranking.machines.size(), 4u);
  EXPECT_EQ(r5->changed, std::vector<std::string>{"M4"});
  kept_but_rank(*r5, *r4);
  // M4's only record removed: M4 leaves the ranking; nobody else changed.
  const auto m4 = store_->list({"M4", "", "", ""});
  ASSERT_EQ(m4.size(), 1u);
  ASSERT_TRUE(store_->remove(m4[0].id));
  const auto r6 = ranker.rank(*store_);
  EXPECT_TRUE(same(*r6));
  EXPECT_EQ(r6->ranking.machines.size(), 3u);
  EXPECT_TRUE(r6->changed.empty());
  kept_but_rank(*r6, *r5);
}

// Lenient (the server): a tolerance of a quantity no machine has yet is skipped, and no series at
// all is no machine ranked; not lenient (history rank): refused as rank_store refuses them.
TEST_P(Store, FleetRankerLenientLeavesOutWhatRankStoreRefuses) {
  store_->record(sample("M1", "2026-01-01", 1, 1));
  store_->record(sample("M1", "2026-02-01", 2, 2));
  RankRequest request;
  request.tolerances = parse_history_tolerances({"EXX=6", "NOPE=1"});
  EXPECT_THROW(rank_store(*store_, request), InputError);
  EXPECT_THROW(FleetRanker(request, false).rank(*store_), InputError);
  FleetRanker lenient(request, true);
  const auto r = lenient.rank(*store_);
  ASSERT_EQ(r->ranking.machines.size(), 1u);
  EXPECT_TRUE(r->notes.empty());
  request.tolerances = parse_history_tolerances({"NOPE=1"});
  EXPECT_TRUE(FleetRanker(request, true).rank(*store_)->ranking.machines.empty());
}

INSTANTIATE_TEST_SUITE_P(Backends, Store, ::testing::Values("sqlite", "postgresql"),
                         [](const auto& p) { return p.param == "sqlite" ? "SQLite" : "PostgreSQL"; });

// ---- SQLite specifics ---------------------------------------------------------------------------

TEST(SqliteStore, WalModeSchemaTableAndNewerSchemaRefused) {
  TempDir d;
  const auto path = (d.path / "h.db").string();
  open_history_store(path)->record(sample("M1", "2026-01-01", 1));
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  auto text = [&](const char* sql) {
    sqlite3_stmt* s = nullptr;
    EXPECT_EQ(sqlite3_prepare_v2(db, sql, -1, &s, nullptr), SQLITE_OK) << sqlite3_errmsg(db);
    std::string out;
    if (sqlite3_step(s) == SQLITE_ROW) out = reinterpret_cast<const char*>(sqlite3_column_text(s, 0));
    sqlite3_finalize(s);
    return out;
  };
  EXPECT_EQ(text("PRAGMA journal_mode"), "wal");
  EXPECT_EQ(text("SELECT group_concat(version) FROM schema_version"), "1,2,3,4,5,6");
  EXPECT_EQ(text("SELECT count(*) FROM sqlite_master WHERE type = 'index' AND name = 'parameters_fleet'"), "1");
  ASSERT_EQ(sqlite3_exec(db, "INSERT INTO schema_version VALUES (7, '2030-01-01T00:00:00Z', 'future')", nullptr,
                         nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(db);
  try {
    open_history_store("sqlite:" + path);
    ADD_FAILURE() << "a store of a newer schema was opened";
  } catch (const StoreError& e) {
    EXPECT_NE(std::string(e.what()).find("schema version 7, newer than this program's 6"), std::string::npos)
        << e.what();
  }
}

// A store of schema version 1 (before latest_values) is migrated when opened: the table is made
// and filled from the stored values, so that the fleet query answers as before.
TEST(SqliteStore, MigrationFromVersion1FillsLatestValues) {
  TempDir d;
  const auto path = (d.path / "v1.db").string();
  std::vector<LatestValue> before;
  {
    auto s = open_history_store(path);
    s->record(sample("M1", "2026-01-01", 1, 1));
    s->record(sample("M1", "2026-03-01", 3, 2));
    s->record(sample("M2", "2026-02-01", 2, 3));
    before = s->latest_parameter("EXX");
  }
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db,
                         "DROP TABLE latest_values; DROP TABLE latest_records; DROP TABLE audit; DROP TABLE sessions; "
                         "DROP TABLE users; DROP TABLE machine_intervals; DROP TABLE machine_revisions; DROP TABLE model_files; "
                         "ALTER TABLE records DROP COLUMN invocation; DELETE FROM schema_version WHERE version >= 2",
                         nullptr, nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(db);
  auto s = open_history_store(path);
  EXPECT_EQ(s->schema_version(), kHistorySchemaVersion);
  const auto after = s->latest_parameter("EXX");
  ASSERT_EQ(after.size(), 2u);
  EXPECT_EQ(after[0].sample.value, 3.0);
  EXPECT_EQ(after[0].sample.record_id, before[0].sample.record_id);
  EXPECT_EQ(after[1].sample.value, 2.0);
  EXPECT_EQ(s->latest_figure("VA")[0].sample.value, 13.0);
}

// A store of schema version 2 (before mtcal serve's accounts) opens, gains the users, sessions
// and audit tables (and machine_intervals), and its records read back unchanged.
TEST(SqliteStore, MigrationFromVersion2KeepsRecordsAndAddsAccounts) {
  TempDir d;
  const auto path = (d.path / "v2.db").string();
  std::vector<CalibrationRecord> before;
  {
    auto s = open_history_store(path);
    s->record(sample("M1", "2026-01-01", 1, 1));
    s->record(sample("M2", "2026-02-01", 2, 3));
    before = s->list();
  }
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db,
                         "DROP TABLE latest_records; DROP TABLE audit; DROP TABLE sessions; DROP TABLE users; "
                         "DROP TABLE machine_intervals; DROP TABLE machine_revisions; DROP TABLE model_files; ALTER TABLE "
                         "records DROP COLUMN invocation; DELETE FROM schema_version WHERE version >= 3",
                         nullptr, nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(db);
  auto s = open_history_store(path);
  EXPECT_EQ(s->schema_version(), kHistorySchemaVersion);
  EXPECT_EQ(s->list(), before);
  EXPECT_TRUE(s->users().empty());
  const auto latest = s->latest_calibrations();  // filled from the records by the migration
  ASSERT_EQ(latest.size(), 2u);
  EXPECT_EQ(latest[0].machine, "M1");
  EXPECT_EQ(latest[0].record_id, before[0].id);
  EXPECT_EQ(latest[0].count, 1);
  s->put_user({"ann", "admin", "$argon2id$x", ""});
  ASSERT_TRUE(s->find_user("ann"));
  EXPECT_EQ(s->find_user("ann")->role, "admin");
  // Intervals per machine: set (with an audit row naming the user), replaced, removed.
  EXPECT_TRUE(s->machine_intervals().empty());
  s->set_machine_interval("M1", 180, "ann");
  s->set_machine_interval("M1", 90, "ann");
  ASSERT_EQ(s->machine_intervals().size(), 1u);
  EXPECT_EQ(s->machine_intervals()[0].days, 90);
  EXPECT_EQ(s->machine_intervals()[0].set_by, "ann");
  EXPECT_EQ(s->audit("M1").size(), 2u);
  EXPECT_THROW(s->set_machine_interval("M1", -1, "ann"), InputError);
  EXPECT_THROW(s->set_machine_interval("", 10, "ann"), InputError);
  s->set_machine_interval("M1", 0, "ann");
  EXPECT_TRUE(s->machine_intervals().empty());
}

TEST(SqliteStore, UnopenableAndNotADatabase) {
  TempDir d;
  EXPECT_THROW(open_history_store((d.path / "no" / "such" / "dir.db").string()), StoreError);
  const auto junk = (d.path / "junk.db").string();
  std::ofstream(junk) << "this is not a database, just text that is long enough to have a header......\n";
  EXPECT_THROW(open_history_store(junk), StoreError);
  EXPECT_THROW(open_history_store(""), InputError);
}

TEST(PostgresStore, UnreachableServerIsAStoreErrorWithoutPassword) {
  try {
    open_history_store("postgresql://u:secret@127.0.0.1:1/db?connect_timeout=2");
    ADD_FAILURE() << "connected to nothing";
  } catch (const StoreError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.find("secret"), std::string::npos) << msg;
    EXPECT_NE(msg.find("cannot connect"), std::string::npos) << msg;
  }
}

// ---- JSON lines: bad input ---------------------------------------------------------------------

namespace {
std::string import_error(const std::string& text) {
  TempDir d;
  auto s = open_history_store((d.path / "h.db").string());
  std::istringstream in(text);
  try {
    import_jsonl(*s, in, "in.jsonl");
  } catch (const InputError& e) {
    EXPECT_TRUE(s->list().empty()) << "a failed import stored records";
    return e.what();
  }
  return "no error";
}
}  // namespace

TEST(HistoryJsonl, BadInputIsRefusedWithFileAndLine) {
  auto r = sample("M1", "2026-01-01", 1);
  TempDir d;
  auto s = open_history_store((d.path / "h.db").string());
  const auto id = s->record(r);
  const std::string good = record_to_json_line(*s->get(id));
  auto with = [&](const std::string& from, const std::string& to) {
    std::string t = good;
    const auto at = t.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return t.replace(at, from.size(), to);
  };
  const std::vector<std::pair<std::string, std::string>> cases{
      {good + "\n{not json\n", "in.jsonl:2"},
      {"[1,2]\n", "expected a JSON object, found array"},
      {R"({"id":"x"})", "expected the key 'type'"},
      {R"({"type":"recording"})", "expected \"record\", \"event\" or \"model_file\", found 'recording'"},
      {R"({"type":"model_file","sha256":"00","kind":"machine","content":"x"})", "expected the SHA-256 of its content"},
      {R"({"type":"model_file","sha256":"2d711642b726b04401627ca9fbac32f5c8530fb1903cc4db02258717921a4881","kind":"plan","content":"x"})",
       "expected the kind machine, parameters or measurements, found 'plan'"},
      {R"({"type":"model_file","sha256":"2d711642b726b04401627ca9fbac32f5c8530fb1903cc4db02258717921a4881","kind":"machine"})",
       "expected the key 'content'"},
      {with(R"("machine_name":"M1",)", ""), "expected the key 'machine_name'"},
      {with(R"("machine_name":"M1")", R"("machine_name":3)"), "field 'machine_name'"},
      {with(R"("command")", R"("extra":1,"command")"), "unexpected key 'extra'"},
      {with(R"("value":1.0)", R"("value":"1")"), "expected a number, found string"},
      {with(R"("measured_at":"2026-01-01")", R"("measured_at":"01.01.2026")"), "expected an ISO 8601 date"},
      {with(R"("identify")", R"("identifY")"), "the line was changed after it was exported"},
      {R"({"type":"event","id":"e","machine":"M","date":"2026-01-01","kind":"explosion","note":""})",
       "found 'explosion'"},
      {R"({"type":"event","id":"e","machine":"M","date":"2026-01-01","kind":"crash"})", "expected the key 'note'"},
  };
  for (const auto& [text, expected] : cases) {
    const std::string msg = import_error(text);
    EXPECT_NE(msg.find(expected), std::string::npos) << "input: " << text << "\nmessage: " << msg;
    EXPECT_NE(msg.find("in.jsonl"), std::string::npos) << msg;
  }
  // Blank lines and CRLF are fine.
  EXPECT_EQ(import_error("\n" + good + "\r\n\n"), "no error");
}

// ---- records from result JSON -----------------------------------------------------------------

TEST(HistoryRecordFromResult, Iso230_2FiguresAndIdentifyParameters) {
  const auto iso = record_from_result(
      "iso230-2", R"({"A": 0.0145, "B": 0.0044, "E": 0.0118, "M": 0.0077, "R": 0.0077, "unit": "mm", "runs": 5})",
      {{"machine", "VMC 800"}, {"serial", "42"}, {"date", "2026-04-01"}, {"axis", "X"}}, {{"x.csv", sha256_hex("x")}});
  EXPECT_EQ(iso.machine_name, "VMC 800");
  EXPECT_EQ(iso.machine_serial, "42");
  EXPECT_EQ(iso.measured_at, "2026-04-01");
  ASSERT_EQ(iso.figures.size(), 5u);
  EXPECT_EQ(iso.figures[0], (RecordedFigure{"A_X", 0.0145, "mm", std::nullopt}));
  EXPECT_EQ(iso.figures[2].name, "E_X");
  EXPECT_TRUE(iso.parameters.empty());
  const auto id = record_from_result(
      "identify",
      R"({"machine":"HU40T","parameters":{"EC0Y":{"value":2.1e-5,"u":9e-7,"unit":"rad"},"EX0C":{"value":0.0032,"u":0.00018,"unit":"mm"}}})",
      {}, {});
  EXPECT_EQ(id.machine_name, "HU40T");
  ASSERT_EQ(id.parameters.size(), 2u);
  EXPECT_EQ(id.parameters[1], (RecordedParameter{"EX0C", 0.0032, 0.00018, "mm"}));
  EXPECT_THROW(record_from_result("x", "[1]", {}, {}), InputError);
  EXPECT_THROW(record_from_result("x", "{", {}, {}), InputError);
}

// ---- the configuration file ----------------------------------------------------------------------

TEST(HistoryConfig, ReadsStoreAndRecordAndRefusesTheRest) {
  TempDir d;
  const auto path = (d.path / "config.yaml").string();
  EXPECT_FALSE(read_history_config((d.path / "none.yaml").string()));
  auto write = [&](const std::string& text) { std::ofstream(path) << text; };
  write("other: 1\nhistory:\n  store: postgresql://mtcal@db/shop\n  record: always\n");
  auto c = read_history_config(path);
  ASSERT_TRUE(c);
  EXPECT_EQ(c->store, "postgresql://mtcal@db/shop");
  EXPECT_TRUE(c->always);
  write("history:\n  store: h.db\n");
  EXPECT_FALSE(read_history_config(path)->always);
  const std::vector<std::pair<std::string, std::string>> bad{
      {"history:\n  store: h.db\n  record: sometimes\n", "config.yaml:3: field 'history.record'"},
      {"history:\n  stor: h.db\n", "unknown key 'stor'"},
      {"history:\n  store: [a, b]\n", "expected a single value"},
      {"history: h.db\n", "expected a mapping"},
      {"- a\n- b\n", "expected a mapping of sections"},
      {"history: {store: \"\n", "expected YAML"},
  };
  for (const auto& [text, expected] : bad) {
    write(text);
    try {
      read_history_config(path);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
}
