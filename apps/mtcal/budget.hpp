// Resource limits of a run (mtcal --max-memory, --max-time, --max-output-size, --max-input-size),
// up-front estimates checked against them, and progress lines on a terminal.
#pragma once

#include <chrono>
#include <cstddef>
#include <string>

#include <CLI/CLI.hpp>

namespace mtcal::cli {

struct RunLimits {
  double memory = 4.0 * (1ull << 30);   // bytes a computation may be estimated to need
  double seconds = 3600;                // estimated run time
  double output = 16.0 * (1ull << 30);  // bytes of one streamed output file
};
RunLimits& run_limits();

// The global options (given before or after the command's name); --max-input-size sets the
// formats layer's input_limits().
void add_limit_options(CLI::App& app);

// What a computation is estimated to need; zero: not estimated. `what` names it in the data's
// and options' words ("eval --grid of 4e9 configurations").
struct Estimate {
  std::string what;
  double bytes = 0, seconds = 0, output_bytes = 0;
};
// Throws LimitError naming the figure, the limit and the option that raises it.
void check_estimate(const Estimate& e);

// The option that raises a limit, for messages ("--max-memory").
const char* limit_option(int limit);

// "12 / 100 runs (12%)" on stderr, only when stderr is a terminal and the work lasts; cleared at
// the end. Thread-safe (update() may be called from workers).
class Progress {
 public:
  Progress(std::string label, std::size_t total);
  ~Progress();
  // total: a new total (0: keep the one given).
  void update(std::size_t done, std::size_t total = 0);
  bool active() const { return active_; }

 private:
  std::string label_;
  std::size_t total_;
  bool active_;
  std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace mtcal::cli
