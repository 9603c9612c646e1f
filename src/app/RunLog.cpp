#include "spall/app/RunLog.hpp"

#include <cstdio>
#include <fmt/format.h>
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

RunLog::RunLog(bool enabled) : enabled_(enabled), tty_(isatty(fileno(stdout)) != 0) {}

void RunLog::banner(const std::vector<std::string>& lines) {
  if (!enabled_) return;
  for (const auto& l : lines) fmt::print("{}\n", l);
  std::fflush(stdout);
}

void RunLog::warning(const std::string& text) {
  if (enabled_) fmt::print(stderr, "warning: {}\n", text);
}

void RunLog::progress(long long step, double time, double endTime, double dt, std::size_t particles,
                      double wall, const std::string& extra) {
  if (!enabled_) return;
  // Terminal: redraw at most 5 times a second. Batch log: a line every 10 s.
  const double every = tty_ ? 0.2 : 10.0;
  if (wall - lastPrint_ < every) return;
  lastPrint_ = wall;
  const double fraction = endTime > 0.0 ? time / endTime : 0.0;
  const double eta = fraction > 0.0 ? wall * (1.0 - fraction) / fraction : -1.0;
  const std::string line =
      fmt::format("step {:>8}  t {:.4e} s ({:5.1f}%)  dt {:.3e}  N {}  wall {}  ETA {}", step, time,
                  100.0 * fraction, dt, particles, duration(wall), duration(eta)) +
      extra;
  if (tty_) {
    fmt::print("\r{}\033[K", line);
    lineOpen_ = true;
  } else {
    fmt::print("{}\n", line);
  }
  std::fflush(stdout);
}

void RunLog::note(const std::string& text) {
  if (!enabled_) return;
  if (lineOpen_) fmt::print("\n"), lineOpen_ = false;
  fmt::print("{}\n", text);
  std::fflush(stdout);
}

void RunLog::summary(const std::vector<std::string>& lines) {
  if (!enabled_) return;
  if (lineOpen_) fmt::print("\n");
  for (const auto& l : lines) fmt::print("{}\n", l);
  std::fflush(stdout);
}

} // namespace spall::app
