#pragma once
// A run of one dimension: the particles, the method that steps them, and the run loop around
// it (time, output, checkpoints, signals). The run loop knows nothing of how the method steps.
// Its members are defined by job: Simulation.cpp (set-up, new run, restart, checkpoint state, the
// loop), RunOutput.cpp (snapshots, history, probes, banner), RunSummary.cpp (the closing summary
// and summary.json), RunFailure.cpp (the rescue point, the replay and message of a failed step, the
// time-step warning).
#include "spall/app/BodyGenerator.hpp"
#include "spall/app/CheckpointFiles.hpp"
#include "spall/app/ParticleRecorder.hpp"
#include "spall/app/Run.hpp"
#include "spall/app/RunLog.hpp"
#include "spall/core/ParticleFields.hpp"
#include "spall/core/Threads.hpp"
#include "spall/diagnostics/Conservation.hpp"
#include "spall/diagnostics/Penetration.hpp"
#include "spall/diagnostics/Probes.hpp"
#include "spall/io/Checkpoint.hpp"
#include "spall/io/CsvLog.hpp"
#include "spall/materials/MaterialUpdate.hpp"
#include "spall/methods/Method.hpp"
#include "spall/parallel/Decomposition.hpp"

#include <chrono>
#include <deque>
#include <filesystem>
#include <limits>
#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <utility>
#include <vector>

namespace spall::app {

using Clock = std::chrono::steady_clock;

template <int Dim> class Simulation {
public:
  Simulation(const Deck& deck, const parallel::MpiContext& mpi);

  // A new run: every rank generates the same particles (ids, jitter and energy deposits
  // therefore do not depend on the rank count), keeps a slice and hands the rest to their owners.
  void generate();
  // A continued run: the first of `candidates` that reads back completely. Throws
  // CheckpointError when none does, UsageError when the checkpoint belongs to another deck.
  void resume(const RestartCandidates& candidates);
  // A run that fails (RunError) leaves a summary.json saying so, then rethrows.
  void run(const RunOptions& options, const std::filesystem::path& dir);
  // After generate or resume, before anything is written: the recorded particles exist (else a
  // DeckError).
  void prepareRecording() {
    recorder_ = std::make_unique<ParticleRecorder<Dim>>(deck_.output);
    recorder_->check(store_, f_, mpi_);
  }

  // All ranks' owned particles.
  std::size_t particles() const { return totalParticles_; }
  // The cores the run uses: ranks x threads per rank (the per-core rates divide by it).
  double cores() const { return static_cast<double>(mpi_.size()) * threadCount(); }
  const std::vector<BodySummary>& bodies() const { return bodies_; }
  const std::vector<std::string>& warnings() const { return deferredWarnings_; }
  // Lines for run.log's start (printed on stderr already).
  void logWarnings(std::vector<std::string> lines) { loggedWarnings_ = std::move(lines); }
  // A rough peak estimate: stored fields, ghosts (~10%) and neighbor indices at the target n_h.
  std::size_t memoryEstimate() const;
  // Before any force: h over the sound and bulk speed.
  double firstTimeStep() const;
  // Collective, after generate(): the plausibility of run.end_time against the time a sound
  // wave takes to cross the largest body (docs/reference.md, "Warnings").
  std::vector<DeckWarning> sceneWarnings() const;

private:
  // Simulation.cpp: the loop
  double stepOnce(double dt, Clock::time_point wall0, bool replay);
  double nextTimeStep();
  // MPM's frictionless contact acts where the bodies' material fills 90% of a node's support: a
  // body under 2 cells across can pass through another (decks/README.md). Warns which.
  void warnThinBodies(double cell);
  // A stable step below this fraction of run.end_time is a collapse: ten billion steps to go is
  // a run that never ends (a point compressed without bound took dt from 3e-8 s to 5e-17 s, and
  // the run went on; at 1e-14 it was not yet a collapse).
  static constexpr double kCollapse = 1e-10;
  std::pair<double, double> clampToTargets(double dt) const;
  void insertDueBodies();
  void checkpoint(double dtNext, Clock::time_point wall0);
  int checkpointKeep() const { return deck_.checkpoint ? deck_.checkpoint->keep : 2; }
  // RunFailure.cpp
  void keepRescuePoint(double dtNext, Clock::time_point wall0);
  [[noreturn]] void explainFailure(const StepFailure& failure, Clock::time_point wall0);
  struct FailureReplay {
    std::vector<std::string> rows;                         // the failure's history, a step a row
    double pMin = std::numeric_limits<double>::infinity(); // the particle's, over good steps
    std::int64_t checkpointStep = -1; // the last good state's checkpoint, or -1
  };
  FailureReplay replayFailure(const StepFailure& failure, Clock::time_point wall0);
  void writeFailureHistory(const ParticleReport& f, const FailureReplay& replay);
  std::string failureText(const StepFailure& failure, const FailureReplay& replay) const;
  void watchTimeStep(double dt);
  void watchEnergy(double dt);
  // Simulation.cpp: checkpoint state
  io::CheckpointState saveState(double dtNext, double wall) const;
  void restoreState(const io::CheckpointHeader& h, bool sameLayout);
  void summarizeWaitingBodies();
  // RunOutput.cpp
  void openLogs(const std::filesystem::path& dir, bool resumed, RunLog& log);
  std::size_t historyBins() const;
  void resolveOutputFields();
  bool snapshotDue() const;
  void writeSnapshot(bool write = true);
  void writeSeries(const std::filesystem::path& snapDir) const;
  void writeFragments();
  void writePenetration();
  void advanceSnapshotClock(const std::string& base);
  void record(double dt, std::int64_t step, Clock::time_point wall0);
  void banner(RunLog& log, const std::filesystem::path& dir);
  // RunSummary.cpp: the closing summary
  void finish(RunLog& log, const RunOptions& options, Clock::time_point wall0, int stopSignal);
  struct RunReport; // RunSummary.cpp
  RunReport report(Clock::time_point wall0);
  void conservationErrors(RunReport& r) const;
  std::vector<std::string> summaryLines(const RunReport& r, const RunOptions& options,
                                        int stopSignal) const;
  void writeSummary(const RunReport& r, const RunOptions& options, int stopSignal) const;
  nlohmann::ordered_json summaryHead(const RunOptions& options) const;
  void writeSummaryFile(const nlohmann::ordered_json& j) const;
  void writeFailureSummary(const RunOptions& options, const std::string& message) const;
  void runSteps(const RunOptions& options, const std::filesystem::path& dir);

  const Deck& deck_;
  const parallel::MpiContext& mpi_;
  std::vector<materials::Material> materials_; // by deck index; the method gets a copy
  ParticleStore store_;
  ParticleFields<Dim> f_;
  Field<std::int32_t> cost_; // neighbors per particle: the load-balancing cost
  std::unique_ptr<parallel::Decomposition<Dim>> decomposition_;
  std::unique_ptr<methods::Method<Dim>> method_;
  std::unique_ptr<diagnostics::Probes<Dim>> probes_;
  std::unique_ptr<diagnostics::PenetrationGauge<Dim>> penetration_; // with [penetration]
  double lastPenetrationTime_ = -1.0; // a snapshot at a history row's time adds no second row
  std::vector<BodySummary> bodies_;
  std::vector<char> waiting_; // by body: its insert_time has not come yet (checkpointed)
  std::size_t totalParticles_ = 0;
  RunLog* log_ = nullptr;
  std::vector<std::string> outputFields_;
  std::vector<std::string> deferredWarnings_;
  std::vector<std::string> loggedWarnings_;
  std::vector<std::pair<double, std::string>> series_;
  io::CsvLog history_, probesCsv_, fragmentsCsv_, penetrationCsv_;
  std::unique_ptr<ParticleRecorder<Dim>> recorder_;
  std::filesystem::path dir_;
  diagnostics::Totals totals0_, last_;
  double time_ = 0.0;
  double nextSnapshotTime_ = 0.0;
  std::int64_t step_ = 0;
  std::int64_t lastSnapshotStep_ = -1;
  int snapshotIndex_ = 0;
  std::size_t baselineRss_ = 0;
  // Restart chain bookkeeping.
  std::string resumedFrom_;                 // checkpoint this run continued from ("" for a new run)
  std::vector<std::string> restartChanges_; // the waiting bodies' keys that differ from it
  double resumeDt_ = 0.0;      // the time step the checkpointed run would have taken next
  double wallOffset_ = 0.0;    // wall seconds of the chain before this job
  std::int64_t startStep_ = 0; // first step of this job
  std::int64_t lastCheckpointStep_ = -1;
  Clock::time_point lastCheckpointWall_;
  Clock::time_point runStart_ = Clock::now();
  int checkpointsWritten_ = 0, checkpointRanks_ = 0;
  std::uint64_t checkpointBytes_ = 0, checkpointWriteBytes_ = 0, checkpointReadBytes_ = 0;
  double checkpointWriteSeconds_ = 0.0, checkpointReadSeconds_ = 0.0;
  // The state to rewind to when a step fails (RunFailure.cpp).
  struct RescuePoint {
    ParticleStore::RowsCopy rows;
    io::CheckpointState state;
    double time = 0.0;
    std::int64_t step = 0;
    bool valid = false;
  } rescue_;
  std::deque<double> recentDt_;
  bool energyDue_ = false; // a history row was written this step: its energy is to be judged
  bool dtLow_ = false;
  int dtWarnings_ = 0;
};

} // namespace spall::app
