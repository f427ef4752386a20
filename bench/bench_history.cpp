// Benchmarks of the calibration history store (issue 19) on SQLite and on PostgreSQL:
//  - recording one result (one transaction, durable: SQLite synchronous=FULL, PostgreSQL with its
//    default fsync), against the baseline of writing the same result JSON to a file and fsync-ing
//    it (what any command's --out costs at least); target <= 10 ms;
//  - the trend queries over 120,000 records (1,000 machines x 10 years of monthly calibrations,
//    6 parameters and 4 figures each): one machine's parameter series, and the fleet-wide latest
//    value per machine; target <= 1 s.
// Run: mtcal_bench_history --benchmark_min_time=0.2 (the 120,000 records are made once per
// backend, about 10 s for SQLite and 30 s for PostgreSQL; the PostgreSQL server is started in a
// temporary folder like the tests' and stopped at the end; its benchmarks are skipped, with the
// reason, where the server cannot be started).
#include <fcntl.h>
#include <unistd.h>

#include <filesystem>
#include <memory>
#include <string>

#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include "mtcal/io/history/store.hpp"
#include "pg_server.hpp"

namespace {

using namespace mtcal;

constexpr int kMachines = 1000, kMonths = 120;

// An ISO 230-2-like result of about 3 kB and an identification's parameters.
CalibrationRecord result(int machine, int month, int salt) {
  CalibrationRecord r;
  r.machine_name = fmt::format("M{:04}", machine);
  r.machine_serial = fmt::format("SN{:06}", machine);
  r.command = "identify";
  r.measured_at = fmt::format("{:04}-{:02}-15", 2016 + month / 12, month % 12 + 1);
  r.metadata = {{"operator", "A. Smith"},
                {"temperature", "20.1 °C"},
                {"instrument", "XL-80 #1234"},
                {"date", r.measured_at}};
  r.inputs = {{"plan.csv", sha256_hex(fmt::format("{}-{}-{}", machine, month, salt))}};
  const double drift = 0.01 * month + 0.001 * machine;
  r.parameters = {{"EXX", 1 + drift, 0.2, "um"}, {"EYY", 2 - drift, 0.2, "um"}, {"EC0Y", 1e-5 * drift, 1e-6, "rad"},
                  {"EB0Z", -3e-5, 1e-6, "rad"},  {"EX0C", 0.003, 0.0002, "mm"}, {"EY0C", -0.004, 0.0002, "mm"}};
  r.figures = {{"VA", 20 + drift, "um", std::nullopt},
               {"A_X", 14 + drift, "um", std::nullopt},
               {"E_X", 11 + drift, "um", std::nullopt},
               {"G", 25 + drift, "um", std::nullopt}};
  std::string targets;
  for (int t = 0; t < 21; ++t)
    targets += fmt::format(R"({}{{"target":{},"mean_up":{},"mean_down":{},"B":{},"R":{}}})", t ? "," : "", t * 50.0,
                           1e-3 * t, 2e-3 * t, -3e-3, 7e-3);
  r.result_json = fmt::format(R"({{"A":{},"E":{},"salt":{},"targets":[{}]}})", 0.014, 0.011, salt, targets);
  return r;
}

struct Fixture {
  std::unique_ptr<testing::PgServer> server;
  std::string conn, why;
};

// The SQLite stores' folder, removed at exit (the filled store is about 450 MB).
struct BenchDir {
  std::filesystem::path path =
      std::filesystem::temp_directory_path() / fmt::format("mtcal-bench-history-{}", ::getpid());
  BenchDir() { std::filesystem::create_directories(path); }
  ~BenchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
};

Fixture& sqlite_fixture(bool filled) {
  static BenchDir bench_dir;
  static Fixture empty, full;
  Fixture& f = filled ? full : empty;
  if (f.conn.empty()) {
    const auto& dir = bench_dir.path;
    f.conn = "sqlite:" + (dir / (filled ? "full.db" : "empty.db")).string();
  }
  return f;
}

Fixture& pg_fixture() {
  static Fixture f = [] {
    Fixture x;
    x.server = std::make_unique<testing::PgServer>(/*fsync=*/true);
    if (!x.server->available()) {
      x.why = x.server->why();
      return x;
    }
    x.conn = x.server->create_database("bench");
    return x;
  }();
  return f;
}

void fill(HistoryStore& s) {
  if (!s.list({"M0000", "", "", ""}).empty()) return;
  std::vector<CalibrationRecord> batch;
  for (int m = 0; m < kMachines; ++m) {
    for (int k = 0; k < kMonths; ++k) batch.push_back(result(m, k, 0));
    if (batch.size() >= 12'000) {
      s.record_all(std::move(batch));
      batch.clear();
    }
  }
  if (!batch.empty()) s.record_all(std::move(batch));
}

std::string connection(benchmark::State& state, bool pg, bool filled) {
  if (!pg) return sqlite_fixture(filled).conn;
  auto& f = pg_fixture();
  if (f.conn.empty()) state.SkipWithError(("PostgreSQL benchmarks skipped: " + f.why).c_str());
  return f.conn;
}

// Baseline: the result's JSON written to a new file and fsync-ed.
void BM_History_Baseline_WriteFileFsync(benchmark::State& state) {
  const auto path = std::filesystem::temp_directory_path() / fmt::format("mtcal-bench-history-{}.json", ::getpid());
  const std::string text = result(0, 0, 0).result_json;
  for (auto _ : state) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0 || ::write(fd, text.data(), text.size()) != static_cast<ssize_t>(text.size()) || ::fsync(fd) != 0)
      state.SkipWithError("cannot write the baseline file");
    ::close(fd);
  }
  std::filesystem::remove(path);
}

void BM_History_RecordOne(benchmark::State& state) {
  const bool pg = state.range(0) == 1;
  const std::string conn = connection(state, pg, false);
  if (conn.empty()) return;
  auto store = open_history_store(conn);
  int salt = 0;
  for (auto _ : state) benchmark::DoNotOptimize(store->record(result(1, 1, ++salt)));
  state.SetLabel(pg ? "PostgreSQL (fsync on)" : "SQLite (WAL, synchronous=FULL)");
}

void BM_History_ParameterSeries(benchmark::State& state) {
  const bool pg = state.range(0) == 1;
  const std::string conn = connection(state, pg, true);
  if (conn.empty()) return;
  auto store = open_history_store(conn);
  fill(*store);
  int m = 0;
  std::size_t n = 0;
  for (auto _ : state) {
    const auto s = store->parameter_series(fmt::format("M{:04}", (m += 37) % kMachines), "EXX");
    n = s.size();
    benchmark::DoNotOptimize(s.data());
  }
  state.counters["samples"] = static_cast<double>(n);
  state.SetLabel(pg ? "PostgreSQL, 120,000 records" : "SQLite, 120,000 records");
}

void BM_History_FleetLatest(benchmark::State& state) {
  const bool pg = state.range(0) == 1;
  const std::string conn = connection(state, pg, true);
  if (conn.empty()) return;
  auto store = open_history_store(conn);
  fill(*store);
  std::size_t n = 0;
  for (auto _ : state) {
    const auto l = store->latest_parameter("EXX");
    n = l.size();
    benchmark::DoNotOptimize(l.data());
  }
  state.counters["machines"] = static_cast<double>(n);
  state.SetLabel(pg ? "PostgreSQL, 120,000 records" : "SQLite, 120,000 records");
}

void backends(benchmark::internal::Benchmark* b) {
  b->ArgName("postgresql")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
}

BENCHMARK(BM_History_Baseline_WriteFileFsync)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_History_RecordOne)->Apply(backends);
BENCHMARK(BM_History_ParameterSeries)->Apply(backends);
BENCHMARK(BM_History_FleetLatest)->Apply(backends);

}  // namespace

BENCHMARK_MAIN();
