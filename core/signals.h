#pragma once
// Orderly shutdown for long-running programs: SIGINT and SIGTERM are blocked in every thread and
// taken by one thread with sigwait, so no signal handler ever runs inside another thread's work.

#include <csignal>

namespace flsd {

// Blocks SIGINT and SIGTERM in the calling thread and in every thread it starts afterwards.
// Call first thing in main.
void BlockTerminationSignals();

// Waits for SIGINT or SIGTERM, or for `seconds` if that is positive; returns the signal number,
// or 0 when the time ran out.
int WaitForTermination(double seconds = 0.0);

}  // namespace flsd
