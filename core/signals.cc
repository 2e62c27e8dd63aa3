#include "core/signals.h"

#include <pthread.h>

#include <cerrno>
#include <ctime>

namespace flsd {
namespace {

sigset_t TerminationSignals() {
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  return signals;
}

}  // namespace

void BlockTerminationSignals() {
  const sigset_t signals = TerminationSignals();
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
}

int WaitForTermination(double seconds) {
  const sigset_t signals = TerminationSignals();
  if (seconds <= 0.0) {
    int signal = 0;
    sigwait(&signals, &signal);
    return signal;
  }
  const auto whole = static_cast<time_t>(seconds);
  const timespec timeout{whole, static_cast<long>((seconds - static_cast<double>(whole)) * 1e9)};
  int signal;
  do {
    signal = sigtimedwait(&signals, nullptr, &timeout);
  } while (signal < 0 && errno == EINTR);
  return signal < 0 ? 0 : signal;
}

}  // namespace flsd
