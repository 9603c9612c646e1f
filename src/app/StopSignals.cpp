#include "spall/app/StopSignals.hpp"

#include <csignal>

namespace spall::app {
namespace {

volatile std::sig_atomic_t received = 0;
struct sigaction previousTerm, previousUsr1;

extern "C" void record(int signal) {
  received = signal;
}

} // namespace

StopSignals::StopSignals() {
  received = 0;
  struct sigaction sa {};
  sa.sa_handler = record;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART; // I/O and MPI calls in flight carry on; the loop looks at step ends
  sigaction(SIGTERM, &sa, &previousTerm);
  sigaction(SIGUSR1, &sa, &previousUsr1);
}

StopSignals::~StopSignals() {
  sigaction(SIGTERM, &previousTerm, nullptr);
  sigaction(SIGUSR1, &previousUsr1, nullptr);
}

int StopSignals::pending() {
  return received;
}

const char* StopSignals::name(int signal) {
  return signal == SIGTERM ? "SIGTERM" : signal == SIGUSR1 ? "SIGUSR1" : "a signal";
}

} // namespace spall::app
