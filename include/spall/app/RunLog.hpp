#pragma once
// The run log on rank 0: a start banner, a progress line (redrawn in place on a terminal, one
// line every ~10 s in a batch log) and a closing summary. Silent when quiet; errors go to stderr
// elsewhere and are never silenced.
#include <string>
#include <vector>

namespace spall::app {

class RunLog {
public:
  explicit RunLog(bool enabled);
  void banner(const std::vector<std::string>& lines);
  void warning(const std::string& text);
  void progress(long long step, double time, double endTime, double dt, std::size_t particles,
                double wall, const std::string& extra = {});
  // A line of its own between progress lines (e.g. a rebalance).
  void note(const std::string& text);
  void summary(const std::vector<std::string>& lines);

private:
  bool enabled_;
  bool tty_;
  double lastPrint_ = -1e300;
  bool lineOpen_ = false;
};

} // namespace spall::app
