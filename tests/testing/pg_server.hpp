// A throw-away PostgreSQL server for tests and benchmarks: initdb in a temporary folder, a free
// port on 127.0.0.1, stopped and removed when the object goes.
#pragma once

#include <string>

namespace mtcal::testing {

class PgServer {
 public:
  // Starts a server (Debian's postgresql: /usr/lib/postgresql/N/bin, or $MTCAL_PG_BIN). When
  // the process runs as root the server runs as the user "postgres" (initdb refuses root).
  // fsync=false for tests (nothing outlives them); benchmarks keep PostgreSQL's defaults.
  // available() is false, and why() says why, when no server could be started.
  explicit PgServer(bool fsync = false);
  ~PgServer();
  PgServer(const PgServer&) = delete;
  PgServer& operator=(const PgServer&) = delete;

  bool available() const { return !port_.empty(); }
  const std::string& why() const { return why_; }
  // A fresh database (CREATE DATABASE) and the connection string to it.
  std::string create_database(const std::string& name);
  // Connection string of the server's "postgres" database.
  std::string conninfo(const std::string& database = "postgres") const;

 private:
  std::string dir_, port_, why_, bin_;
  bool as_postgres_ = false;
  std::string run_as(const std::string& command) const;
};

// One server for the whole test program (initdb + start take about a second), stopped at exit.
PgServer& shared_pg_server();

// Whether Debian's PostgreSQL server binaries are installed (a bin folder with initdb).
std::string find_pg_bin();

}  // namespace mtcal::testing
