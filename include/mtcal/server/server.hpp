// mtcal serve: the calibration office in a browser (fleet, machine, upload pages and their JSON API)
// on cpp-httplib, with accounts, sessions, CSRF tokens and roles (docs/serve.md).
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "mtcal/server/accounts.hpp"

namespace mtcal::server {

struct ServerOptions {
  std::string store;               // history store connection (open_history_store)
  std::string host = "127.0.0.1";  // address to listen on
  int port = 8080;                 // 0: any free port (bind() says which)
  std::string tls_cert, tls_key;   // PEM files: HTTPS when both are given
  std::size_t max_upload = std::size_t{32} << 20;  // largest request body (bytes); larger: 413
  int session_hours = 12;                          // a session ends this long after login
  int interval_days = 365;  // a machine is overdue this long after its last calibration (unless an admin set its own)
  int threads = 8;                                 // request threads (each with its own store connection)
  int login_attempts = 5;                          // failed logins per user or address before a lockout
  int lockout_seconds = 900;
  // Cost of the password hashes the server makes (users added on the users page, and the hash a
  // login of an unknown user is checked against, so that it costs what a known user's does).
  // Minimum is for tests only.
  KdfCost kdf_cost = KdfCost::Interactive;
  // The fleet's ranking columns (share of tolerance used, drift, predicted date out of
  // tolerance): tolerances as `mtcal history rank` takes them, a tolerance file (acceptance YAML,
  // docs/reports.md) and QUANTITY=VALUE or QUANTITY=LO:HI in the quantity's unit. Neither: no
  // ranking. Read and checked when the server starts (InputError).
  std::string tolerance_file;
  std::vector<std::string> tolerances;
  // Largest number of indexations of an uploaded probing-contacts file (the all-triples
  // estimator takes C(n, 3) triples: 300 take about 1 s).
  std::size_t max_indexations = 300;
};

// A route of the server: what the router registers and what the tests walk. pattern is the
// request path (query parameters carry names and ids, never path segments); min_role is the
// least role that may use it; public routes need no session (the login page, static assets).
struct Route {
  std::string method, path;
  Role min_role = Role::Viewer;
  bool is_public = false;
  bool api = false;     // JSON in and out; unauthenticated: 401 (a page: 303 to /login)
  std::string example;  // a query string that reaches the handler in tests ("name=M1"), may be empty
};

class Server {
 public:
  // Opens the store (StoreError: the store is unreachable; the message says why) and builds
  // the routes. TLS files are read here (InputError naming the file when unreadable).
  explicit Server(ServerOptions o);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  // Binds host:port; returns the port (the free one chosen when port is 0). Throws Error when
  // the address cannot be bound.
  int bind();
  // Serves until stop() (from another thread; a stop() before run() makes run() return at once,
  // so stop() may come at any time); call bind() first. The program should ignore SIGPIPE (a client that
  // closes its connection mid-response would otherwise end the process).
  void run();
  void stop();
  // Every route the router knows, in registration order.
  const std::vector<Route>& routes() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mtcal::server
