#include "Simulation.hpp"

#include "spall/app/Setup.hpp"
#include "spall/app/StopSignals.hpp"
#include "spall/app/SystemInfo.hpp"
#include "spall/io/Xdmf.hpp"
#include "spall/methods/MpmMethod.hpp"
#include "spall/methods/SphMethod.hpp"

#include <cmath>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <fstream>
#include <limits>
#include <numbers>
#include <sstream>

// Set-up, a new run, a restart, the run's state in a checkpoint, and the run loop.
namespace spall::app {

namespace fs = std::filesystem;

template <int Dim>
Simulation<Dim>::Simulation(const Deck& deck, const parallel::MpiContext& mpi)
    : deck_(deck), mpi_(mpi), materials_(buildMaterials(deck)) {
  for (const auto& b : deck.bodies) waiting_.push_back(b.insert_time > 0.0 ? 1 : 0);
  baselineRss_ = residentBytes();
  // The modules register their fields, in list order (strength fields only where a deck has a
  // solid, and so on).
  auto modules = buildModules<Dim>(deck);
  for (const auto& m : modules) m->registerFields(store_, f_);
  // Neighbors per particle from the last search: the load-balancing cost. Migrates, never
  // written. Checkpointed: a restart on the same rank count then rebalances exactly as the run
  // would have.
  cost_ = store_.add<std::int32_t>("cost", kCheckpoint);
  if (deck.fragments) f_.fragment = store_.add<std::int64_t>("fragment", kOutput);
  parallel::DecompositionConfig dc;
  dc.curve = deck.decomposition.curve == CurveType::Morton ? parallel::Curve::Morton
                                                           : parallel::Curve::Hilbert;
  dc.metis = deck.decomposition.partitioner == Partitioner::Metis;
  dc.rebalanceEvery = deck.decomposition.rebalance_every;
  dc.imbalanceThreshold = deck.decomposition.imbalance_threshold;
  decomposition_ =
      std::make_unique<parallel::Decomposition<Dim>>(mpi.comm(), dc, f_.id, f_.x, cost_);
  methods::MethodSetup setup = methodSetup(deck);
  if (deck.solver.method == SolverMethod::Mpm && fieldPerBody(deck.solver.contact))
    warnThinBodies(setup.solver.mpm.cell_size);
  setup.note = [this](const std::string& line) {
    if (log_) log_->note(line);
  };
  materials::MaterialUpdate update(materials_, deck_.run.seed);
  if (deck.solver.method == SolverMethod::Mpm)
    method_ = std::make_unique<methods::MpmMethod<Dim>>(mpi, std::move(setup), std::move(update),
                                                        std::move(modules), store_, f_, cost_,
                                                        *decomposition_);
  else
    method_ = std::make_unique<methods::SphMethod<Dim>>(mpi, std::move(setup), std::move(update),
                                                        std::move(modules), store_, f_, cost_,
                                                        *decomposition_);
  probes_ = std::make_unique<diagnostics::Probes<Dim>>(deck.probes, store_,
                                                       deck.run.geometry == Geometry::RZ);
  if (const auto& pc = deck.penetration) {
    std::vector<char> penetrator(deck.bodies.size(), 0);
    for (std::size_t b = 0; b < deck.bodies.size(); ++b)
      penetrator[b] = std::find(pc->penetrator.begin(), pc->penetrator.end(),
                                deck.bodies[b].name) != pc->penetrator.end();
    Vec<Dim> surface, direction;
    for (int d = 0; d < Dim; ++d) {
      surface[d] = pc->surface[static_cast<std::size_t>(d)];
      direction[d] = pc->direction[static_cast<std::size_t>(d)];
    }
    penetration_ = std::make_unique<diagnostics::PenetrationGauge<Dim>>(
        std::move(penetrator), surface, direction, method_->support());
  }
  resolveOutputFields();
  // Keys of SPH's pair loop in an MPM deck (a shipped deck run with --set solver.method=mpm).
  if (const auto& keys = deck_.solver.sphOnlyKeys; !keys.empty())
    deferredWarnings_.push_back(fmt::format(
        "{}:{}: solver.{} act on SPH's pair loop and do nothing with method \"mpm\" (its "
        "shock viscosity: solver.mpm.viscosity; decks/topics/mpm.md)",
        deck_.solver.where.file, deck_.solver.where.line, fmt::join(keys, ", solver.")));
  // ASPH's keys in an SPH deck: SPH's smoothing lengths are scalars.
  if (const auto& keys = deck_.solver.asphOnlyKeys; !keys.empty())
    deferredWarnings_.push_back(fmt::format(
        "{}:{}: solver.{} act on ASPH's smoothing tensors and do nothing with method \"sph\" "
        "(set method = \"asph\")",
        deck_.solver.where.file, deck_.solver.where.line, fmt::join(keys, ", solver.")));
  // ASPH in bins: hypervelocity impacts with strength over-compress (decks/topics/solids.md).
  if (deck_.solver.time_bins > 1 && deck_.solver.method == SolverMethod::Asph)
    deferredWarnings_.push_back(fmt::format(
        "{}:{}: solver.time_bins with method \"asph\": in the stability matrix's impacts above "
        "5 km/s with strength ASPH's particles in bins over-compress (up to 3.4 rho0 against "
        "1.7, energy off by 1e-2 against 1e-5 with one step for all); SPH keeps them "
        "(decks/topics/solids.md, \"Time bins\")",
        deck_.solver.where.file, deck_.solver.where.line));
  // With the plain SPH velocity gradient a solid's strain rate under-reads where the support is
  // cut, and a confined body settles with stresses off the load (decks/README.md). MPM's
  // gradient is the grid's: no such key.
  for (const auto& b : deck_.boundaries)
    if (deck_.solver.method != SolverMethod::Mpm && b.type == BoundaryType::Pressure &&
        !deck_
             .materials[static_cast<std::size_t>(
                 deck_.bodies[static_cast<std::size_t>(b.bodyIndex)].material_index)]
             .strength.none() &&
        deck_.solver.velocity_gradient != VelocityGradient::Corrected)
      deferredWarnings_.push_back(fmt::format(
          "{}:{}: body '{}' has strength and a pressure boundary, but solver.velocity_gradient "
          "is not \"corrected\": it will settle with its stresses off the load, by up to 40% "
          "at the surface (decks/topics/confining-pressure.md)",
          b.where.file, b.where.line, b.body));
}

template <int Dim> void Simulation<Dim>::generate() {
  bodies_ = generateBodies<Dim>(deck_, materials_, store_, f_);
  applyEnergySources<Dim>(deck_, store_, f_);
  decomposition_->distributeInitial(store_);
  totalParticles_ = mpi_.sum(static_cast<std::uint64_t>(store_.localCount()));
  std::vector<std::uint64_t> bodyParticles;
  for (const auto& b : bodies_) bodyParticles.push_back(b.particles);
  method_->start({bodyParticles});
}

// A continued run: the first of `candidates` that reads back completely. Throws
// CheckpointError when none does, UsageError when the checkpoint belongs to another deck.
template <int Dim> void Simulation<Dim>::resume(const RestartCandidates& candidates) {
  if (candidates.files.empty())
    throw io::CheckpointError(
        candidates.problem.empty()
            ? "no checkpoint to restart from"
            : fmt::format("cannot restart: {} and there is no complete checkpoint beside it",
                          candidates.problem));
  if (!candidates.problem.empty())
    deferredWarnings_.push_back(candidates.problem + "; falling back to the newest complete "
                                                     "checkpoint");
  std::string skipped;
  for (std::size_t k = 0; k < candidates.files.size(); ++k) {
    const std::string path = candidates.files[k].string();
    try {
      const auto t0 = Clock::now();
      const io::CheckpointHeader header = io::readCheckpointHeader(mpi_.comm(), path);
      if (header.dimension != Dim)
        throw UsageError(
            fmt::format("{} holds a {}D run; the deck is {}D", path, header.dimension, Dim));
      const std::string before = header.state.text("deck");
      const auto w = header.state.integers.find("bodies_waiting");
      const auto free = w == header.state.integers.end()
                            ? std::vector<std::string>()
                            : restartFreeTables(before, deck_, w->second, header.time);
      restartChanges_.clear();
      const auto diffs =
          deckPhysicsDifferences(before, deck_.resolved_toml, free, &restartChanges_);
      if (!diffs.empty()) {
        std::string list;
        for (std::size_t d = 0; d < diffs.size() && d < 12; ++d) list += "\n  " + diffs[d];
        if (diffs.size() > 12) list += fmt::format("\n  ... and {} more", diffs.size() - 12);
        throw UsageError(fmt::format(
            "{} was written by a different deck; a restart may change only run.end_time, "
            "run.max_steps, run.title, the [output], [checkpoint], [decomposition], "
            "[fragments] and [penetration] tables, and the bodies that have not joined yet "
            "with the materials only they use:{}",
            path, list));
      }
      const bool sameLayout =
          static_cast<int>(header.rankCounts.size()) == mpi_.size() &&
          header.state.text("decomposition_curve") == kCurveNames(deck_.decomposition.curve) &&
          header.state.text("decomposition_partitioner") ==
              kPartitionerNames(deck_.decomposition.partitioner);
      const std::uint64_t bytes =
          io::readCheckpointParticles(mpi_.comm(), header, store_, sameLayout);
      restoreState(header, sameLayout);
      summarizeWaitingBodies();
      checkpointReadSeconds_ = std::chrono::duration<double>(Clock::now() - t0).count();
      checkpointReadBytes_ = mpi_.sum(bytes);
      resumedFrom_ = path;
      if (!skipped.empty())
        deferredWarnings_.push_back(fmt::format("skipped unusable checkpoints:{}", skipped));
      return;
    } catch (const io::CheckpointError& e) {
      if (!candidates.fallback) throw;
      skipped += fmt::format("\n  {}", e.what());
      if (k + 1 == candidates.files.size())
        throw io::CheckpointError(fmt::format(
            "cannot restart: no complete checkpoint in {}{}{}",
            candidates.files.front().parent_path().string(),
            candidates.problem.empty() ? "" : " (" + candidates.problem + ")", skipped));
    }
  }
}

// A restart's bodies that have not joined yet are the deck's now (restartFreeTables): their
// count, mass and spacing made afresh, as a new run makes them. Ids number the bodies in deck
// order, so a joined body after a waiting one keeps its ids only while that one's count stands.
template <int Dim> void Simulation<Dim>::summarizeWaitingBodies() {
  const std::size_t rows = store_.localCount();
  ParticleId firstBefore = 0, firstNow = 0;
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    const std::size_t before = bodies_[b].particles;
    if (waiting_[b]) {
      bodies_[b] = insertBody<Dim>(deck_, materials_, b, firstNow, store_, f_);
      store_.resizeLocal(rows);
    } else if (firstNow != firstBefore) {
      throw UsageError(fmt::format(
          "body '{}' joined the run before the checkpoint with ids from {}; the bodies that "
          "have not joined yet listed before it now have {} particles, not {}, which would "
          "number it from {}: list the bodies that join later after those present",
          bodies_[b].name, firstBefore, firstNow, firstBefore, firstNow));
    }
    firstBefore += before;
    firstNow += bodies_[b].particles;
  }
}

template <int Dim> std::size_t Simulation<Dim>::memoryEstimate() const {
  const double neighbors =
      std::pow(2.0 * 2.0 * deck_.solver.nodes_per_h, Dim) * (Dim == 3   ? std::numbers::pi / 6.0
                                                             : Dim == 2 ? std::numbers::pi / 4.0
                                                                        : 1.0);
  const double perParticle =
      1.1 * static_cast<double>(store_.bytesPerParticle()) + 4.0 * neighbors + 16.0;
  return static_cast<std::size_t>(perParticle * static_cast<double>(particles()));
}

template <int Dim> double Simulation<Dim>::firstTimeStep() const {
  // MPM's limit needs no force evaluation: the method's own (collective, as here).
  if (deck_.solver.method == SolverMethod::Mpm) return method_->stableTimeStep(0.0, 0, 0.0);
  const auto h = store_[f_.h];
  const auto cs = store_[f_.cs];
  const auto v = store_[f_.v];
  double dt = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < store_.localCount(); ++i) {
    const double signal = cs[i] + v[i].norm(); // before any force: sound and bulk speed
    if (signal > 0.0) dt = std::min(dt, h[i] / signal);
  }
  return mpi_.min(deck_.solver.cfl * dt);
}

// Everything besides the particle fields that the run needs to continue exactly: identical
// on every rank (the checkpoint writer stores rank 0's copy).
template <int Dim>
io::CheckpointState Simulation<Dim>::saveState(double dtNext, double wall) const {
  io::CheckpointState st;
  st.texts["deck"] = deck_.resolved_toml;
  st.reals["dt"] = {dtNext};
  st.reals["wall_seconds"] = {wall};
  st.reals["next_snapshot_time"] = {nextSnapshotTime_};
  const auto& t = totals0_;
  st.reals["initial_totals"] = {
      t.mass,     t.momentum[0],      t.momentum[1],      t.momentum[2],     t.kinetic,
      t.internal, t.momentumScale[0], t.momentumScale[1], t.momentumScale[2]};
  st.integers["snapshot_index"] = {snapshotIndex_};
  st.integers["last_snapshot_step"] = {lastSnapshotStep_};
  std::vector<double> times;
  std::string files;
  for (const auto& [time, file] : series_) {
    times.push_back(time);
    files += file + "\n";
  }
  st.reals["snapshot_times"] = times;
  st.texts["snapshot_files"] = files;
  std::vector<std::int64_t> bodyParticles;
  std::vector<double> bodyMass, bodySpacing;
  for (const auto& b : bodies_) {
    bodyParticles.push_back(static_cast<std::int64_t>(b.particles));
    bodyMass.push_back(b.mass);
    bodySpacing.push_back(b.spacing);
  }
  st.integers["body_particles"] = bodyParticles;
  st.reals["body_mass"] = bodyMass;
  st.reals["body_spacing"] = bodySpacing;
  st.unsignedIntegers["probe_particles"] = probes_->tracked();
  // Random numbers are counter-based (a hash of seed, particle id and stream), so the seed is
  // the whole random state: nothing advances while the run steps.
  st.integers["random_seed"] = {static_cast<std::int64_t>(deck_.run.seed)};
  const auto d = decomposition_->state();
  st.reals["decomposition_box"] = d.box;
  st.unsignedIntegers["decomposition_begins"] = d.begins;
  st.integers["decomposition_owners"] = d.owners;
  st.texts["decomposition_curve"] = std::string(kCurveNames(deck_.decomposition.curve));
  st.texts["decomposition_partitioner"] =
      std::string(kPartitionerNames(deck_.decomposition.partitioner));
  st.integers["bodies_waiting"] = std::vector<std::int64_t>(waiting_.begin(), waiting_.end());
  if (penetration_) penetration_->save(st);
  method_->save(st);
  return st;
}

template <int Dim>
void Simulation<Dim>::restoreState(const io::CheckpointHeader& h, bool sameLayout) {
  const auto& st = h.state;
  time_ = h.time;
  step_ = h.step;
  resumeDt_ = st.real("dt");
  wallOffset_ = st.real("wall_seconds");
  nextSnapshotTime_ = st.real("next_snapshot_time");
  const auto& t = st.realArray("initial_totals");
  if (t.size() != 9)
    throw io::CheckpointError(h.path + ": state/initial_totals has the wrong size");
  totals0_.mass = t[0];
  for (int d = 0; d < 3; ++d) {
    totals0_.momentum[static_cast<std::size_t>(d)] = t[1 + static_cast<std::size_t>(d)];
    totals0_.momentumScale[static_cast<std::size_t>(d)] = t[6 + static_cast<std::size_t>(d)];
  }
  totals0_.kinetic = t[4];
  totals0_.internal = t[5];
  snapshotIndex_ = static_cast<int>(st.integer("snapshot_index"));
  lastSnapshotStep_ = st.integer("last_snapshot_step");
  const auto& times = st.realArray("snapshot_times");
  std::istringstream files(st.text("snapshot_files"));
  series_.clear();
  std::string file;
  for (double time : times) {
    if (!std::getline(files, file))
      throw io::CheckpointError(h.path + ": state/snapshot_files is shorter than snapshot_times");
    series_.emplace_back(time, file);
  }
  const auto& bp = st.integerArray("body_particles");
  const auto& bm = st.realArray("body_mass");
  const auto& bs = st.realArray("body_spacing");
  if (bp.size() != deck_.bodies.size() || bm.size() != bp.size() || bs.size() != bp.size())
    throw io::CheckpointError(h.path + ": state/body_* do not match the deck's bodies");
  bodies_.clear();
  for (std::size_t b = 0; b < bp.size(); ++b)
    bodies_.push_back({deck_.bodies[b].name, static_cast<std::size_t>(bp[b]), bm[b], bs[b]});
  const auto& probes = st.unsignedArray("probe_particles");
  if (probes.size() != probes_->size())
    throw io::CheckpointError(h.path + ": state/probe_particles does not match the deck's probes");
  probes_->restoreTracked(probes);
  if (const auto w = st.integers.find("bodies_waiting"); w != st.integers.end()) {
    if (w->second.size() != deck_.bodies.size())
      throw io::CheckpointError(h.path + ": state/bodies_waiting does not match the deck's bodies");
    waiting_.assign(w->second.begin(), w->second.end());
  } else {
    // Written before bodies could wait: every body was there from t = 0.
    waiting_.assign(deck_.bodies.size(), 0);
  }
  if (penetration_) penetration_->restore(st);
  lastPenetrationTime_ = time_; // its row was written before the checkpoint
  method_->restore(st);
  checkpointRanks_ = static_cast<int>(h.rankCounts.size());
  totalParticles_ = h.particles;
  lastCheckpointStep_ = step_;
  if (sameLayout) {
    try {
      decomposition_->restore({st.realArray("decomposition_box"),
                               st.unsignedArray("decomposition_begins"),
                               st.integerArray("decomposition_owners")});
    } catch (const std::invalid_argument& e) {
      throw io::CheckpointError(h.path + ": " + e.what());
    }
  } else {
    decomposition_->distributeLoaded(store_);
  }
}

// ---- the run loop: time, output and checkpoint triggers, signals ----------------------------

template <int Dim> void Simulation<Dim>::run(const RunOptions& options, const fs::path& dir) {
  runStart_ = Clock::now();
  try {
    runSteps(options, dir);
  } catch (const RunError& e) {
    // Best effort: the failure's own message stands whatever happens here.
    if (mpi_.root() && !dir_.empty() && fs::is_directory(dir_)) {
      try {
        writeFailureSummary(options, e.what());
        std::ofstream(dir_ / "run.log", std::ios::app) << "error: " << e.what() << "\n";
      } catch (const std::exception&) {
      }
    }
    throw;
  }
}

template <int Dim> void Simulation<Dim>::runSteps(const RunOptions& options, const fs::path& dir) {
  RunLog log(mpi_.root() && !options.quiet, deck_.output.progress_seconds,
             deck_.output.progress_percent, mpi_.root());
  log_ = &log;
  const auto wall0 = Clock::now();
  for (const auto& w : loggedWarnings_) log.record(w);
  for (const auto& w : deferredWarnings_) log.warning(w);
  banner(log, dir);
  dir_ = dir;
  const bool resumed = !resumedFrom_.empty();
  openLogs(dir, resumed, log);
  if (recorder_) recorder_->open(dir, resumed, time_, store_, f_, mpi_);
  if (resumed)
    log.note(fmt::format(
        "restarted from {} at step {} (t = {:.6g} s){}; {:.1f} MB read in {:.2f} s", resumedFrom_,
        step_, time_,
        checkpointRanks_ == mpi_.size() ? ""
                                        : fmt::format(", written on {} rank{}", checkpointRanks_,
                                                      checkpointRanks_ > 1 ? "s" : ""),
        checkpointReadBytes_ / 1e6, checkpointReadSeconds_));
  if (resumed && !restartChanges_.empty())
    log.note(fmt::format("the bodies that had not joined the run differ from the checkpoint's "
                         "deck:\n  {}",
                         fmt::join(restartChanges_, "\n  ")));

  StopSignals signals;
  double dt = 0.0;
  startStep_ = step_;
  const double end = deck_.run.end_time;
  int stopSignal = 0;
  // A failed step (StepFailure, the same on every rank) is explained by explainFailure.
  try {
    if (resumed) {
      // The rates and the time step of the checkpointed step: no evaluation here, so the run
      // continues exactly as the uninterrupted one.
      dt = resumeDt_;
      last_ = diagnostics::computeTotals(store_, f_, mpi_);
    } else {
      probes_->attach(store_, f_, mpi_);
      method_->evaluate(step_, time_);
      dt = nextTimeStep();
      totals0_ = diagnostics::computeTotals(store_, f_, mpi_);
      record(0.0, 0, wall0);
      writeSnapshot();
    }
    lastCheckpointWall_ = wall0;
    if (resumed && !(time_ < end * (1.0 - 1e-12) && step_ < deck_.run.max_steps))
      log.note(fmt::format("the checkpoint is at the end of this run (t = {:.6g} s, step {}): "
                           "nothing to do; extend it with --set run.end_time=...",
                           time_, step_));
    keepRescuePoint(dt, wall0);
    while (time_ < end * (1.0 - 1e-12) && step_ < deck_.run.max_steps) {
      dt = stepOnce(dt, wall0, false);
      watchTimeStep(dt);
      watchEnergy(dt);
      const double wall = std::chrono::duration<double>(Clock::now() - wall0).count();
      log.progress(step_, time_, end, dt, particles(), wall,
                   mpi_.size() > 1 ? fmt::format("  imbalance {:.2f}", method_->stats().imbalance)
                                   : "");
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
      if (deck_.output.failure_history > 0 && step_ % deck_.output.failure_history == 0)
        keepRescuePoint(dt, wall0);
    }
  } catch (const StepFailure& failure) {
    try {
      explainFailure(failure, wall0);
    } catch (...) {
      log_ = nullptr;
      throw;
    }
  }
  if (!stopSignal) {
    if (lastSnapshotStep_ != step_) writeSnapshot();
    // The end of a run is a checkpoint too: a chain extends it with a later end time.
    if (lastCheckpointStep_ != step_) checkpoint(dt, wall0);
  }
  history_.flush();
  probesCsv_.flush();
  penetrationCsv_.flush();
  finish(log, options, wall0, stopSignal);
  log_ = nullptr;
}

// One step of the loop: advance, the snapshot due at the new time, the next stable dt. A replay
// (RunFailure.cpp) steps again through steps already logged: no history rows.
template <int Dim>
double Simulation<Dim>::stepOnce(double dt, Clock::time_point wall0, bool replay) {
  const auto [dtClamped, timeAfter] = clampToTargets(dt);
  const double dtStep = method_->advance(dtClamped, step_, time_);
  time_ = dtStep == dtClamped ? timeAfter : time_ + dtStep;
  ++step_;
  insertDueBodies();
  if (!replay) record(dtStep, step_, wall0);
  if (snapshotDue()) writeSnapshot(!replay);
  return nextTimeStep();
}

// The method's stable step; a step below kCollapse of the end time is a collapse.
template <int Dim> double Simulation<Dim>::nextTimeStep() {
  return method_->stableTimeStep(kCollapse * deck_.run.end_time, step_, time_);
}

// Shortens dt so that snapshot times and the end time are hit exactly; splits the last two
// steps before a target evenly rather than leaving a sliver. Returns the step and the time after
// it: a step that ends on a target ends on it exactly (time + (target - time) can miss it by an
// ulp), so that a chain whose end time is an output time of a longer run takes that run's
// steps from there bit for bit.
template <int Dim> std::pair<double, double> Simulation<Dim>::clampToTargets(double dt) const {
  double target = deck_.run.end_time;
  // An end time that is an output time (k every, which may be an ulp off the deck's literal)
  // ends where a longer run's snapshot lands, so that the chain extending it takes that run's
  // steps.
  if (deck_.output.every > 0.0)
    target = std::abs(nextSnapshotTime_ - target) <= 1e-12 * target
                 ? nextSnapshotTime_
                 : std::min(target, nextSnapshotTime_);
  for (std::size_t b = 0; b < waiting_.size(); ++b)
    if (waiting_[b]) target = std::min(target, deck_.bodies[b].insert_time);
  const double left = target - time_;
  if (left <= 0.0) return {dt, time_ + dt};
  if (dt >= left) return {left, target};
  if (1.5 * dt > left) return {0.5 * left, time_ + 0.5 * left};
  return {dt, time_ + dt};
}

// Bodies whose insert_time has come join the run (the step before was shortened to end on it):
// made on rank 0 with their t = 0 ids, given their modules' initial values, sent to their
// owners; then the rates of the whole state again, so that the next step starts from forces that
// include them. The reference of the conserved totals grows by what they bring.
template <int Dim> void Simulation<Dim>::insertDueBodies() {
  std::vector<std::size_t> due;
  for (std::size_t b = 0; b < waiting_.size(); ++b)
    if (waiting_[b] && deck_.bodies[b].joinedBy(time_)) due.push_back(b);
  if (due.empty()) return;
  const diagnostics::Totals before = diagnostics::computeTotals(store_, f_, mpi_);
  const std::size_t first = store_.localCount();
  std::vector<std::uint64_t> bodyParticles;
  for (const auto& b : bodies_) bodyParticles.push_back(b.particles);
  for (const std::size_t b : due) {
    waiting_[b] = 0;
    if (!mpi_.root()) continue;
    ParticleId firstId = 0;
    for (std::size_t o = 0; o < b; ++o) firstId += bodyParticles[o];
    insertBody<Dim>(deck_, materials_, b, firstId, store_, f_);
  }
  method_->start({bodyParticles, first});
  decomposition_->migrate(store_, step_);
  method_->evaluate(step_, time_);
  totalParticles_ = mpi_.sum(static_cast<std::uint64_t>(store_.localCount()));
  const diagnostics::Totals after = diagnostics::computeTotals(store_, f_, mpi_);
  totals0_.mass += after.mass - before.mass;
  for (std::size_t d = 0; d < 3; ++d) {
    totals0_.momentum[d] += after.momentum[d] - before.momentum[d];
    totals0_.momentumScale[d] += after.momentumScale[d] - before.momentumScale[d];
  }
  totals0_.kinetic += after.kinetic - before.kinetic;
  totals0_.internal += after.internal - before.internal;
  if (log_)
    for (const std::size_t b : due)
      log_->note(fmt::format("t = {:.6g} s (step {}): body '{}' joins the run, {} particles", time_,
                             step_, bodies_[b].name, bodies_[b].particles));
}

// Writes ckpt_<step>.h5 (atomically), then points `latest` at it, then prunes old ones. The
// logs are flushed first, so every row up to this step is on disk before the checkpoint is.
template <int Dim> void Simulation<Dim>::checkpoint(double dtNext, Clock::time_point wall0) {
  method_->stats().phases.time(methods::kCheckpoint, [&] {
    history_.flush();
    probesCsv_.flush();
    penetrationCsv_.flush();
    const std::string name = checkpointFileName(step_);
    const fs::path ckDir = dir_ / "checkpoints";
    // Every rank must write the same state (each writes its checksums; rank 0 the values): the
    // wall time as the slowest rank's. A rank's own clock here corrupted 3-rank checkpoints.
    const double wall = mpi_.max(std::chrono::duration<double>(Clock::now() - wall0).count());
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
