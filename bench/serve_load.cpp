// A bounded load test of mtcal serve on loopback (issue 32): a SQLite store of MACHINES x MONTHS
// records (default 1,000 x 120 = 120,000, as bench_history), the server in this process, then
//  1. the fleet page alone, one client, sequential: p50/p99, against the login page (no store
//     access) in the same run as the baseline; then as a browser asks for it (compressed), and
//     right after each of 20 new records of ranked machines (the ranking follows each);
//  2. CLIENTS concurrent clients (each logged in with its own session) sending REQUESTS requests
//     in all, mixed: fleet page, machine page, machine JSON, uploads of the real ISO 230-2 file
//     (recorded); p50/p99 per kind, errors, and the check that nothing was lost (records of the
//     upload machine after = before + uploads answered 200).
// Stops by itself. Run: mtcal_serve_load [MACHINES MONTHS CLIENTS REQUESTS] (ISO 230-2 file from
// $MTCAL_SHARED_DATA/iso230-2/b02_x_axis.dat, default ../shared/data relative to the source tree).
#include <httplib.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "mtcal/io/history/store.hpp"
#include "mtcal/io/system/sha256.hpp"
#include "mtcal/server/server.hpp"

namespace {

using namespace mtcal;
using Clock = std::chrono::steady_clock;

CalibrationRecord result(int machine, int month) {
  CalibrationRecord r;
  r.machine_name = fmt::format("M{:04}", machine);
  r.machine_serial = fmt::format("SN{:06}", machine);
  r.command = month % 2 ? "iso230-2" : "ballbar";
  r.measured_at = fmt::format("{:04}-{:02}-15", 2016 + month / 12, month % 12 + 1);
  r.metadata = {{"operator", "A. Smith"}, {"date", r.measured_at}};
  r.inputs = {{"x.dat", sha256_hex(fmt::format("{}-{}", machine, month))}};
  const double drift = 0.01 * month + 0.001 * machine;
  r.parameters = {{"EXX", 1 + drift, 0.2, "um"}, {"EC0Y", 1e-5 * drift, 1e-6, "rad"}};
  r.figures = {{"A_X", 14 + drift, "um", std::nullopt}, {"E_X", 11 + drift, "um", std::nullopt}};
  r.result_json = fmt::format(R"({{"A":{},"E":{}}})", 0.014, 0.011);
  return r;
}

// The server's Server-Timing metrics of a response ("NAME;dur=MS", comma-separated, in one or
// more headers): "app" the whole handler; the fleet's routes add their parts (wait, rank, read,
// parts, join, gzip).
std::map<std::string, double> server_timing(const httplib::Result& r) {
  std::map<std::string, double> out;
  if (!r) return out;
  for (const auto& [k, v] : r->headers) {
    if (k != "Server-Timing") continue;
    std::stringstream items(v);
    for (std::string item; std::getline(items, item, ',');) {
      const auto semi = item.find(";dur=");
      if (semi == std::string::npos) continue;
      std::string name = item.substr(0, semi);
      name.erase(0, name.find_first_not_of(' '));
      out[name] = std::atof(item.c_str() + semi + 5);
    }
  }
  return out;
}
// The server's own time for a request ("app"); nullopt without one.
std::optional<double> server_ms(const httplib::Result& r) {
  const auto t = server_timing(r);
  const auto app = t.find("app");
  if (app == t.end()) return std::nullopt;
  return app->second;
}
double percentile(std::vector<double> v, double p);
// p50 / p99 of each of the fleet route's parts (Server-Timing other than "app").
void print_parts(const std::map<std::string, std::vector<double>>& parts) {
  if (parts.empty()) return;
  std::printf("    the fleet's parts in the handler, p50 / p99 ms:");
  for (const char* k : {"wait", "rank", "read", "parts", "join", "gzip"})
    if (const auto p = parts.find(k); p != parts.end())
      std::printf(" %s %.1f / %.1f", k, percentile(p->second, 0.5), percentile(p->second, 0.99));
  std::printf("\n");
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const auto i = static_cast<std::size_t>(p * static_cast<double>(v.size() - 1) + 0.5);
  return v[std::min(i, v.size() - 1)];
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The machine's load average (1, 5, 15 min) from /proc/loadavg: the figures depend on it.
void print_load(const char* when) {
  std::ifstream in("/proc/loadavg");
  double a = 0, b = 0, c = 0;
  if (in >> a >> b >> c) std::printf("load average %s: %.2f %.2f %.2f\n", when, a, b, c);
}

struct Session {
  std::string cookie, csrf;
};

Session login(int port, const std::string& user, const std::string& password) {
  httplib::Client c("127.0.0.1", port);
  c.set_connection_timeout(10, 0);  // bounded: a server that stops answering ends the run with errors
  c.set_read_timeout(120, 0);
  // A failed request (no answer within the timeouts) leaves the session empty: the client's
  // requests are then refused and counted as errors (it does not end the run).
  const auto page = c.Get("/login");
  if (!page) return {};
  std::string token;
  for (const auto& [k, v] : page->headers)
    if (k == "Set-Cookie" && v.rfind("mtcal_login=", 0) == 0) token = v.substr(12, 64);
  const auto r = c.Post("/login", {{"Cookie", "mtcal_login=" + token}},
                        httplib::Params{{"csrf", token}, {"user", user}, {"password", password}});
  Session s;
  if (!r) return s;
  for (const auto& [k, v] : r->headers)
    if (k == "Set-Cookie" && v.rfind("mtcal_session=", 0) == 0) s.cookie = v.substr(14, 64);
  const auto fleet = c.Get("/api/machine?name=M0000", {{"Cookie", "mtcal_session=" + s.cookie}});
  std::smatch m;
  const auto page2 = c.Get("/upload", {{"Cookie", "mtcal_session=" + s.cookie}});
  if (page2 && std::regex_search(page2->body, m, std::regex("name=\"csrf\" value=\"([0-9a-f]{64})\""))) s.csrf = m[1];
  (void)fleet;
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  std::signal(SIGPIPE, SIG_IGN);  // a closed connection must not end the run
  const int machines = argc > 1 ? std::atoi(argv[1]) : 1000;
  const int months = argc > 2 ? std::atoi(argv[2]) : 120;
  const int clients = argc > 3 ? std::atoi(argv[3]) : 50;
  const int requests = argc > 4 ? std::atoi(argv[4]) : 10000;
  const char* shared = std::getenv("MTCAL_SHARED_DATA");
  const std::string data = read_file(std::string(shared ? shared : MTCAL_SHARED_DATA_DIR) + "/iso230-2/b02_x_axis.dat");
  if (data.empty()) {
    std::fprintf(stderr, "no ISO 230-2 file: set MTCAL_SHARED_DATA\n");
    return 1;
  }
  const auto dir = std::filesystem::temp_directory_path() / fmt::format("mtcal-serve-load-{}", ::getpid());
  std::filesystem::create_directories(dir);
  // MTCAL_LOAD_STORE=FILE: the store is kept in FILE and, when FILE exists, used as it is (filled
  // by an earlier run of the same size): before/after runs of a change without filling again.
  const char* kept = std::getenv("MTCAL_LOAD_STORE");
  const bool reuse = kept && *kept && std::filesystem::exists(kept);
  const std::string conn = "sqlite:" + (kept && *kept ? std::string(kept) : (dir / "load.db").string());
  if (reuse) {
    std::printf("store: %s as it is (MTCAL_LOAD_STORE)\n", kept);
    auto store = open_history_store(conn);  // migrated to this program's schema when older
    if (!store->find_user("load"))
      server::add_user(*store, "load", "engineer", "load-test-password", server::KdfCost::Minimum);
  }
  if (!reuse) {
    auto store = open_history_store(conn);
    const auto t0 = Clock::now();
    std::vector<CalibrationRecord> batch;
    for (int m = 0; m < machines; ++m) {
      for (int k = 0; k < months; ++k) batch.push_back(result(m, k));
      if (batch.size() >= 12'000) store->record_all(std::move(batch)), batch.clear();
    }
    if (!batch.empty()) store->record_all(std::move(batch));
    server::add_user(*store, "load", "engineer", "load-test-password", server::KdfCost::Minimum);
    std::printf("store: %d machines x %d records filled in %.1f s\n", machines, months,
                std::chrono::duration<double>(Clock::now() - t0).count());
  }
  server::ServerOptions o;
  o.store = conn;
  o.port = 0;
  // MTCAL_LOAD_THREADS=N: the server's request threads (default 8, as mtcal serve's).
  const char* threads_env = std::getenv("MTCAL_LOAD_THREADS");
  o.threads = threads_env && std::atoi(threads_env) > 0 ? std::atoi(threads_env) : 8;
  std::printf("server threads: %d\n", o.threads);
  // The fleet's ranking columns on (history rank over every machine's A_X), as a plant would run
  // it; MTCAL_LOAD_TOLERANCE= (empty) turns them off.
  const char* tol = std::getenv("MTCAL_LOAD_TOLERANCE");
  const std::string tolerance = tol ? tol : "A_X=30";
  if (!tolerance.empty()) o.tolerances = {tolerance};
  std::printf("fleet ranking: %s\n", tolerance.empty() ? "off" : ("--tolerance " + tolerance).c_str());
  server::Server srv(o);
  const int port = srv.bind();
  std::thread runner([&] { srv.run(); });

  // 1. The fleet page alone, against the login page.
  print_load("before the sequential part");
  const Session main_session = login(port, "load", "load-test-password");
  // before(i): run before request i, untimed (a write by another program).
  auto timed = [&](const std::string& path, int n, const Session* s, const std::string& accept_encoding = {},
                   const std::function<void(int)>& before = {}) {
    httplib::Client c("127.0.0.1", port);
    c.set_connection_timeout(10, 0);
    c.set_read_timeout(120, 0);
    std::vector<double> ms;
    httplib::Headers h;
    if (s) h = {{"Cookie", "mtcal_session=" + s->cookie}};
    if (!accept_encoding.empty()) h.emplace("Accept-Encoding", accept_encoding);
    std::string encoding;
    std::vector<double> in_server;
    std::map<std::string, std::vector<double>> parts;
    for (int i = 0; i < n; ++i) {
      if (before) before(i);
      const auto t = Clock::now();
      const auto r = c.Get(path, h);
      ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t).count());
      if (const auto handler = server_ms(r)) in_server.push_back(*handler);
      for (const auto& [k, v] : server_timing(r))
        if (k != "app") parts[k].push_back(v);
      if (!r || r->status != 200) std::printf("  %s: status %d\n", path.c_str(), r ? r->status : -1);
      if (r) encoding = r->get_header_value("Content-Encoding");
    }
    if (!accept_encoding.empty()) std::printf("  (Accept-Encoding: %s; answered Content-Encoding: %s)\n",
                                              accept_encoding.c_str(), encoding.empty() ? "none" : encoding.c_str());
    if (!in_server.empty())
      std::printf("  %s: in the server's handler (Server-Timing) p50 %.2f ms, p99 %.2f ms\n", path.c_str(),
                  percentile(in_server, 0.5), percentile(in_server, 0.99));
    print_parts(parts);
    return ms;
  };
  const auto login_ms = timed("/login", 200, nullptr);
  const auto fleet_ms = timed("/fleet", 50, &main_session);
  std::printf("login page (baseline): p50 %.2f ms, p99 %.2f ms\n", percentile(login_ms, 0.5), percentile(login_ms, 0.99));
  std::printf("fleet page (%d machines): p50 %.1f ms, p99 %.1f ms (%.0fx the login page's p50)\n", machines,
              percentile(fleet_ms, 0.5), percentile(fleet_ms, 0.99),
              percentile(fleet_ms, 0.5) / std::max(1e-9, percentile(login_ms, 0.5)));
  // The fleet page as a browser asks for it: Chromium and Firefox accept gzip and brotli.
  const auto browser_ms = timed("/fleet", 20, &main_session, "gzip, deflate, br");
  std::printf("fleet page, compressed as a browser accepts it: p50 %.1f ms, p99 %.1f ms\n", percentile(browser_ms, 0.5),
              percentile(browser_ms, 0.99));
  // The fleet page after each of 20 new records of fleet machines (written by another program,
  // as `mtcal ... --record` would): the ranking follows each of them.
  {
    auto writer = open_history_store(conn);
    const auto after_ms = timed("/fleet", 20, &main_session, {}, [&](int i) {
      // A new record at every run (the operator names the run), also on a kept store.
      auto r = result((i * 37) % machines, months + i);
      r.metadata["operator"] = fmt::format("load run {}", ::getpid());
      writer->record(std::move(r));
    });
    std::printf("fleet page after each new record of a ranked machine: p50 %.1f ms, p99 %.1f ms\n",
                percentile(after_ms, 0.5), percentile(after_ms, 0.99));
  }

  // 2. Mixed load.
  print_load("before the mixed load");
  auto store = open_history_store(conn);
  const std::size_t before = store->list({"LOAD-UP", "", "", ""}).size();
  std::atomic<int> next{0}, uploads_ok{0}, errors{0};
  std::mutex mutex;
  std::map<std::string, std::vector<double>> lat, lat_server, fleet_parts;
  const auto t0 = Clock::now();
  std::vector<std::thread> threads;
  for (int t = 0; t < clients; ++t)
    threads.emplace_back([&, t] {
      const Session s = login(port, "load", "load-test-password");
      httplib::Client c("127.0.0.1", port);
      c.set_connection_timeout(10, 0);
      c.set_read_timeout(120, 0);
      const httplib::Headers h{{"Cookie", "mtcal_session=" + s.cookie}, {"X-CSRF-Token", s.csrf}};
      std::map<std::string, std::vector<double>> mine, mine_server, mine_parts;
      for (int i; (i = next++) < requests;) {
        const int kind = i % 20;
        const std::string machine = fmt::format("M{:04}", (i * 7919) % machines);
        const auto start = Clock::now();
        std::string name;
        auto r = [&] {
          if (kind == 0) {
            name = "fleet";
            return c.Get("/fleet", h);
          }
          if (kind < 10) {
            name = "machine page";
            return c.Get("/machine?name=" + machine, h);
          }
          if (kind < 19) {
            name = "machine JSON";
            return c.Get("/api/machine?name=" + machine, h);
          }
          name = "upload";
          httplib::MultipartFormDataItems items{{"machine", "LOAD-UP", "", ""},
                                                {"operator", fmt::format("client {} request {}", t, i), "", ""},
                                                {"confirm", "1", "", ""},
                                                {"file", data, "b02_x_axis.dat", "text/plain"}};
          auto res = c.Post("/api/upload", h, items);
          if (res && res->status == 200) ++uploads_ok;
          return res;
        }();
        mine[name].push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
        if (const auto handler = server_ms(r)) mine_server[name].push_back(*handler);
        if (kind == 0)
          for (const auto& [k, v] : server_timing(r))
            if (k != "app") mine_parts[k].push_back(v);
        if (!r || r->status != 200) ++errors;
      }
      std::lock_guard lock(mutex);
      for (auto& [k, v] : mine) lat[k].insert(lat[k].end(), v.begin(), v.end());
      for (auto& [k, v] : mine_server) lat_server[k].insert(lat_server[k].end(), v.begin(), v.end());
      for (auto& [k, v] : mine_parts) fleet_parts[k].insert(fleet_parts[k].end(), v.begin(), v.end());
    });
  for (auto& th : threads) th.join();
  const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
  std::printf("mixed load: %d clients, %d requests in %.1f s (%.0f requests/s), %d errors\n", clients, requests, wall,
              requests / wall, errors.load());
  // The client's time against the handler's (Server-Timing): the rest is waiting in httplib's
  // queue for one of the server's threads, reading, parsing and sending.
  for (const auto& [k, v] : lat) {
    std::printf("  %-13s n=%5zu p50 %8.1f ms  p99 %8.1f ms", k.c_str(), v.size(), percentile(v, 0.5),
                percentile(v, 0.99));
    if (const auto s = lat_server.find(k); s != lat_server.end())
      std::printf("  (in the handler: p50 %7.1f ms, p99 %7.1f ms)", percentile(s->second, 0.5),
                  percentile(s->second, 0.99));
    std::printf("\n");
    if (k == "fleet") print_parts(fleet_parts);
  }
  const std::size_t after = store->list({"LOAD-UP", "", "", ""}).size();
  std::printf("records of LOAD-UP: before %zu, after %zu, uploads answered 200: %d -> %s\n", before, after,
              uploads_ok.load(), after == before + static_cast<std::size_t>(uploads_ok.load()) ? "nothing lost" : "LOST");
  print_load("after the mixed load");
  srv.stop();
  runner.join();
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
  return errors.load() == 0 && after == before + static_cast<std::size_t>(uploads_ok.load()) ? 0 : 1;
}
