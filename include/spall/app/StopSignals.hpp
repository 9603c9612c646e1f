#pragma once
// SIGTERM and SIGUSR1 ask a run to checkpoint at the next step boundary and exit 0 (a batch
// system's wall-clock warning, a preemption). The handler only records the signal; the step
// loop agrees on it across ranks, so a signal delivered to one rank stops all of them.
namespace spall::app {

class StopSignals {
public:
  StopSignals();  // installs the handlers
  ~StopSignals(); // restores what was there before
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  // The signal received since installation (SIGTERM or SIGUSR1), or 0.
  static int pending();
  static const char* name(int signal);
};

} // namespace spall::app
