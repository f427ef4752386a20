// Shared by the libFuzzer targets: the reader's expected failures (mtcal::Error) are fine, anything
// else (another exception, a crash, a sanitizer report, a hang, unbounded memory) is a finding.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <set>
#include <string>
#include <string_view>

#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal::fuzz {

inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// Runs f; a typed mtcal error is the reader refusing the input, the expected outcome for most
// mutated inputs. Other exceptions propagate and abort the run (libFuzzer reports a crash).
template <class F>
void expect_mtcal_errors_only(F&& f) {
  try {
    f();
  } catch (const mtcal::Error&) {
  }
}

// The readers that take a path: the input goes to one file per process (rewritten every run),
// removed when the process ends (the replays in ctest left theirs in /tmp).
inline std::string write_input(const std::uint8_t* data, std::size_t size, const char* suffix) {
  struct RemovedAtExit {
    std::set<std::string> paths;
    ~RemovedAtExit() {
      for (const auto& p : paths) std::remove(p.c_str());
    }
  };
  static RemovedAtExit written;
  const std::string path = "/tmp/mtcal-fuzz-" + std::to_string(::getpid()) + suffix;
  written.paths.insert(path);
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) __builtin_trap();
  if (size && std::fwrite(data, 1, size, f) != size) __builtin_trap();
  std::fclose(f);
  return path;
}

// An example machine (the readers of axis-named columns need one), loaded once.
inline const Machine& example_machine(const char* name) {
  static const Machine m = load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/" + name);
  return m;
}

}  // namespace mtcal::fuzz
