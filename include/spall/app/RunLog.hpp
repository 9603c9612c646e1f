#pragma once
// The run log on rank 0: a start banner, a progress line (redrawn in place on a terminal; in a
// batch log, a plain line every N wall seconds and at every N percent of the run) and a closing
// summary. Silent when quiet; errors go to stderr elsewhere and are never silenced. With
// `record`, the same lines (progress at the batch cadence, warnings too) also go to a file once
// attach() names it, those before it first: OUT/run.log, written whatever --quiet says.
#include <cstdio>
#include <string>
#include <vector>

namespace spall::app {

class RunLog {
public:
  // Batch-log progress cadence: every `seconds` of wall time and every `percent` of the end
  // time (0: not by percent).
  explicit RunLog(bool enabled, double seconds = 30.0, double percent = 10.0, bool record = false);
  ~RunLog();
  RunLog(const RunLog&) = delete;
  RunLog& operator=(const RunLog&) = delete;
  // The file the recorded lines go to (appended to: a restart continues it). Throws RunError
  // when it cannot be opened.
  void attach(const std::string& path);
  // Whether stdout reaches a terminal. Under an MPI launcher a rank's stdout is a pseudo-terminal
  // whatever the user redirected, so the launcher's own stdout decides.
  static bool stdoutIsTerminal();
  void banner(const std::vector<std::string>& lines);
  void warning(const std::string& text);
  void progress(long long step, double time, double endTime, double dt, std::size_t particles,
                double wall, const std::string& extra = {});
  // A line of its own between progress lines (e.g. a rebalance).
  void note(const std::string& text);
  void summary(const std::vector<std::string>& lines);
  // A line for the file alone (already printed elsewhere).
  void record(const std::string& line);

private:
  bool batchDue(double wall, double fraction, double& lastPrint, double& lastFraction) const;

  bool record_;
  std::FILE* file_ = nullptr;
  std::vector<std::string> pending_; // recorded before attach()
  double fileLastPrint_ = -1e300, fileLastFraction_ = 0.0;
  bool enabled_;
  bool tty_;
  double seconds_, percent_;
  double lastPrint_ = -1e300;
  double lastFraction_ = 0.0;
  bool lineOpen_ = false;
};

} // namespace spall::app
