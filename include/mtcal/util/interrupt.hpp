// Stopping long computations from outside them (a signal handler, another thread): the library's
// parallel loops look at a flag between tasks and throw Interrupted.
#pragma once

#include "mtcal/util/errors.hpp"

namespace mtcal {

// Thrown by a loop that saw the request; no partial result is returned.
class Interrupted : public Error {
 public:
  Interrupted() : Error("interrupted") {}
};

// Async-signal-safe (a lock-free atomic store): a SIGINT handler may call it. The command-line
// program does not need it (its handler ends the process after removing temporary outputs); the
// Python module does, because Python's own handler only records the signal until the GIL is
// taken back, which a computation running without the GIL does not do.
void request_interrupt() noexcept;
void clear_interrupt() noexcept;
bool interrupt_requested() noexcept;
// Throws Interrupted if a stop was requested.
void check_interrupt();

}  // namespace mtcal
