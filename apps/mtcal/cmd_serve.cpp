// mtcal serve: the calibration office in a browser on a history store (docs/serve.md).
#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <thread>

#include <fmt/format.h>

#include "common.hpp"
#include "mtcal/io/history/store.hpp"
#include "mtcal/server/server.hpp"
#include "mtcal/util/parse.hpp"

namespace mtcal::cli {
namespace {

struct ServeCliOptions {
  std::string store, listen = "127.0.0.1:8080", tls_cert, tls_key, add_user, role = "viewer", tolerance_file;
  std::vector<std::string> tolerances;
  int interval_days = 365, session_hours = 12, threads = 8;
  double max_upload_mib = 32;
};

// The password of --add-user: $MTCAL_PASSWORD, else one line of standard input.
std::string new_password() {
  if (const char* p = std::getenv("MTCAL_PASSWORD"); p && *p) return p;
  if (isatty(STDIN_FILENO)) std::cerr << "password for the new user: " << std::flush;
  std::string line;
  std::getline(std::cin, line);
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return line;
}

int run_serve(const ServeCliOptions& o) {
  std::string conn = o.store;
  if (conn.empty())
    if (const char* e = std::getenv("MTCAL_HISTORY")) conn = e;
  if (conn.empty())
    throw InputError({"--store", 0, ""}, "expected a history store (--store FILE or postgresql://...), found none");
  if (!o.add_user.empty()) {
    auto store = open_history_store(conn);
    server::add_user(*store, o.add_user, o.role, new_password());
    std::cout << fmt::format("user {} ({}) saved in {}\n", o.add_user, o.role, store->describe());
    return 0;
  }
  server::ServerOptions s;
  s.store = conn;
  const auto colon = o.listen.rfind(':');
  const auto port = colon == std::string::npos ? std::nullopt : parse_number(o.listen.substr(colon + 1));
  if (!port || *port < 0 || *port > 65535 || *port != static_cast<int>(*port) || colon == 0)
    throw InputError({"--listen", 0, ""}, "expected HOST:PORT (127.0.0.1:8080), found '" + printable(o.listen) + "'");
  s.host = o.listen.substr(0, colon);
  if (s.host.size() > 2 && s.host.front() == '[' && s.host.back() == ']') s.host = s.host.substr(1, s.host.size() - 2);
  s.port = static_cast<int>(*port);
  s.tls_cert = o.tls_cert;
  s.tls_key = o.tls_key;
  s.interval_days = o.interval_days;
  s.session_hours = o.session_hours;
  s.threads = o.threads;
  s.max_upload = static_cast<std::size_t>(o.max_upload_mib * 1024 * 1024);
  s.tolerance_file = o.tolerance_file;
  s.tolerances = o.tolerances;
  // SIGINT and SIGTERM end the server from a thread of their own (sigwait), not in a handler.
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  // A browser that closes its connection while a page is sent must not end the server.
  std::signal(SIGPIPE, SIG_IGN);
  server::Server server(s);
  const int bound = server.bind();
  std::cerr << fmt::format("mtcal: serving {} on {}://{}:{}/ (Ctrl-C stops)\n", conn.rfind("postgres", 0) == 0 ? "the store" : conn,
                           s.tls_cert.empty() ? "http" : "https", s.host, bound);
  std::thread waiter([&] {
    int sig = 0;
    sigwait(&set, &sig);
    server.stop();
  });
  server.run();
  // run() returned: by a signal (the waiter is done) or by an error (wake the waiter).
  pthread_kill(waiter.native_handle(), SIGTERM);
  waiter.join();
  std::cerr << "mtcal: server stopped\n";
  return 0;
}

}  // namespace

std::vector<Command> add_serve_commands(CLI::App& app) {
  auto o = std::make_shared<ServeCliOptions>();
  auto* c = app.add_subcommand("serve",
                               "The calibration office in a browser: fleet, machine and upload pages and their JSON "
                               "API on a history store, with accounts (viewer, engineer, admin)");
  c->add_option("--store", o->store, "The history store: a SQLite file, sqlite:PATH or postgresql://user@host/db "
                                     "(default $MTCAL_HISTORY)");
  auto* listen = c->add_option("--listen", o->listen, "HOST:PORT to listen on (default 127.0.0.1:8080; port 0: any free port)");
  auto* tls_cert = c->add_option("--tls-cert", o->tls_cert, "PEM certificate: serve HTTPS (with --tls-key)");
  auto* tls_key = c->add_option("--tls-key", o->tls_key, "PEM private key of --tls-cert");
  auto* add_user = c->add_option("--add-user", o->add_user,
                "Create or change a user and exit (password from $MTCAL_PASSWORD or one line of stdin)")
      // An empty name would otherwise mean "no --add-user" and start serving.
      ->check([](const std::string& name) { return name.empty() ? std::string("expected a user name, found ''") : std::string(); });
  c->add_option("--role", o->role, "Role of --add-user: viewer, engineer or admin (default viewer)")
      ->check(CLI::IsMember({"viewer", "engineer", "admin"}));
  auto* interval = c->add_option("--interval-days", o->interval_days, "A machine is overdue this many days after its last calibration "
                                                     "of a kind (default 365)")
      ->check(CLI::PositiveNumber);
  auto* tolerance_file = c->add_option("--tolerance-file", o->tolerance_file,
                "Tolerances of the fleet's ranking (share of tolerance used, drift, date out of tolerance), as "
                "history rank --tolerance-file: the acceptance YAML of docs/reports.md");
  auto* tolerance = c->add_option("--tolerance", o->tolerances,
                "QUANTITY=VALUE (|value| <= VALUE for a parameter, value <= VALUE for a figure) or QUANTITY=LO:HI, "
                "in the quantity's unit, as history rank --tolerance; repeatable");
  auto* session = c->add_option("--session-hours", o->session_hours, "A login lasts this long (default 12)")
                      ->check(CLI::PositiveNumber);
  auto* threads = c->add_option("--threads", o->threads, "Request threads (default 8)")->check(CLI::Range(1, 256));
  auto* max_upload =
      c->add_option("--max-upload", o->max_upload_mib, "Largest request in MiB (default 32)")->check(CLI::PositiveNumber);
  // --add-user saves a user and exits: the serving options would be silently ignored with it, so
  // they are refused (naming both) instead.
  for (auto* serving : {listen, tls_cert, tls_key, interval, tolerance_file, tolerance, session, threads, max_upload})
    add_user->excludes(serving);
  c->footer(
      "Examples:\n"
      "  MTCAL_PASSWORD=... mtcal serve --store shop.db --add-user ann --role admin\n"
      "  mtcal serve --store shop.db                       # http://127.0.0.1:8080/\n"
      "  mtcal serve --store shop.db --tolerance-file examples/acceptance/tolerances.yaml --interval-days 180\n"
      "  mtcal serve --store postgresql://mtcal@db/plant --listen 0.0.0.0:8443 --tls-cert c.pem --tls-key k.pem\n"
      "See docs/serve.md for roles, the JSON API, a systemd unit and backups.");
  return {{c, [o] { return run_serve(*o); }}};
}

}  // namespace mtcal::cli
