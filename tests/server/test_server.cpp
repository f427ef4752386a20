// mtcal serve's security and fault tests: every route of the router refused without a session and
// with too small a role, CSRF, session fixation, logout, escaping, SQL metacharacters, path
// traversal, oversized and malformed uploads, garbage requests, login throttling; on SQLite and
// on a real PostgreSQL server (tests/testing/pg_server).
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

// Before httplib.h (through Eigen): its system headers define macros that break Eigen's declarations.
#include "mtcal/io/history/queries.hpp"
#include "mtcal/io/json/history_json.hpp"
#include "mtcal/evaluation/iso230_2.hpp"
#include "mtcal/io/instruments/iso230_files.hpp"
#include "mtcal/report/evaluation.hpp"
#include "mtcal/report/recorded.hpp"

#include <httplib.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <regex>
#include <sstream>
#include <thread>

#include <gtest/gtest.h>
#include <libpq-fe.h>

#include <nlohmann/json.hpp>

#include "mtcal/io/history/store.hpp"
#include "mtcal/server/server.hpp"
#include "pg_server.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
using namespace mtcal;
using namespace mtcal::server;

namespace {

mtcal::testing::PgServer& pg() { return mtcal::testing::shared_pg_server(); }

using mtcal::testing::TempDir;

int g_db = 0;
const std::string kPassword = "correct horse battery";
const std::string kXss = "<script>alert('x')</script>";
const std::string kSql = "M'); DROP TABLE records; --";

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string data_file() {
  const char* dir = std::getenv("MTCAL_SHARED_DATA");
  return std::string(dir ? dir : "../shared/data") + "/iso230-2/b02_x_axis.dat";
}

CalibrationRecord sample(const std::string& machine, const std::string& date, double value) {
  CalibrationRecord r;
  r.machine_name = machine;
  r.command = "iso230-2";
  r.measured_at = date;
  r.metadata = {{"operator", kXss}};
  r.figures = {{"A_X", value, "um", std::nullopt}, {"E_X", value / 2, "um", std::nullopt}};
  r.result_json = "{\"n\":" + std::to_string(value) + "}";
  return r;
}

// Percent-encoding of a query value (every byte but letters and digits).
std::string encode(const std::string& s) {
  std::string out;
  for (const unsigned char c : s) {
    char buf[4];
    if (std::isalnum(c)) {
      out += static_cast<char>(c);
    } else {
      std::snprintf(buf, sizeof buf, "%%%02X", c);
      out += buf;
    }
  }
  return out;
}

// A logged-in browser: its session cookie and the session's CSRF token.
struct Login {
  std::string cookie, csrf;
  httplib::Headers headers() const { return {{"Cookie", "mtcal_session=" + cookie}}; }
};

class Serve : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    if (GetParam() == "postgresql") {
      if (!pg().available()) GTEST_SKIP() << "PostgreSQL tests skipped: " << pg().why();
      conn_ = pg().create_database("serve" + std::to_string(::getpid()) + "_" + std::to_string(g_db++));
    } else {
      conn_ = "sqlite:" + (dir_.path / ("s" + std::to_string(g_db++) + ".db")).string();
    }
    store_ = open_history_store(conn_);
    for (const auto& [name, role] : std::vector<std::pair<std::string, std::string>>{
             {"vera", "viewer"}, {"eng", "engineer"}, {"ada", "admin"}})
      add_user(*store_, name, role, kPassword, KdfCost::Minimum);
    ids_.push_back(store_->record_by(sample("M1", "2026-01-10", 4.0), "eng"));
    ids_.push_back(store_->record_by(sample("M1", "2026-06-10", 5.0), "eng"));
    ids_.push_back(store_->record_by(sample(kXss, "2026-03-01", 6.0), "eng"));
    store_->add_event_by({"", "M1", "2026-02-01", EventKind::Repair, kXss}, "eng");
    start(65536);
  }
  void TearDown() override { stop(); }

  void start(std::size_t max_upload) {
    ServerOptions o;
    o.store = conn_;
    o.port = 0;
    o.max_upload = max_upload;
    o.threads = 4;
    o.kdf_cost = KdfCost::Minimum;
    o.tolerances = tolerances_;
    server_ = std::make_unique<Server>(o);
    port_ = server_->bind();
    thread_ = std::thread([this] { server_->run(); });
  }
  void stop() {
    if (server_) server_->stop();
    if (thread_.joinable()) thread_.join();
    server_.reset();
  }

  httplib::Client client() const {
    // Every wait bounded: a server that does not answer fails the test, it does not hang it.
    httplib::Client c("127.0.0.1", port_);
    c.set_connection_timeout(5, 0);
    c.set_read_timeout(20, 0);
    c.set_write_timeout(20, 0);
    return c;
  }

  static std::string set_cookie(const httplib::Result& r, const std::string& name) {
    for (const auto& [k, v] : r->headers)
      if (k == "Set-Cookie" && v.rfind(name + "=", 0) == 0) return v.substr(name.size() + 1, v.find(';') - name.size() - 1);
    return {};
  }
  static std::string csrf_in(const std::string& html) {
    std::smatch m;
    if (std::regex_search(html, m, std::regex("name=\"csrf\" value=\"([0-9a-f]{64})\""))) return m[1];
    return {};
  }

  // Logs in (GET /login for the form's token, POST /login); fixed: a session cookie the client
  // already holds (session fixation). Returns an empty cookie when the login was refused.
  Login login(const std::string& user, const std::string& password = kPassword, const std::string& fixed = {},
              int* status = nullptr) {
    auto c = client();
    const auto page = c.Get("/login");
    EXPECT_TRUE(page);
    const std::string login_cookie = set_cookie(page, "mtcal_login");
    std::string cookies = "mtcal_login=" + login_cookie;
    if (!fixed.empty()) cookies += "; mtcal_session=" + fixed;
    const auto r = c.Post("/login", {{"Cookie", cookies}},
                          httplib::Params{{"csrf", csrf_in(page->body)}, {"user", user}, {"password", password}});
    EXPECT_TRUE(r);
    if (status) *status = r->status;
    Login l;
    if (r->status != 303) return l;
    l.cookie = set_cookie(r, "mtcal_session");
    const auto fleet = c.Get("/fleet", l.headers());
    l.csrf = csrf_in(fleet->body);
    return l;
  }

  // /api/fleet of a server started now on the store (the session's cookie works there: sessions
  // are kept in the store).
  nlohmann::json fresh_fleet(const Login& l) const {
    ServerOptions o;
    o.store = conn_;
    o.port = 0;
    o.threads = 1;
    o.kdf_cost = KdfCost::Minimum;
    o.tolerances = tolerances_;
    Server fresh(o);
    const int port = fresh.bind();
    std::thread run([&] { fresh.run(); });
    httplib::Client fc("127.0.0.1", port);
    fc.set_connection_timeout(5, 0);
    fc.set_read_timeout(20, 0);
    const auto r = fc.Get("/api/fleet", l.headers());
    fresh.stop();
    run.join();
    return r ? nlohmann::json::parse(r->body) : nlohmann::json();
  }
  // A fleet without what counts to the server's clock (as_of and the ages).
  static nlohmann::json without_ages(nlohmann::json f) {
    f.erase("as_of");
    for (auto& m : f["machines"])
      for (auto& x : m["calibrations"]) x.erase("age_days");
    return f;
  }

  std::size_t record_count() { return store_->list().size(); }
  std::size_t event_count() { return store_->events().size(); }

  TempDir dir_;
  std::string conn_;
  std::unique_ptr<HistoryStore> store_;
  std::unique_ptr<Server> server_;
  std::thread thread_;
  int port_ = 0;
  std::vector<std::string> ids_;
  std::vector<std::string> tolerances_;
};

// A request to a route as the tests send it: its example query, form fields, the CSRF token.
httplib::Result send(httplib::Client& c, const Route& r, const httplib::Headers& h, const std::string& csrf,
                     const std::vector<std::string>& ids) {
  std::string query = r.example;
  query = std::regex_replace(query, std::regex("id=0"), "id=" + ids[0]);
  query = std::regex_replace(query, std::regex("a=0&b=1"), "a=" + ids[0] + "&b=" + ids[1]);
  const std::string path = r.path + (query.empty() ? "" : "?" + query);
  if (r.method == "GET") return c.Get(path, h);
  httplib::Params p{{"machine", "M1"}, {"date", "2026-07-01"}, {"kind", "crash"}, {"note", "n"}};
  if (!csrf.empty()) p.emplace("csrf", csrf);
  return c.Post(path, h, p);
}

TEST_P(Serve, OnlyLoginAndStaticAssetsArePublic) {
  ASSERT_FALSE(server_->routes().empty());
  for (const auto& r : server_->routes()) {
    if (r.is_public) {
      EXPECT_TRUE(r.path == "/login" || r.path.rfind("/static/", 0) == 0) << r.path;
    }
  }
}

TEST_P(Serve, EveryRouteRefusedWithoutASession) {
  auto c = client();
  c.set_follow_location(false);
  const std::string forged = std::string(64, 'a');
  for (const auto& r : server_->routes()) {
    if (r.is_public) continue;
    for (const httplib::Headers& h : {httplib::Headers{}, httplib::Headers{{"Cookie", "mtcal_session=" + forged}}}) {
      const auto res = send(c, r, h, "", ids_);
      ASSERT_TRUE(res) << r.path;
      if (r.api || r.method == "POST") {
        EXPECT_EQ(res->status, 401) << r.method << " " << r.path;
      } else {
        EXPECT_EQ(res->status, 303) << r.path;
        EXPECT_EQ(res->get_header_value("Location"), "/login") << r.path;
      }
      EXPECT_EQ(res->body.find("M1"), std::string::npos) << r.path << " leaks data without a session";
    }
  }
  EXPECT_EQ(record_count(), 3u);
  EXPECT_EQ(event_count(), 1u);
}

TEST_P(Serve, EveryRouteRefusedToATooSmallRoleAndOpenToItsRole) {
  const Login viewer = login("vera"), engineer = login("eng"), admin = login("ada");
  ASSERT_FALSE(viewer.cookie.empty());
  auto c = client();
  std::size_t checked = 0;
  for (const auto& r : server_->routes()) {
    if (r.is_public || r.path == "/logout") continue;
    for (const auto& [who, role] : {std::pair{&viewer, Role::Viewer}, {&engineer, Role::Engineer}, {&admin, Role::Admin}}) {
      const auto res = send(c, r, who->headers(), who->csrf, ids_);
      ASSERT_TRUE(res) << r.path;
      if (static_cast<int>(role) < static_cast<int>(r.min_role)) {
        EXPECT_EQ(res->status, 403) << r.method << " " << r.path << " as " << to_string(role);
        ++checked;
      } else {
        EXPECT_NE(res->status, 403) << r.method << " " << r.path << " as " << to_string(role) << ": " << res->body;
        EXPECT_NE(res->status, 401) << r.method << " " << r.path << " as " << to_string(role);
      }
    }
  }
  EXPECT_GE(checked, 8u);  // upload, events, users ... refused to viewers, users to engineers
}

TEST_P(Serve, PostsWithoutTheCsrfTokenAreRefusedAndWriteNothing) {
  const Login admin = login("ada");
  auto c = client();
  for (const auto& r : server_->routes()) {
    if (r.method != "POST" || r.is_public) continue;
    for (const std::string& token : {std::string(), std::string(64, '0')}) {
      const auto res = send(c, r, admin.headers(), token, ids_);
      ASSERT_TRUE(res);
      EXPECT_EQ(res->status, 403) << r.path << " with token '" << token << "'";
    }
  }
  EXPECT_EQ(record_count(), 3u);
  EXPECT_EQ(event_count(), 1u);
  // The login form too: without its token (double-submit cookie) no session is made.
  const auto res = c.Post("/login", httplib::Params{{"user", "ada"}, {"password", kPassword}});
  EXPECT_EQ(res->status, 403);
  EXPECT_EQ(set_cookie(res, "mtcal_session"), "");
  // With the token an event is added: the refusals above were the token's doing.
  const auto ok = c.Post("/events", admin.headers(),
                         httplib::Params{{"csrf", admin.csrf}, {"machine", "M1"}, {"date", "2026-07-01"},
                                         {"kind", "crash"}, {"note", "n"}});
  EXPECT_EQ(ok->status, 303);
  EXPECT_EQ(event_count(), 2u);
}

// The pages are never stored (no-store); Plotly (4.8 MB, no user data) is cached a day, with one
// Cache-Control header: a second "no-store" beside it made browsers fetch and compile it per page.
TEST_P(Serve, PlotlyIsCachedAndPagesAreNot) {
  auto c = client();
  const auto js = c.Get("/static/plotly.min.js");
  ASSERT_TRUE(js);
  EXPECT_EQ(js->status, 200);
  EXPECT_EQ(js->headers.count("Cache-Control"), 1u);
  EXPECT_EQ(js->get_header_value("Cache-Control"), "public, max-age=86400");
  const auto page = c.Get("/login");
  ASSERT_TRUE(page);
  EXPECT_EQ(page->headers.count("Cache-Control"), 1u);
  EXPECT_EQ(page->get_header_value("Cache-Control"), "no-store");
}

TEST_P(Serve, SessionFixationLogoutAndCookieFlags) {
  const std::string fixed(64, 'b');
  const Login l = login("eng", kPassword, fixed);
  ASSERT_EQ(l.cookie.size(), 64u);
  EXPECT_NE(l.cookie, fixed);
  auto c = client();
  EXPECT_EQ(c.Get("/fleet", {{"Cookie", "mtcal_session=" + fixed}})->status, 303);
  EXPECT_EQ(c.Get("/fleet", l.headers())->status, 200);
  // A second login from the same browser gets a new id, and the old one ends.
  const Login again = login("eng", kPassword, l.cookie);
  EXPECT_NE(again.cookie, l.cookie);
  EXPECT_EQ(c.Get("/api/fleet", l.headers())->status, 401);
  // The cookie's flags.
  const auto page = c.Get("/login");
  std::string attrs;
  for (const auto& [k, v] : page->headers)
    if (k == "Set-Cookie") attrs = v;
  EXPECT_NE(attrs.find("HttpOnly"), std::string::npos);
  EXPECT_NE(attrs.find("SameSite=Strict"), std::string::npos);
  // Logout ends the session in the store: the cookie is worth nothing afterwards.
  const auto out = c.Post("/logout", again.headers(), httplib::Params{{"csrf", again.csrf}});
  EXPECT_EQ(out->status, 303);
  EXPECT_EQ(c.Get("/fleet", again.headers())->status, 303);
  EXPECT_EQ(c.Get("/api/fleet", again.headers())->status, 401);
}

TEST_P(Serve, ScriptInNamesAndNotesIsShownEscapedEverywhere) {
  const Login l = login("eng");
  auto c = client();
  const std::vector<std::string> pages = {"/fleet",
                                          "/machine?name=" + encode(kXss),
                                          "/machine?name=M1",
                                          "/record?id=" + ids_[2],
                                          "/diff?a=" + ids_[0] + "&b=" + ids_[2],
                                          "/upload?machine=" + encode(kXss)};
  for (const auto& p : pages) {
    const auto r = c.Get(p, l.headers());
    ASSERT_EQ(r->status, 200) << p << r->body;
    EXPECT_EQ(r->body.find("<script>alert"), std::string::npos) << p;
    EXPECT_NE(r->body.find("&lt;script&gt;alert("), std::string::npos) << p;
  }
  // The JSON API carries the text as it is (JSON, not HTML; served as application/json).
  const auto j = c.Get("/api/machine?name=M1", l.headers());
  EXPECT_EQ(j->get_header_value("Content-Type"), "application/json");
  EXPECT_NE(j->body.find(kXss), std::string::npos);
  // A 404 page repeats no path unescaped.
  const auto nf = c.Get("/%3Cscript%3Ealert(1)%3C/script%3E", l.headers());
  EXPECT_EQ(nf->status, 404);
  EXPECT_EQ(nf->body.find("<script>alert"), std::string::npos);
}

TEST_P(Serve, SqlMetacharactersAreDataNotSql) {
  const Login l = login("eng");
  auto c = client();
  const auto r = c.Post("/api/events", {{"Cookie", "mtcal_session=" + l.cookie}, {"X-CSRF-Token", l.csrf}},
                        httplib::Params{{"machine", kSql}, {"date", "2026-07-01"}, {"kind", "crash"}, {"note", "' OR 1=1 --"}});
  ASSERT_EQ(r->status, 200) << r->body;
  const auto evs = store_->events(kSql);
  ASSERT_EQ(evs.size(), 1u);
  EXPECT_EQ(evs[0].note, "' OR 1=1 --");
  EXPECT_EQ(record_count(), 3u);  // the records table is still there, whole
  // A user name of SQL is no way in.
  int status = 0;
  EXPECT_TRUE(login("' OR '1'='1", "x' OR 'x'='x", {}, &status).cookie.empty());
  EXPECT_EQ(status, 401);
  EXPECT_EQ(c.Get("/api/machine?name=" + encode("M1' OR '1'='1"), l.headers())->status, 404);
}

// "Write compensation" of a recorded result (schema 5): the record's machine file from the
// store and its parameters applied by name, units converted (20 um/m is the 2e-5 mm/mm of a
// parameter file in internal units): the same answer as the machine file uploaded with that
// parameter file. A record whose machine file the store lacks: 404 naming its inputs' SHA-256;
// ids of SQL or a path: 404, nothing else.
TEST_P(Serve, CompensationOfARecordUsesItsStoredModelFiles) {
  const std::string machine =
      "mtcal_machine: 1\nname: T1\ntopology: wXYfZt\nunits: {length: mm, angle: deg}\naxes:\n  X: {travel: [-100, 100]}\n"
      "  Y: {travel: [-100, 100]}\n  Z: {travel: [-100, 0]}\ntool: {length: 100, spindle_point: [0, 0, 0]}\n"
      "workpiece: {origin: [0, 0, -50]}\nerrors:\n  EXX: {unit: um, argument_unit: m, polynomial: [0, 8.0]}\n";
  const std::string params =
      "mtcal_parameters: 1\nunits: {length: mm, angle: rad}\nerrors:\n  EXX: {unit: mm, argument_unit: mm, polynomial: [0, 2e-5]}\n  EC0Y: 1e-5 rad\n";
  CalibrationRecord r = sample("T1", "2026-05-01", 1.0);
  r.command = "identify";
  r.inputs = {{"t1.yaml", sha256_hex(machine)}, {"plan.csv", sha256_hex("plan")}};
  r.parameters = {{"EXX.1", 20, 0.5, "um/m"}, {"EC0Y", 10, std::nullopt, "urad"}};
  const std::string held = store_->record_all({r}, {}, nullptr, {{sha256_hex(machine), "machine", machine}})[0];
  CalibrationRecord bare = sample("T2", "2026-05-01", 1.0);
  bare.inputs = {{"run.dat", sha256_hex("run")}};
  const std::string lacking = store_->record(bare);

  const Login l = login("eng");
  auto c = client();
  const httplib::Headers h{{"Cookie", "mtcal_session=" + l.cookie}, {"X-CSRF-Token", l.csrf}};
  const auto from_record = c.Post("/api/compensation", h,
                                  httplib::MultipartFormDataItems{{"record", held, "", ""}, {"format", "linuxcnc", "", ""},
                                                                  {"summary", "1", "", ""}});
  ASSERT_EQ(from_record->status, 200) << from_record->body;
  const auto from_files = c.Post("/api/compensation", h,
                                 httplib::MultipartFormDataItems{{"machine_file", machine, "t1.yaml", "application/yaml"},
                                                                 {"params", params, "p.yaml", "application/yaml"},
                                                                 {"format", "linuxcnc", "", ""},
                                                                 {"summary", "1", "", ""}});
  ASSERT_EQ(from_files->status, 200) << from_files->body;
  EXPECT_EQ(from_record->body, from_files->body);
  const auto without = c.Post("/api/compensation", h,
                              httplib::MultipartFormDataItems{{"machine_file", machine, "t1.yaml", "application/yaml"},
                                                              {"format", "linuxcnc", "", ""},
                                                              {"summary", "1", "", ""}});
  EXPECT_NE(without->body, from_record->body);  // the parameters changed the answer
  const auto zip = c.Post("/api/compensation", h,
                          httplib::MultipartFormDataItems{{"record", held, "", ""}, {"format", "linuxcnc", "", ""}});
  ASSERT_EQ(zip->status, 200);
  EXPECT_EQ(zip->body.substr(0, 4), std::string("PK\x03\x04", 4));
  // No machine file in the store: 404 naming the input's SHA-256.
  const auto missing = c.Post("/api/compensation", h,
                              httplib::MultipartFormDataItems{{"record", lacking, "", ""}, {"format", "linuxcnc", "", ""}});
  EXPECT_EQ(missing->status, 404);
  EXPECT_NE(missing->body.find("has no machine file in the store"), std::string::npos) << missing->body;
  EXPECT_NE(missing->body.find(sha256_hex("run")), std::string::npos) << missing->body;
  for (const std::string& id : {kSql, std::string("../../etc/passwd"), std::string("' OR 1=1 --")}) {
    const auto bad = c.Post("/api/compensation", h,
                            httplib::MultipartFormDataItems{{"record", id, "", ""}, {"format", "linuxcnc", "", ""}});
    EXPECT_EQ(bad->status, 404) << id << ": " << bad->body;
  }
  // The record pages: the form where the machine file is held, the reason where not.
  const auto page = c.Get("/record?id=" + held, l.headers());
  EXPECT_NE(page->body.find("id=\"rec-comp-write\""), std::string::npos);
  EXPECT_NE(page->body.find("id=\"report-why\""), std::string::npos);
  EXPECT_NE(c.Get("/record?id=" + lacking, l.headers())->body.find("id=\"rec-comp-why\""), std::string::npos);
  EXPECT_NE(c.Get("/machine?name=T1", l.headers())->body.find("id=\"rec-comp-record\""), std::string::npos);
  EXPECT_EQ(record_count(), 5u);
}

// A record's own report (/record/report): an ISO 230-2 record whose runs the store holds is shown
// as the command's path makes it (positioning_report of the runs read as `mtcal iso230-2` reads
// them), under the reports' CSP, the metadata escaped; a record whose runs the store lacks, or
// that does not say how its command ran, gets 404 naming its file's SHA-256, and its record page
// says so. (That the page equals the command's --report file: tests/server/test_serve_cli.sh.)
TEST_P(Serve, RecordReportIsMadeFromTheStoredMeasurements) {
  std::string runs = "target,run,direction,deviation\n";
  for (int t = 0; t < 3; ++t)
    for (int run = 1; run <= 2; ++run)
      for (const char* dir : {"up", "down"})
        runs += std::to_string(100 * t) + "," + std::to_string(run) + "," + dir + "," +
                std::to_string(0.001 * (t + run) + (dir[0] == 'u' ? 0.002 : 0)) + "\n";
  ReportMetadata meta;
  meta.set("machine", kXss);
  meta.set("axis", "X");
  const ToleranceVerdict verdict{{{"A", 7.5, 10, true}}};
  const std::string command = "mtcal iso230-2 x.csv --tolerance A=10 --record";
  CalibrationRecord r = sample("R1", "2026-05-01", 1.0);
  r.inputs = {{"x.csv", sha256_hex(runs)}};
  r.invocation = json_text(positioning_invocation(command, "x.csv", "auto", "mm", "", 0, verdict, meta));
  const std::string held = store_->record_all({r}, {}, nullptr, {{sha256_hex(runs), "measurements", runs}})[0];
  CalibrationRecord gone = r;
  gone.measured_at = "2026-06-01";
  gone.inputs = {{"x.csv", sha256_hex("other runs")}};
  const std::string lacking = store_->record(gone);

  const Login l = login("vera");
  auto c = client();
  const auto res = c.Get("/record/report?id=" + held, l.headers());
  ASSERT_EQ(res->status, 200) << res->body;
  EXPECT_EQ(res->get_header_value("Content-Security-Policy"),
            "default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'; img-src data: blob:");
  EXPECT_EQ(res->body.find(kXss), std::string::npos);
  const auto at = res->body.find("<td class=\"date\">");
  ASSERT_NE(at, std::string::npos);
  const std::string date = res->body.substr(at + 17, res->body.find("</td>", at) - at - 17);
  const PositioningRuns read = parse_positioning_csv(runs, "x.csv", "mm");
  EXPECT_EQ(res->body, positioning_report(command, read, sha256_hex(runs), evaluate_positioning(read), verdict, meta).html(date));
  EXPECT_NE(res->body.find("PASS"), std::string::npos);  // the verdict kept with the record
  EXPECT_NE(c.Get("/record?id=" + held, l.headers())->body.find("id=\"report-link\""), std::string::npos);
  // The runs not in the store; a record that does not say how it ran (the fixture's).
  for (const auto& [id, sha] : {std::pair{lacking, sha256_hex("other runs")}, std::pair{ids_[0], std::string()}}) {
    const auto none = c.Get("/record/report?id=" + id, l.headers());
    EXPECT_EQ(none->status, 404) << id;
    const auto page = c.Get("/record?id=" + id, l.headers())->body;
    EXPECT_NE(page.find("id=\"report-why\""), std::string::npos) << id;
    if (!sha.empty()) {
      EXPECT_NE(none->body.find(sha), std::string::npos) << none->body;
      EXPECT_NE(page.find(sha), std::string::npos);
    } else {
      EXPECT_NE(page.find("does not say how its command ran"), std::string::npos) << page;
    }
  }
  // Why other commands' records have no report: a regress record of an mtcal that kept no
  // invocation for it, a command whose report is not made from the store, one without --report.
  for (const auto& [other, why] : {std::pair<std::string, std::string>{"regress", "does not say how its command ran"},
                                     {"volumetric", "the report of mtcal volumetric is not made from the store yet"},
                                     {"fit-motion", "mtcal fit-motion has no --report"}}) {
    CalibrationRecord o = sample("R2", "2026-07-01", 2.0);
    o.command = other;
    const auto none = c.Get("/record/report?id=" + store_->record(o), l.headers());
    EXPECT_EQ(none->status, 404) << other;
    EXPECT_NE(none->body.find(why), std::string::npos) << none->body;
  }
}

// "Write compensation" from uploaded files reads a parameter file in either form --params reads:
// an Etalon exchange file ([C0Y] VALUE in rad, TF5280's format) gives the same compensation as
// mtcal's YAML with the same value, and a different one from the machine file alone (the ISG
// target: its parameters include the squareness EC0Y).
TEST_P(Serve, CompensationOfUploadedFilesReadsEtalonParameterFiles) {
  const std::string machine =
      "mtcal_machine: 1\nname: T1\ntopology: wXYfZt\nunits: {length: mm, angle: deg}\naxes:\n  X: {travel: [-100, 100]}\n"
      "  Y: {travel: [-100, 100]}\n  Z: {travel: [-100, 0]}\ntool: {length: 100, spindle_point: [0, 0, 0]}\n"
      "workpiece: {origin: [0, 0, -50]}\n";
  const std::string yaml = "mtcal_parameters: 1\nunits: {length: mm, angle: rad}\nerrors:\n  EC0Y: 2e-5 rad\n";
  const std::string etalon = "// exported\n[C0Y]\nVALUE = 2e-5\n";
  const Login l = login("eng");
  auto c = client();
  const httplib::Headers h{{"Cookie", "mtcal_session=" + l.cookie}, {"X-CSRF-Token", l.csrf}};
  auto post = [&](const std::string* params, const std::string& name) {
    httplib::MultipartFormDataItems items{{"machine_file", machine, "t1.yaml", "application/yaml"},
                                          {"format", "isg", "", ""},
                                          {"summary", "1", "", ""}};
    if (params) items.push_back({"params", *params, name, "text/plain"});
    return c.Post("/api/compensation", h, items);
  };
  const auto from_etalon = post(&etalon, "volcomp.etalon");
  ASSERT_EQ(from_etalon->status, 200) << from_etalon->body;
  const auto from_yaml = post(&yaml, "p.yaml");
  ASSERT_EQ(from_yaml->status, 200) << from_yaml->body;
  EXPECT_EQ(from_etalon->body, from_yaml->body);
  EXPECT_NE(post(nullptr, "")->body, from_etalon->body);  // the parameter changed the answer
  // A block that names no error of the machine is refused (422), as --params refuses it.
  const std::string unknown = "[EXU]\nVALUE = 1\n";
  EXPECT_EQ(post(&unknown, "bad.etalon")->status, 422);
}

TEST_P(Serve, PathTraversalInFileNamesAndParameters) {
  const Login l = login("eng");
  auto c = client();
  const std::string content = read_file(data_file());
  ASSERT_FALSE(content.empty()) << data_file();
  const std::string victim = (dir_.path / "evil.dat").string();
  httplib::MultipartFormDataItems items{{"csrf", l.csrf, "", ""},
                                        {"machine", "M9", "", ""},
                                        {"confirm", "1", "", ""},
                                        {"file", content, "../../../../" + victim.substr(1), "text/plain"}};
  const auto r = c.Post("/api/upload", {{"Cookie", "mtcal_session=" + l.cookie}, {"X-CSRF-Token", l.csrf}}, items);
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_FALSE(fs::exists(victim));
  RecordFilter f;
  f.machine = "M9";
  const auto recs = store_->list(f);
  ASSERT_EQ(recs.size(), 1u);
  EXPECT_EQ(recs[0].inputs.at(0).path, "evil.dat");  // the name only, never a path
  for (const std::string p : {"/static/../../../etc/passwd", "/static/%2e%2e/%2e%2e/etc/passwd",
                              "/record?id=../../../etc/passwd", "/machine?name=..%2F..%2Fetc%2Fpasswd",
                              "/api/diff?a=../x&b=/etc/passwd"}) {
    const auto res = c.Get(p, l.headers());
    ASSERT_TRUE(res) << p;
    EXPECT_GE(res->status, 400) << p;
    EXPECT_EQ(res->body.find("root:"), std::string::npos) << p;
  }
}

TEST_P(Serve, OversizedAndMalformedUploadsRecordNothing) {
  const Login l = login("eng");
  auto c = client();
  const httplib::Headers h{{"Cookie", "mtcal_session=" + l.cookie}, {"X-CSRF-Token", l.csrf}};
  auto upload = [&](const std::string& content, const std::string& name) {
    httplib::MultipartFormDataItems items{{"machine", "M7", "", ""}, {"confirm", "1", "", ""},
                                          {"file", content, name, "text/plain"}};
    return c.Post("/api/upload", h, items);
  };
  const std::size_t before = record_count();
  EXPECT_EQ(upload(std::string(100'000, 'x'), "big.dat")->status, 413);     // over max_upload (64 KiB here)
  EXPECT_EQ(upload("TGT_DATA[1]=abc\nnot a line\n", "bad.dat")->status, 422);  // the reader's error
  EXPECT_EQ(upload("", "empty.dat")->status, 400);
  EXPECT_EQ(upload(read_file(data_file()), "x.exe")->status, 415);
  EXPECT_EQ(upload(std::string("\x89PNG\r\n\x1a\n\0\0", 10), "img.csv")->status, 422);
  const auto bad = upload("TGT_DATA[1]=abc\n", "bad.dat");
  EXPECT_NE(bad->body.find("bad.dat"), std::string::npos) << bad->body;  // names the file as the user knows it
  EXPECT_EQ(bad->body.find("/tmp/"), std::string::npos) << bad->body;
  EXPECT_EQ(record_count(), before);
  // Missing fields, a bad date, an unknown event kind: 400 with one line, nothing written.
  EXPECT_EQ(c.Post("/api/events", h, httplib::Params{{"machine", "M1"}, {"date", "yesterday"}, {"kind", "crash"}})->status, 400);
  EXPECT_EQ(c.Post("/api/events", h, httplib::Params{{"machine", "M1"}, {"date", "2026-01-01"}, {"kind", "fire"}})->status, 400);
  EXPECT_EQ(c.Post("/api/events", h, httplib::Params{{"date", "2026-01-01"}, {"kind", "crash"}})->status, 400);
  EXPECT_EQ(event_count(), 1u);
  // The server still serves.
  EXPECT_EQ(c.Get("/api/fleet", h)->status, 200);
}

TEST_P(Serve, UploadedFileIsRecordedWithItsAuthorAfterConfirmation) {
  const Login l = login("eng");
  auto c = client();
  c.set_follow_location(false);
  const std::string content = read_file(data_file());
  httplib::MultipartFormDataItems items{{"csrf", l.csrf, "", ""},
                                        {"machine", "B02", "", ""},
                                        {"date", "2022-10-20", "", ""},
                                        {"file", content, "b02_x_axis.dat", "text/plain"}};
  const auto preview = c.Post("/upload", l.headers(), items);
  ASSERT_EQ(preview->status, 200) << preview->body;
  EXPECT_EQ(record_count(), 3u);  // nothing before the confirmation
  std::smatch m;
  ASSERT_TRUE(std::regex_search(preview->body, m, std::regex("name=\"token\" value=\"([0-9a-f]{64})\"")));
  const std::string token = m[1];
  // Another session cannot confirm it.
  const Login other = login("ada");
  EXPECT_EQ(c.Post("/upload/confirm", other.headers(), httplib::Params{{"csrf", other.csrf}, {"token", token}})->status,
            404);
  const auto ok = c.Post("/upload/confirm", l.headers(), httplib::Params{{"csrf", l.csrf}, {"token", token}});
  ASSERT_EQ(ok->status, 303);
  EXPECT_EQ(ok->get_header_value("Location"), "/machine?name=B02");
  // Twice is once.
  EXPECT_EQ(c.Post("/upload/confirm", l.headers(), httplib::Params{{"csrf", l.csrf}, {"token", token}})->status, 404);
  RecordFilter f;
  f.machine = "B02";
  const auto recs = store_->list(f);
  ASSERT_EQ(recs.size(), 1u);
  EXPECT_EQ(recs[0].command, "iso230-2");
  EXPECT_EQ(recs[0].measured_at, "2022-10-20");
  const auto a = store_->audit(recs[0].id);
  ASSERT_EQ(a.size(), 1u);
  EXPECT_EQ(a[0].user, "eng");
  // The fleet shows the machine.
  const auto fleet = c.Get("/api/fleet", l.headers());
  EXPECT_NE(fleet->body.find("\"B02\""), std::string::npos);
}

TEST_P(Serve, LoginThrottlingAndGarbageRequests) {
  int status = 0;
  for (int i = 0; i < 5; ++i) {
    EXPECT_TRUE(login("vera", "wrong password!", {}, &status).cookie.empty());
    EXPECT_EQ(status, 401);
  }
  // The sixth try is refused even with the right password.
  EXPECT_TRUE(login("vera", kPassword, {}, &status).cookie.empty());
  EXPECT_EQ(status, 429);
  // Garbage on the socket: a 4xx, and the server goes on serving.
  for (const std::string& garbage : {std::string("GARBAGE\r\n\r\n"), std::string("GET /fleet HTTP/9.9\r\n\r\n"),
                                    std::string("\x01\x02\x03\xff\r\n\r\n", 8),
                                    "GET /" + std::string(20000, 'a') + " HTTP/1.1\r\n\r\n"}) {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<uint16_t>(port_));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    const timeval limit{10, 0};  // no answer within 10 s fails the test instead of hanging it
    ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &limit, sizeof limit);
    ::setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &limit, sizeof limit);
    ASSERT_EQ(::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
    ASSERT_EQ(::send(fd, garbage.data(), garbage.size(), 0), static_cast<ssize_t>(garbage.size()));
    char buf[512] = {};
    const ssize_t n = ::recv(fd, buf, sizeof buf - 1, 0);
    ::close(fd);
    ASSERT_GT(n, 12) << "no answer to garbage";
    const std::string head(buf, static_cast<std::size_t>(n));
    EXPECT_EQ(head.substr(0, 10), "HTTP/1.1 4") << head.substr(0, 40);
  }
  auto c = client();
  EXPECT_EQ(c.Get("/login")->status, 200);
}

// The fleet's ranking by hand: A_X <= 10 um. M1: 4 um (2026-01-10), 5 um (2026-06-10): half the
// tolerance used, drifting 1 um per 151 days, so the line reaches 10 um 5 x 151 = 755 days after
// 2026-06-10, on 2028-07-04. The machine named <script>: 6 um once, 60 % used, no line. It ranks
// first (the larger share).
TEST_P(Serve, FleetRanksByTheShareOfToleranceUsed) {
  stop();
  tolerances_ = {"A_X=10"};
  start(65536);
  const Login l = login("vera");
  auto c = client();
  const auto r = c.Get("/api/fleet", l.headers());
  ASSERT_EQ(r->status, 200) << r->body;
  const auto fleet = nlohmann::json::parse(r->body);
  ASSERT_TRUE(fleet["ranked"].get<bool>());
  std::map<std::string, nlohmann::json> by;
  for (const auto& m : fleet["machines"]) by[m["machine"].get<std::string>()] = m["rank"];
  ASSERT_EQ(by.size(), 2u);
  const auto& m1 = by["M1"];
  const auto& x = by[kXss];
  EXPECT_EQ(m1["rank"], 2);
  EXPECT_EQ(x["rank"], 1);
  EXPECT_NEAR(m1["utilisation"].get<double>(), 0.5, 1e-12);
  EXPECT_NEAR(x["utilisation"].get<double>(), 0.6, 1e-12);
  EXPECT_EQ(m1["drift"], "predicted");
  EXPECT_EQ(x["drift"], "no_fit");
  const std::string date = m1["out_of_tolerance_on"].get<std::string>();
  EXPECT_TRUE(date.rfind("2028-07-04", 0) == 0 || date.rfind("2028-07-03T23:59", 0) == 0) << date;
  EXPECT_NEAR(m1["quantities"][0]["rate_per_year"].get<double>(), 365.2425 / 151, 0.01);
  // The page shows the columns, escaped.
  const auto page = c.Get("/fleet", l.headers());
  EXPECT_NE(page->body.find("Tolerance used (%)"), std::string::npos);
  EXPECT_NE(page->body.find("<td class=\"num\">50</td>"), std::string::npos);
  EXPECT_EQ(page->body.find("<script>alert"), std::string::npos);
  // A new record changes the ranking (it is not served stale).
  store_->record_by(sample("M1", "2026-09-10", 9.0), "eng");
  const auto again = nlohmann::json::parse(c.Get("/api/fleet", l.headers())->body);
  for (const auto& m : again["machines"])
    if (m["machine"] == "M1") {
      EXPECT_NEAR(m["rank"]["utilisation"].get<double>(), 0.9, 1e-12);
    }
  // After every kind of write, by the server or by another program on the store, the fleet's
  // ranking is what history rank gives (rank_store, printed as to_json): an upload through the
  // server, an event, a removal and an older record (M1's latest record and count stay).
  const auto same_as_history_rank = [&](const std::string& when) {
    RankRequest request;
    request.tolerances = parse_history_tolerances({"A_X=10"});
    const auto rank = nlohmann::json::parse(to_json(rank_store(*store_, request).ranking).dump());
    const auto fleet_now = nlohmann::json::parse(c.Get("/api/fleet", l.headers())->body);
    std::map<std::string, nlohmann::json> served;
    for (const auto& m : fleet_now["machines"])
      if (!m["rank"].is_null()) served[m["machine"].get<std::string>()] = m["rank"];
    ASSERT_EQ(served.size(), rank["machines"].size()) << when;
    for (const auto& m : rank["machines"]) {
      const auto& f = served[m["machine"].get<std::string>()];
      for (const char* k : {"rank", "utilisation", "years_to_limit", "outside", "quantities"})
        EXPECT_EQ(f[k], m[k]) << when << ": " << m["machine"] << " " << k;
    }
  };
  same_as_history_rank("after a record");
  const Login e = login("eng");
  const httplib::Headers h{{"Cookie", "mtcal_session=" + e.cookie}, {"X-CSRF-Token", e.csrf}};
  httplib::MultipartFormDataItems items{{"machine", "M7", "", ""}, {"date", "2026-10-01", "", ""},
                                        {"confirm", "1", "", ""},
                                        {"file", read_file(data_file()), "b02_x_axis.dat", "text/plain"}};
  const auto up = c.Post("/api/upload", h, items);
  ASSERT_EQ(up->status, 200) << up->body;
  same_as_history_rank("after an upload");
  ASSERT_EQ(c.Post("/api/events", h, httplib::Params{{"machine", "M1"}, {"date", "2026-09-20"}, {"kind", "repair"}})->status,
            200);
  same_as_history_rank("after an event");
  ASSERT_TRUE(store_->remove(ids_[0]));
  store_->record_by(sample("M1", "2026-02-10", 1.0), "eng");
  same_as_history_rank("after a removal and an older record");
}

// The server keeps the fleet between requests and makes again only the machines whose inputs
// changed. Requests from several clients at once (httplib's threads) while another program
// records on the same store: every answer is whole and shows at least the records written
// before it was sent; afterwards, and after another program's removal, the fleet is the one a
// server started on the store then makes (ages aside: they count to each server's as_of).
TEST_P(Serve, KeptFleetFollowsOtherWritersUnderConcurrentRequests) {
  stop();
  tolerances_ = {"A_X=10"};
  start(65536);
  const Login l = login("vera");
  constexpr int kWrites = 12;
  std::atomic<int> written{0};
  std::atomic<bool> done{false};
  std::thread writer([&] {
    auto other = open_history_store(conn_);  // another program's connection
    for (int i = 0; i < kWrites; ++i) {
      other->record(sample("W", "2026-01-" + std::string(i < 9 ? "0" : "") + std::to_string(i + 1), 1.0 + i));
      ++written;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    done = true;
  });
  std::atomic<int> failed{0}, stale{0}, answers{0};
  std::vector<std::thread> readers;
  for (int t = 0; t < 4; ++t)
    readers.emplace_back([&, t] {
      auto c = client();
      for (bool last = false; !last;) {
        last = done.load();
        const int before = written.load();
        const bool api = t % 2 == 0;
        const auto r = c.Get(api ? "/api/fleet" : "/fleet", l.headers());  // gzip'd: httplib's client accepts it
        if (!r || r->status != 200) {
          ++failed;
          continue;
        }
        ++answers;
        if (!api) {
          if (r->body.find("<p id=\"summary\">") == std::string::npos || r->body.rfind("</html>\n") + 8 != r->body.size())
            ++failed;
          continue;
        }
        long long shown = 0;
        const auto fleet = nlohmann::json::parse(r->body);
        for (const auto& m : fleet["machines"])
          if (m["machine"] == "W") shown = m["calibrations"][0]["count"].get<long long>();
        if (shown < before || shown > kWrites) {
          if (++stale == 1) ADD_FAILURE() << "W shows " << shown << " records, " << before << " were written before";
        }
      }
    });
  writer.join();
  for (auto& r : readers) r.join();
  EXPECT_EQ(failed.load(), 0);
  EXPECT_EQ(stale.load(), 0);
  EXPECT_GE(answers.load(), 4);
  auto c = client();
  const auto kept = nlohmann::json::parse(c.Get("/api/fleet", l.headers())->body);
  EXPECT_EQ(without_ages(kept), without_ages(fresh_fleet(l)));
  bool has_w = false;
  for (const auto& m : kept["machines"])
    if (m["machine"] == "W") has_w = m["calibrations"][0]["count"] == kWrites;
  EXPECT_TRUE(has_w) << kept.dump();
  // Another program removes the only record of the machine named <script>: it leaves the fleet.
  open_history_store(conn_)->remove(ids_[2]);
  const auto after = nlohmann::json::parse(c.Get("/api/fleet", l.headers())->body);
  EXPECT_EQ(without_ages(after), without_ages(fresh_fleet(l)));
  EXPECT_EQ(after["machines"].size(), 2u);
  EXPECT_EQ(c.Get("/fleet", l.headers())->body.find("name=%3Cscript"), std::string::npos);
  // gzip'd when the client accepts it (httplib's client inflates it): the same page and JSON.
  for (const char* path : {"/fleet", "/api/fleet"}) {
    httplib::Headers plain = l.headers(), gzip = l.headers();
    plain.emplace("Accept-Encoding", "identity");
    gzip.emplace("Accept-Encoding", "gzip;q=1.0, br;q=0");
    const auto p = c.Get(path, plain), g = c.Get(path, gzip);
    ASSERT_TRUE(p && g) << path;
    EXPECT_EQ(p->get_header_value("Content-Encoding"), "") << path;
    EXPECT_EQ(g->get_header_value("Content-Encoding"), "gzip") << path;
    if (std::string(path) == "/fleet")
      EXPECT_EQ(g->body, p->body);
    else
      EXPECT_EQ(without_ages(nlohmann::json::parse(g->body)), without_ages(nlohmann::json::parse(p->body)));
  }
}

// The ranking's entries are kept between requests and made again only for the machines whose
// series changed (FleetRanker's `changed`) or whose rank moved. After each of a series of random
// writes (seeded: a failure repeats) — records of ranked machines in and out of tolerance, older
// than their latest or newer, removals, uploads through the server, new machines — the fleet's
// ranking is a fresh FleetRanker's (the server's: lenient, as a removal can leave no machine with
// an A), and every fourth time the whole fleet is the one a server started then makes.
TEST_P(Serve, KeptRankingEntriesEqualAFreshRankingAfterRandomWrites) {
  stop();
  tolerances_ = {"A_X=10", "A=0.2"};  // the samples' A_X in um, the uploads' A in mm
  start(65536);
  const Login l = login("vera");
  const Login e = login("eng");
  const httplib::Headers h{{"Cookie", "mtcal_session=" + e.cookie}, {"X-CSRF-Token", e.csrf}};
  std::mt19937 rng(32);
  const auto pick = [&](int n) { return static_cast<int>(rng() % static_cast<unsigned>(n)); };
  std::vector<std::string> machines{"M1", kXss};
  for (int i = 0; i < 6; ++i) machines.push_back("R" + std::to_string(i));
  auto c = client();
  RankRequest request;
  request.tolerances = parse_history_tolerances(tolerances_);
  for (int step = 0; step < 20; ++step) {
    const std::string machine = machines[static_cast<std::size_t>(pick(static_cast<int>(machines.size())))];
    char date[16];
    std::snprintf(date, sizeof date, "%d-%02d-%02d", 2025 + pick(3), 1 + pick(12), 1 + pick(28));
    std::string did;
    if (step % 5 == 0) {  // the kinds of write in turn, the rest drawn
      httplib::MultipartFormDataItems items{{"machine", machine, "", ""}, {"date", date, "", ""},
                                            {"confirm", "1", "", ""},
                                            {"file", read_file(data_file()), "b02_x_axis.dat", "text/plain"}};
      const auto up = c.Post("/api/upload", h, items);
      ASSERT_EQ(up->status, 200) << up->body;
      did = "upload to " + machine;
    } else if (step % 5 == 1) {
      const auto all = store_->list();
      const auto& victim = all[static_cast<std::size_t>(pick(static_cast<int>(all.size())))];
      ASSERT_TRUE(store_->remove(victim.id));
      did = "removal of " + victim.id;
    } else {
      const double value = 0.5 * pick(25);  // 0 to 12 um: some outside the 10 um
      store_->record_by(sample(machine, date, value), "eng");
      did = "record of " + machine + " on " + date + ": " + std::to_string(value) + " um";
    }
    const auto served = nlohmann::json::parse(c.Get("/api/fleet", l.headers())->body);
    if (step % 4 == 3) {  // a server started now (a few: each start reads the whole store)
      ASSERT_EQ(without_ages(served), without_ages(fresh_fleet(l))) << "step " << step << ", after the " << did;
    }
    const auto rank = nlohmann::json::parse(to_json(FleetRanker(request, true).rank(*store_)->ranking).dump());
    std::map<std::string, nlohmann::json> by;
    for (const auto& m : served["machines"])
      if (!m["rank"].is_null()) by[m["machine"].get<std::string>()] = m["rank"];
    ASSERT_EQ(by.size(), rank["machines"].size()) << "step " << step;
    if (step % 5 == 0) {
      EXPECT_TRUE(by.count(machine)) << "the upload's A ranks " << machine;
    }
    for (const auto& m : rank["machines"]) {
      const auto& f = by[m["machine"].get<std::string>()];
      for (const char* k : {"rank", "utilisation", "years_to_limit", "outside", "quantities"})
        ASSERT_EQ(f[k], m[k]) << "step " << step << ", after the " << did << ": " << m["machine"] << " " << k;
    }
  }
}

// Intervals per machine: an admin sets one (an audit row names them), the fleet's overdue
// follows it, 0 returns to the default; a viewer cannot set one (the route walk checks roles).
TEST_P(Serve, CalibrationIntervalsPerMachine) {
  const Login admin = login("ada");
  auto c = client();
  const httplib::Headers h{{"Cookie", "mtcal_session=" + admin.cookie}, {"X-CSRF-Token", admin.csrf}};
  auto fleet_m1 = [&] {
    const auto fleet = nlohmann::json::parse(c.Get("/api/fleet", h)->body);
    for (const auto& m : fleet["machines"])
      if (m["machine"] == "M1") return m;
    return nlohmann::json();
  };
  // Default 365 days: M1's 2026-06-10 is overdue only from 2027-06-10 on; the server's own age decides.
  auto m1 = fleet_m1();
  EXPECT_EQ(m1["interval_days"], 365);
  EXPECT_FALSE(m1["interval_own"].get<bool>());
  auto r = c.Post("/api/intervals", h, httplib::Params{{"machine", "M1"}, {"days", "1"}});
  ASSERT_EQ(r->status, 200) << r->body;
  m1 = fleet_m1();
  EXPECT_EQ(m1["interval_days"], 1);
  EXPECT_TRUE(m1["overdue"].get<bool>());  // measured 2026-06-10, more than a day ago
  const auto audit = store_->audit("M1");
  ASSERT_EQ(audit.size(), 1u);
  EXPECT_EQ(audit[0].user, "ada");
  EXPECT_EQ(audit[0].action, "interval");
  EXPECT_EQ(c.Post("/api/intervals", h, httplib::Params{{"machine", "M1"}, {"days", "-3"}})->status, 400);
  EXPECT_EQ(c.Post("/api/intervals", h, httplib::Params{{"machine", "M1"}, {"days", "1.5"}})->status, 400);
  ASSERT_EQ(c.Post("/api/intervals", h, httplib::Params{{"machine", "M1"}, {"days", "0"}})->status, 200);
  EXPECT_EQ(fleet_m1()["interval_days"], 365);
  EXPECT_TRUE(store_->machine_intervals().empty());
  // The admin page lists the machines, escaped.
  const auto page = c.Get("/admin/machines", admin.headers());
  ASSERT_EQ(page->status, 200);
  EXPECT_EQ(page->body.find("<script>alert"), std::string::npos);
}

// POST /api/users (the users page's form for scripts): an admin adds a user, who can then log in
// with that role; a bad role or short password is 400 and stores nothing.
TEST_P(Serve, AdminsAddUsersThroughTheApi) {
  const Login admin = login("ada");
  auto c = client();
  const httplib::Headers h{{"Cookie", "mtcal_session=" + admin.cookie}, {"X-CSRF-Token", admin.csrf}};
  const auto r = c.Post("/api/users", h, httplib::Params{{"user", "bob"}, {"role", "engineer"}, {"password", kPassword}});
  ASSERT_EQ(r->status, 200) << r->body;
  const auto j = nlohmann::json::parse(r->body);
  EXPECT_EQ(j["name"], "bob");
  EXPECT_EQ(j["role"], "engineer");
  ASSERT_TRUE(store_->find_user("bob"));
  EXPECT_EQ(store_->find_user("bob")->role, "engineer");
  EXPECT_FALSE(login("bob").cookie.empty());
  EXPECT_EQ(c.Post("/api/users", h, httplib::Params{{"user", "carl"}, {"role", "root"}, {"password", kPassword}})->status,
            400);
  EXPECT_EQ(c.Post("/api/users", h, httplib::Params{{"user", "carl"}, {"role", "viewer"}, {"password", "short"}})->status,
            400);
  EXPECT_FALSE(store_->find_user("carl"));
}

// The store lost in the middle of a request: the test holds an exclusive lock on the records
// table, the server's confirmed upload waits for it inside its write, and the server's database
// connection is ended (pg_terminate_backend, as when PostgreSQL restarts). The answer is 503 with
// the reason, nothing is recorded, and the next requests are served on a new connection.
TEST_P(Serve, StoreLostMidRequestIs503AndRecordsNothing) {
  if (GetParam() != "postgresql") GTEST_SKIP() << "a connection ended mid-request needs the PostgreSQL server";
  const Login l = login("eng");
  const std::string content = read_file(data_file());
  ASSERT_FALSE(content.empty());
  PGconn* db = PQconnectdb(conn_.c_str());
  ASSERT_EQ(PQstatus(db), CONNECTION_OK) << PQerrorMessage(db);
  auto run = [&](const std::string& sql) {
    PGresult* r = PQexec(db, sql.c_str());
    const bool ok = PQresultStatus(r) == PGRES_COMMAND_OK || PQresultStatus(r) == PGRES_TUPLES_OK;
    std::string first = ok && PQntuples(r) > 0 ? PQgetvalue(r, 0, 0) : "";
    if (!ok) ADD_FAILURE() << sql << ": " << PQerrorMessage(db);
    PQclear(r);
    return first;
  };
  run("SET statement_timeout = '20s'");
  run("BEGIN");
  run("LOCK TABLE records IN ACCESS EXCLUSIVE MODE");
  const std::size_t before = 3;
  int status = 0;
  std::string body;
  std::thread upload([&] {
    auto c = client();
    httplib::MultipartFormDataItems items{{"machine", "M5", "", ""}, {"confirm", "1", "", ""},
                                          {"file", content, "b02_x_axis.dat", "text/plain"}};
    const auto answer = c.Post("/api/upload", {{"Cookie", "mtcal_session=" + l.cookie}, {"X-CSRF-Token", l.csrf}}, items);
    if (answer) {
      status = answer->status;
      body = answer->body;
    }
  });
  std::string pid;
  for (int i = 0; i < 200 && pid.empty(); ++i) {
    pid = run("SELECT pid FROM pg_stat_activity WHERE datname = current_database() AND wait_event_type = 'Lock' AND "
              "pid <> pg_backend_pid()");
    if (pid.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  EXPECT_FALSE(pid.empty()) << "the server's write never waited for the lock";
  if (!pid.empty()) run("SELECT pg_terminate_backend(" + pid + ")");
  upload.join();
  run("ROLLBACK");
  PQfinish(db);
  EXPECT_EQ(status, 503) << body;
  EXPECT_NE(body.find("the history store is unavailable"), std::string::npos) << body;
  EXPECT_EQ(record_count(), before);
  // Served on: the broken connection was dropped, a write succeeds.
  auto c = client();
  EXPECT_EQ(c.Get("/api/fleet", l.headers())->status, 200);
  const auto ok = c.Post("/api/events", {{"Cookie", "mtcal_session=" + l.cookie}, {"X-CSRF-Token", l.csrf}},
                         httplib::Params{{"machine", "M1"}, {"date", "2026-07-01"}, {"kind", "repair"}});
  EXPECT_EQ(ok->status, 200) << ok->body;
}

INSTANTIATE_TEST_SUITE_P(Backends, Serve, ::testing::Values("sqlite", "postgresql"),
                         [](const auto& p) { return p.param; });

TEST(ServeStart, AnUnreachableStoreIsAClearErrorAtStart) {
  ServerOptions o;
  o.store = "postgresql://mtcal@127.0.0.1:1/none?connect_timeout=2";
  try {
    Server s(o);
    ADD_FAILURE() << "a server started on an unreachable store";
  } catch (const StoreError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot connect to the history store"), std::string::npos) << e.what();
  }
  TempDir d;
  o.store = (d.path / "no-such-dir" / "x.db").string();
  EXPECT_THROW(Server{o}, StoreError);
}

// The hang of this test on a loaded machine: Server::stop() before httplib marked the server
// running did nothing (httplib's stop() only acts on a running server), and the thread of run()
// then served for ever. A server stopped at once after its thread starts, or before, must end.
TEST(ServeStart, StopRightAfterStartEndsTheServer) {
  TempDir d;
  ServerOptions o;
  o.store = "sqlite:" + (d.path / "stop.db").string();
  o.port = 0;
  o.threads = 1;
  o.kdf_cost = KdfCost::Minimum;
  std::atomic<int> finished{0};
  std::thread watchdog([&] {  // fails loudly instead of hanging until ctest's TIMEOUT
    for (int i = 0; i < 600 && finished.load() == 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    if (finished.load() == 0) {
      std::fprintf(stderr, "a stopped server did not end within 60 s\n");
      std::_Exit(1);
    }
  });
  for (int i = 0; i < 50; ++i) {
    Server s(o);
    s.bind();
    if (i % 2) {
      std::thread t([&] { s.run(); });
      s.stop();
      t.join();
    } else {
      s.stop();  // before run(): run() returns at once
      s.run();
    }
  }
  finished = 1;
  watchdog.join();
}

TEST(ServeStart, PasswordsAreMemoryHardHashesAndPoliciesHold) {
  const std::string h = hash_password("a long enough password", KdfCost::Minimum);
  EXPECT_EQ(h.rfind("$argon2id$", 0), 0u) << h;
  EXPECT_TRUE(verify_password("a long enough password", h));
  EXPECT_FALSE(verify_password("a long enough passwort", h));
  EXPECT_NE(hash_password("a long enough password", KdfCost::Minimum), h);  // salted
  EXPECT_FALSE(password_problem("short").empty());
  EXPECT_FALSE(user_name_problem("a<b").empty());
  EXPECT_FALSE(user_name_problem("").empty());
  EXPECT_TRUE(user_name_problem("ann.smith").empty());
  TempDir d;
  auto store = open_history_store((d.path / "u.db").string());
  EXPECT_THROW(add_user(*store, "ann", "root", "a long enough password", KdfCost::Minimum), InputError);
  EXPECT_THROW(add_user(*store, "ann", "admin", "short", KdfCost::Minimum), InputError);
  add_user(*store, "ann", "admin", "a long enough password", KdfCost::Minimum);
  EXPECT_EQ(store->find_user("ann")->password_hash.find("a long enough"), std::string::npos);
}

}  // namespace
