// Writes a small, known fleet into a history store (through the store's own record()) for the
// command-line and browser tests of `mtcal history diff | trend | rank`.
// Usage: history_fixture STORE
//        history_fixture STORE --fleet MACHINES MONTHS   (a synthetic fleet for timing the commands:
//        machine Mi, EC0Y = a + b t + noise urad with u = 1.5, monthly from 2016-01-01, one transaction)
//
// The values are chosen so that the tests can state their results by hand (tests/history/test_history_cli.sh):
//   HU40T (serial 4711): EC0Y 20, 26, 30 urad (u = 2) and A_X 8, 9, 11 um at 2021-01-01 and one and
//     two mean Gregorian years later; a crash on 2021-06-01 and a compensation loaded on 2022-03-01.
//   VMC-2: EC0Y 10, 10.5, 11 urad (u = 1), A_X 14, 15, 17 um at the same dates.
//   LATHE-3: EXX 1.5 um (u = 0.5) only, once.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <random>
#include <string>

#include "mtcal/io/history/store.hpp"

int main(int argc, char** argv) {
  if (argc != 2 && !(argc == 5 && std::string(argv[2]) == "--fleet")) {
    std::cerr << "usage: history_fixture STORE [--fleet MACHINES MONTHS]\n";
    return 2;
  }
  using namespace mtcal;
  try {
    auto store = open_history_store(argv[1]);
    if (argc == 5) {
      const int machines = std::stoi(argv[3]), months = std::stoi(argv[4]);
      std::mt19937_64 gen(7);
      std::uniform_real_distribution<double> start(-20, 20), rate(0, 3);
      std::normal_distribution<double> noise(0, 1.5);
      std::vector<CalibrationRecord> all;
      for (int m = 0; m < machines; ++m) {
        const double a = start(gen), b = rate(gen);
        for (int k = 0; k < months; ++k) {
          CalibrationRecord r;
          r.machine_name = "M" + std::to_string(m);
          r.command = "identify";
          char date[16];
          std::snprintf(date, sizeof date, "%04d-%02d-01", 2016 + k / 12, 1 + k % 12);
          r.measured_at = date;
          r.parameters = {{"EC0Y", a + b * k / 12.0 + noise(gen), 1.5, "urad"}};
          r.result_json = "{\"m\": " + std::to_string(m) + ", \"k\": " + std::to_string(k) + "}";
          all.push_back(std::move(r));
        }
      }
      store->record_all(std::move(all));
      return 0;
    }
    const char* dates[] = {"2021-01-01", "2022-01-01T05:49:12Z", "2023-01-01T11:38:24Z"};
    const double hu_c[] = {20, 26, 30}, hu_a[] = {8, 9, 11}, vmc_c[] = {10, 10.5, 11}, vmc_a[] = {14, 15, 17};
    const char* operators[] = {"J. Doe", "A. Smith", "J. Doe"};
    for (int i = 0; i < 3; ++i) {
      CalibrationRecord r;
      r.machine_name = "HU40T";
      r.machine_serial = "4711";
      r.command = "identify";
      r.measured_at = dates[i];
      r.metadata = {{"machine", "HU40T"},
                    {"serial", "4711"},
                    {"date", dates[i]},
                    {"operator", operators[i]},
                    {"temperature_air", "20." + std::to_string(i + 1) + " °C"}};
      r.parameters = {{"EC0Y", hu_c[i], 2.0, "urad"}};
      r.figures = {{"A_X", hu_a[i], "um", std::nullopt}};
      r.result_json = "{\"fixture\": " + std::to_string(i) + "}";
      store->record(r);
      r.machine_name = "VMC-2";
      r.machine_serial.clear();
      r.metadata = {{"machine", "VMC-2"}, {"date", dates[i]}};
      r.parameters = {{"EC0Y", vmc_c[i], 1.0, "urad"}};
      r.figures = {{"A_X", vmc_a[i], "um", std::nullopt}};
      store->record(r);
    }
    CalibrationRecord lathe;
    lathe.machine_name = "LATHE-3";
    lathe.command = "fit-motion";
    lathe.measured_at = "2022-06-01";
    lathe.parameters = {{"EXX", 1.5, 0.5, "um"}};
    lathe.result_json = "{}";
    store->record(lathe);
    store->add_event({"", "HU40T", "2021-06-01", EventKind::Crash, "spindle crash into the fixture, <b>Y axis</b>"});
    store->add_event({"", "HU40T", "2022-03-01", EventKind::CompensationLoaded, "new pitch table"});
  } catch (const std::exception& e) {
    std::cerr << "history_fixture: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
