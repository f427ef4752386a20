// A throw-away PostgreSQL server for shell tests: prints the connection string of a fresh database
// (or "SKIPPED: why"), then keeps the server until its standard input closes.
#include <iostream>
#include <string>

#include "pg_server.hpp"

int main() {
  mtcal::testing::PgServer pg;
  if (!pg.available()) {
    std::cout << "SKIPPED: " << pg.why() << std::endl;
    return 0;
  }
  std::cout << pg.create_database("serve_browser") << std::endl;
  std::string line;
  while (std::getline(std::cin, line)) {
  }
  return 0;
}
