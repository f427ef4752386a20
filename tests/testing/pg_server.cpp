// A throw-away PostgreSQL server for tests and benchmarks (see pg_server.hpp).
#include "pg_server.hpp"

#include <arpa/inet.h>
#include <libpq-fe.h>
#include <netinet/in.h>
#include <pwd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>

namespace mtcal::testing {

namespace {

// A port that nothing listens on now (the kernel picks it); the server binds it right after.
std::string free_port() {
  const int s = ::socket(AF_INET, SOCK_STREAM, 0);
  if (s < 0) return "";
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = 0;
  socklen_t len = sizeof a;
  std::string port;
  if (::bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0 &&
      ::getsockname(s, reinterpret_cast<sockaddr*>(&a), &len) == 0)
    port = std::to_string(ntohs(a.sin_port));
  ::close(s);
  return port;
}

std::string shell_quote(const std::string& s) {
  std::string out = "'";
  for (const char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

}  // namespace

std::string find_pg_bin() {
  if (const char* env = std::getenv("MTCAL_PG_BIN"); env && *env) return env;
  namespace fs = std::filesystem;
  std::error_code ec;
  std::string best;
  for (const auto& e : fs::directory_iterator("/usr/lib/postgresql", ec))
    if (fs::exists(e.path() / "bin" / "initdb") && (best.empty() || e.path().string() > best)) best = e.path().string();
  return best.empty() ? "" : best + "/bin";
}

std::string PgServer::run_as(const std::string& command) const {
  return as_postgres_ ? "runuser -u postgres -- sh -c " + shell_quote(command) : command;
}

PgServer::PgServer(bool fsync) {
  bin_ = find_pg_bin();
  if (bin_.empty()) {
    why_ = "PostgreSQL server not installed (no /usr/lib/postgresql/*/bin/initdb; scripts/install-deps installs it)";
    return;
  }
  as_postgres_ = ::geteuid() == 0;
  if (as_postgres_ && !::getpwnam("postgres")) {
    why_ = "running as root and there is no user 'postgres' to run the server as (initdb refuses root)";
    return;
  }
  char templ[] = "/tmp/mtcal-pg-XXXXXX";
  if (!::mkdtemp(templ)) {
    why_ = "cannot create a temporary folder";
    return;
  }
  dir_ = templ;
  if (as_postgres_ && std::system(("chown postgres " + shell_quote(dir_)).c_str()) != 0) {
    why_ = "cannot give the temporary folder to the user postgres";
    return;
  }
  const std::string data = dir_ + "/data", log = dir_ + "/log";
  // C locale: byte-wise ordering and no locale the machine may lack; trust on the local socket
  // and 127.0.0.1 only (the server listens nowhere else).
  const std::string init = bin_ + "/initdb -D " + shell_quote(data) +
                           " -U mtcal --auth=trust --locale=C --encoding=UTF8 --no-sync > " + shell_quote(log) +
                           " 2>&1";
  if (std::system(run_as(init).c_str()) != 0) {
    why_ = "initdb failed (see " + log + ")";
    return;
  }
  for (int attempt = 0; attempt < 5 && port_.empty(); ++attempt) {
    const std::string port = free_port();
    std::string opts = "-p " + port + " -k " + dir_ + " -c listen_addresses=127.0.0.1 -c max_connections=50";
    if (!fsync) opts += " -c fsync=off -c synchronous_commit=off -c full_page_writes=off";
    const std::string start = bin_ + "/pg_ctl -D " + shell_quote(data) + " -l " + shell_quote(log) + " -w -t 30 -o " +
                              shell_quote(opts) + " start > /dev/null 2>&1";
    if (std::system(run_as(start).c_str()) == 0) port_ = port;
  }
  if (port_.empty()) why_ = "pg_ctl start failed (see " + log + ")";
}

PgServer::~PgServer() {
  if (!port_.empty())
    std::system(
        run_as(bin_ + "/pg_ctl -D " + shell_quote(dir_ + "/data") + " -m immediate -w stop > /dev/null 2>&1").c_str());
  if (!dir_.empty()) {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
}

std::string PgServer::conninfo(const std::string& database) const {
  return "postgresql://mtcal@127.0.0.1:" + port_ + "/" + database;
}

std::string PgServer::create_database(const std::string& name) {
  PGconn* c = PQconnectdb(conninfo().c_str());
  if (PQstatus(c) != CONNECTION_OK) {
    const std::string msg = PQerrorMessage(c);
    PQfinish(c);
    throw std::runtime_error("cannot connect to the test server: " + msg);
  }
  PGresult* r = PQexec(c, ("CREATE DATABASE \"" + name + "\"").c_str());
  const bool ok = PQresultStatus(r) == PGRES_COMMAND_OK;
  const std::string msg = PQerrorMessage(c);
  PQclear(r);
  PQfinish(c);
  if (!ok) throw std::runtime_error("CREATE DATABASE " + name + ": " + msg);
  return conninfo(name);
}

PgServer& shared_pg_server() {
  static PgServer server;
  return server;
}

}  // namespace mtcal::testing
