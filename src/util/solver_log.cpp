#include "mtcal/util/solver_log.hpp"

#include <atomic>
#include <mutex>

#include <glog/logging.h>

namespace mtcal {

namespace {
std::atomic<bool> g_verbose{false};
std::once_flag g_init;

void set_flags() {
  FLAGS_logtostderr = true;  // never log files in /tmp
  // glog severities: INFO 0, WARNING 1, ERROR 2, FATAL 3 (FATAL aborts whatever the level).
  FLAGS_minloglevel = g_verbose ? google::GLOG_INFO : google::GLOG_FATAL;
  FLAGS_stderrthreshold = g_verbose ? google::GLOG_INFO : google::GLOG_FATAL;
}

void init_once() {
  // Without InitGoogleLogging glog prints "Logging before InitGoogleLogging() is written to
  // STDERR" before the first message; initialised here once, unless the host program did.
  std::call_once(g_init, [] {
    if (!google::IsGoogleLoggingInitialized()) google::InitGoogleLogging("mtcal");
    set_flags();
  });
}

}  // namespace

// Called by the program before work starts (not concurrently with solves).
void set_solver_logging(bool verbose) {
  g_verbose = verbose;
  init_once();
  set_flags();
}

// Called before each solve, from any thread: the flags are written once, under call_once.
void apply_solver_logging() { init_once(); }

}  // namespace mtcal
