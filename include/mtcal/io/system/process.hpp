// Running another program (a headless browser, an interpreter): no shell, a time limit, its output kept.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace mtcal {

struct ProgramRun {
  int exit_status = -1;    // the program's exit status; -1 when a signal ended it
  int signal = 0;          // the signal that ended it (SIGKILL after the time limit), 0 when it exited
  bool timed_out = false;  // the time limit ended it
  std::string out, err;    // what it wrote to standard output and standard error
  bool ok() const { return !timed_out && signal == 0 && exit_status == 0; }
};

// The first of names that is an executable file: a name with a '/' as it is, else looked up in
// the directories of $PATH. nullopt when there is none.
std::optional<std::string> find_program(const std::vector<std::string>& names);

// Runs argv[0] (a path, not looked up) with the arguments argv[1..] directly (posix_spawn: no
// shell, so nothing in an argument is interpreted), standard input from /dev/null, standard
// output and error kept, in a process group of its own. After timeout_s seconds the whole group
// is killed (SIGKILL) and timed_out set; when the program has exited, helpers it left behind in
// its group are killed too. Output beyond max_output bytes per stream is dropped. Throws Error
// when the program cannot be started (naming it and the reason). A non-empty working_dir is the
// program's working directory (LinuxCNC's interpreter finds the subroutine files a program calls
// there); the caller's stays as it is. Each "NAME=value" in environment replaces (or adds) that
// variable in the program's environment; the rest is inherited.
ProgramRun run_program(const std::vector<std::string>& argv, double timeout_s,
                       std::size_t max_output = std::size_t{256} << 20, const std::string& working_dir = {},
                       const std::vector<std::string>& environment = {});

}  // namespace mtcal
