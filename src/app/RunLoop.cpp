#include "Simulation.hpp"

#include "spall/app/StopSignals.hpp"
#include "spall/app/SystemInfo.hpp"
#include "spall/io/Xdmf.hpp"

#include <fmt/format.h>
#include <fstream>

// The run loop: time, output and checkpoint triggers, signals.
namespace spall::app {

namespace fs = std::filesystem;

template <int Dim> void Simulation<Dim>::run(const RunOptions& options, const fs::path& dir) {
  RunLog log(mpi_.root() && !options.quiet);
  log_ = &log;
  const auto wall0 = Clock::now();
  for (const auto& w : deferredWarnings_) log.warning(w);
  banner(log, dir);
  dir_ = dir;
  const bool resumed = !resumedFrom_.empty();
  openLogs(dir, resumed, log);
  if (resumed)
    log.note(fmt::format(
        "restarted from {} at step {} (t = {:.6g} s){}; {:.1f} MB read in {:.2f} s", resumedFrom_,
        step_, time_,
        checkpointRanks_ == mpi_.size() ? ""
                                        : fmt::format(", written on {} rank{}", checkpointRanks_,
                                                      checkpointRanks_ > 1 ? "s" : ""),
        checkpointReadBytes_ / 1e6, checkpointReadSeconds_));

  StopSignals signals;
  double dt = 0.0;
  startStep_ = step_;
  if (resumed) {
    // The rates and the time step of the checkpointed step: no evaluation here, so the run
    // continues exactly as the uninterrupted one.
    dt = resumeDt_;
    last_ = diagnostics::computeTotals(store_, f_, mpi_);
  } else {
    probes_->attach(store_, f_, mpi_);
    method_->evaluate(step_);
    dt = nextTimeStep();
    totals0_ = diagnostics::computeTotals(store_, f_, mpi_);
    record(0.0, 0, wall0);
    writeSnapshot();
  }
  lastCheckpointWall_ = wall0;

  const double end = deck_.run.end_time;
  double lastProgress = -1.0;
  int stopSignal = 0;
  if (resumed && !(time_ < end * (1.0 - 1e-12) && step_ < deck_.run.max_steps))
    log.note(fmt::format("the checkpoint is at the end of this run (t = {:.6g} s, step {}): "
                         "nothing to do; extend it with --set run.end_time=...",
                         time_, step_));
  while (time_ < end * (1.0 - 1e-12) && step_ < deck_.run.max_steps) {
    dt = clampToTargets(dt);
    method_->advance(dt, step_, time_);
    time_ += dt;
    ++step_;
    record(dt, step_, wall0);
    if (snapshotDue()) writeSnapshot();
    const double wall = std::chrono::duration<double>(Clock::now() - wall0).count();
    if (wall - lastProgress > 0.0) {
      log.progress(step_, time_, end, dt, particles(), wall,
                   mpi_.size() > 1 ? fmt::format("  imbalance {:.2f}", method_->stats().imbalance)
                                   : "");
      lastProgress = wall;
    }
    dt = nextTimeStep();
    // Checkpoint triggers, agreed on by all ranks: a signal on any rank, rank 0's wall clock.
    int due[2] = {StopSignals::pending(), 0};
    if (mpi_.root() && deck_.checkpoint && deck_.checkpoint->every_wall_seconds > 0.0)
      due[1] = std::chrono::duration<double>(Clock::now() - lastCheckpointWall_).count() >=
               deck_.checkpoint->every_wall_seconds;
    MPI_Allreduce(MPI_IN_PLACE, due, 2, MPI_INT, MPI_MAX, mpi_.comm());
    const bool stepsDue = deck_.checkpoint && deck_.checkpoint->every_steps > 0 &&
                          step_ % deck_.checkpoint->every_steps == 0;
    if (due[0] || due[1] || stepsDue) checkpoint(dt, wall0);
    if (due[0]) {
      stopSignal = due[0];
      break;
    }
  }
  if (!stopSignal) {
    if (lastSnapshotStep_ != step_) writeSnapshot();
    // The end of a run is a checkpoint too: a chain extends it with a later end time.
    if (lastCheckpointStep_ != step_) checkpoint(dt, wall0);
  }
  history_.flush();
  probesCsv_.flush();
  finish(log, options, wall0, stopSignal);
  log_ = nullptr;
}

// The method's stable step; a step below 1e-14 of the end time is a collapse.
template <int Dim> double Simulation<Dim>::nextTimeStep() {
  return method_->stableTimeStep(1e-14 * deck_.run.end_time, step_, time_);
}

// Shortens dt so that snapshot times and the end time are hit exactly; splits the last two
// steps before a target evenly rather than leaving a sliver.
template <int Dim> double Simulation<Dim>::clampToTargets(double dt) const {
  double target = deck_.run.end_time;
  if (deck_.output.every > 0.0) target = std::min(target, nextSnapshotTime_);
  const double left = target - time_;
  if (left <= 0.0) return dt;
  if (dt >= left) return left;
  if (1.5 * dt > left) return 0.5 * left;
  return dt;
}

// Writes ckpt_<step>.h5 (atomically), then points `latest` at it, then prunes old ones. The
// logs are flushed first, so every row up to this step is on disk before the checkpoint is.
template <int Dim> void Simulation<Dim>::checkpoint(double dtNext, Clock::time_point wall0) {
  method_->stats().phases.time(methods::kCheckpoint, [&] {
    history_.flush();
    probesCsv_.flush();
    const std::string name = checkpointFileName(step_);
    const fs::path ckDir = dir_ / "checkpoints";
    const double wall = std::chrono::duration<double>(Clock::now() - wall0).count();
    const auto w =
        io::writeCheckpoint(mpi_.comm(), (ckDir / name).string(), store_, time_, step_, Dim,
                            BuildInfo::version(), saveState(dtNext, wallOffset_ + wall));
    parallel::onRoot<RunError>(mpi_.comm(), [&] {
      publishLatest(ckDir, name);
      pruneCheckpoints(ckDir, checkpointKeep());
    });
    ++checkpointsWritten_;
    checkpointBytes_ = w.bytes;
    checkpointWriteSeconds_ += w.seconds;
    checkpointWriteBytes_ += w.bytes;
    lastCheckpointStep_ = step_;
    lastCheckpointWall_ = Clock::now();
    if (log_)
      log_->note(fmt::format("checkpoint {} at step {}: {:.1f} MB in {:.2f} s ({:.0f} MB/s)",
                             (fs::path("checkpoints") / name).string(), step_, w.bytes / 1e6,
                             w.seconds, w.seconds > 0 ? w.bytes / 1e6 / w.seconds : 0.0));
  });
}

template class Simulation<1>;
template class Simulation<2>;
template class Simulation<3>;

} // namespace spall::app
