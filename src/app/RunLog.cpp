#include "spall/app/RunLog.hpp"

#include "spall/core/Error.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fmt/format.h>
#include <string_view>
#include <unistd.h>

namespace spall::app {

namespace {
std::string duration(double s) {
  if (!(s >= 0.0) || s > 1e8) return "?";
  if (s < 60) return fmt::format("{:.1f}s", s);
  if (s < 3600) return fmt::format("{}m{:02d}s", int(s) / 60, int(s) % 60);
  return fmt::format("{}h{:02d}m", int(s) / 3600, int(s) % 3600 / 60);
}
} // namespace

RunLog::RunLog(bool enabled, double seconds, double percent, bool record)
    : record_(record), enabled_(enabled), tty_(enabled && stdoutIsTerminal()), seconds_(seconds),
      percent_(percent) {}

RunLog::~RunLog() {
  if (file_) std::fclose(file_);
}

void RunLog::attach(const std::string& path) {
  if (!record_) return;
  if (file_) std::fclose(file_);
  file_ = std::fopen(path.c_str(), "a");
  if (!file_) throw RunError("cannot open " + path + ": " + std::strerror(errno));
  for (const auto& l : pending_) fmt::print(file_, "{}\n", l);
  pending_.clear();
  std::fflush(file_);
}

void RunLog::record(const std::string& line) {
  if (!record_) return;
  if (!file_) {
    pending_.push_back(line);
    return;
  }
  fmt::print(file_, "{}\n", line);
  std::fflush(file_);
}

// A batch log's cadence: every seconds_ of wall time, and whenever the run crosses a multiple of
// percent_.
bool RunLog::batchDue(double wall, double fraction, double& lastPrint, double& lastFraction) const {
  const bool byPercent = percent_ > 0.0 && std::floor(100.0 * fraction / percent_) >
                                               std::floor(100.0 * lastFraction / percent_);
  if (wall - lastPrint < seconds_ && !byPercent) return false;
  lastPrint = wall;
  lastFraction = fraction;
  return true;
}

bool RunLog::stdoutIsTerminal() {
  if (isatty(fileno(stdout)) == 0) return false;
  const bool launched = std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMIX_RANK") ||
                        std::getenv("PMI_RANK") || std::getenv("SLURM_STEP_ID");
  if (!launched) return true;
  // The launcher is our parent on its own node (mpirun, srun's step daemon elsewhere): its fd 1
  // is what the user sees. Anything else (a remote daemon, no /proc) counts as a batch log.
  char target[256] = {};
  const std::string link = "/proc/" + std::to_string(getppid()) + "/fd/1";
  const ssize_t n = readlink(link.c_str(), target, sizeof target - 1);
  if (n <= 0) return false;
  const std::string_view t(target, static_cast<std::size_t>(n));
  return t.starts_with("/dev/pts/") || t.starts_with("/dev/tty");
}

void RunLog::banner(const std::vector<std::string>& lines) {
  for (const auto& l : lines) record(l);
  if (!enabled_) return;
  for (const auto& l : lines) fmt::print("{}\n", l);
  std::fflush(stdout);
}

void RunLog::warning(const std::string& text) {
  record("warning: " + text);
  if (enabled_) fmt::print(stderr, "warning: {}\n", text);
}

void RunLog::progress(long long step, double time, double endTime, double dt, std::size_t particles,
                      double wall, const std::string& extra) {
  if (!enabled_ && !record_) return;
  const double fraction = endTime > 0.0 ? time / endTime : 0.0;
  const double eta = fraction > 0.0 ? wall * (1.0 - fraction) / fraction : -1.0;
  const auto line = [&] {
    return fmt::format("step {:>8}  t {:.4e} s ({:5.1f}%)  dt {:.3e}  N {}  wall {}  ETA {}", step,
                       time, 100.0 * fraction, dt, particles, duration(wall), duration(eta)) +
           extra;
  };
  if (record_ && batchDue(wall, fraction, fileLastPrint_, fileLastFraction_)) record(line());
  if (!enabled_) return;
  // Terminal: redraw at most 5 times a second. Batch log: batchDue's cadence.
  if (tty_) {
    if (wall - lastPrint_ < 0.2) return;
    lastPrint_ = wall;
    lastFraction_ = fraction;
    fmt::print("\r{}\033[K", line());
    lineOpen_ = true;
  } else {
    if (!batchDue(wall, fraction, lastPrint_, lastFraction_)) return;
    fmt::print("{}\n", line());
  }
  std::fflush(stdout);
}

void RunLog::note(const std::string& text) {
  record(text);
  if (!enabled_) return;
  if (lineOpen_) fmt::print("\n"), lineOpen_ = false;
  fmt::print("{}\n", text);
  std::fflush(stdout);
}

void RunLog::summary(const std::vector<std::string>& lines) {
  for (const auto& l : lines) record(l);
  if (!enabled_) return;
  if (lineOpen_) fmt::print("\n");
  for (const auto& l : lines) fmt::print("{}\n", l);
  std::fflush(stdout);
}

} // namespace spall::app
