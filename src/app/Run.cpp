#include "spall/app/Run.hpp"

#include "spall/app/BodyGenerator.hpp"
#include "spall/app/CheckpointFiles.hpp"
#include "spall/app/RunLog.hpp"
#include "spall/app/StopSignals.hpp"
#include "spall/app/SystemInfo.hpp"
#include "spall/diagnostics/Conservation.hpp"
#include "spall/diagnostics/Probes.hpp"
#include "spall/io/Checkpoint.hpp"
#include "spall/io/CsvLog.hpp"
#include "spall/io/Snapshot.hpp"
#include "spall/io/Xdmf.hpp"
#include "spall/neighbors/NeighborList.hpp"
#include "spall/parallel/Decomposition.hpp"
#include "spall/parallel/HaloExchange.hpp"
#include "spall/solvers/Boundaries.hpp"
#include "spall/solvers/SphSolver.hpp"

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <limits>
#include <numbers>
#include <sstream>

namespace spall::app {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

std::vector<materials::Eos> buildEos(const Deck& deck) {
  std::vector<materials::Eos> eos;
  for (const auto& m : deck.materials) {
    const auto& c = m.eos;
    if (c.type == "ideal_gas")
      eos.emplace_back(materials::IdealGas{c.gamma});
    else if (c.type == "linear")
      eos.emplace_back(materials::LinearEos{m.density, c.bulk_modulus});
    else if (c.type == "mie_gruneisen")
      eos.emplace_back(materials::MieGruneisen{m.density, c.c0, c.s, c.gamma0});
    else
      eos.emplace_back(materials::Tillotson{m.density, c.a, c.b, c.A, c.B, c.alpha, c.beta, c.e0,
                                            c.e_iv, c.e_cv});
  }
  return eos;
}

std::vector<std::optional<materials::Strength>> buildStrength(const Deck& deck) {
  std::vector<std::optional<materials::Strength>> out;
  for (const auto& m : deck.materials) {
    const auto& c = m.strength;
    if (c.type == "elastic")
      out.emplace_back(materials::Elastic{c.shear_modulus});
    else if (c.type == "von_mises")
      out.emplace_back(materials::VonMises{c.shear_modulus, c.yield_stress});
    else if (c.type == "johnson_cook")
      out.emplace_back(materials::JohnsonCook{
          c.shear_modulus, c.A, c.B, c.n, c.C, c.m, c.reference_strain_rate, c.room_temperature,
          c.melt_temperature, c.specific_heat, c.taylor_quinney});
    else
      out.emplace_back(std::nullopt);
  }
  return out;
}

const char* kernelName(KernelType k) {
  switch (k) {
  case KernelType::CubicSpline:
    return "cubic_spline";
  case KernelType::WendlandC2:
    return "wendland_c2";
  case KernelType::WendlandC4:
    return "wendland_c4";
  }
  return "?";
}
const char* densityName(DensityMethod d) {
  switch (d) {
  case DensityMethod::Continuity:
    return "continuity";
  case DensityMethod::Summation:
    return "summation";
  case DensityMethod::NormalizedSummation:
    return "normalized_summation";
  }
  return "?";
}

// Wall time by phase, for the closing summary and tools/bench.
struct Phases {
  double neighbors = 0, density = 0, forces = 0, integration = 0, boundaries = 0, exchange = 0,
         output = 0, checkpoint = 0;
  template <class F> static void time(double& slot, F&& f) {
    const auto t0 = Clock::now();
    f();
    slot += std::chrono::duration<double>(Clock::now() - t0).count();
  }
};

// Everything a run of one dimension holds.
template <int Dim> class Simulation {
public:
  Simulation(const Deck& deck, const parallel::MpiContext& mpi)
      : deck_(deck), mpi_(mpi), eos_(buildEos(deck)), strength_(buildStrength(deck)) {
    for (const auto& b : deck.bodies) {
      if (b.insert_time > 0.0)
        throw DeckError(b.where, fmt::format("body '{}': insert_time arrives with the penetration "
                                             "work and is not available yet",
                                             b.name));
    }
    baselineRss_ = residentBytes();
    // Strength fields and the deviatoric work only where a deck has a solid.
    const bool solids = std::any_of(strength_.begin(), strength_.end(),
                                    [](const auto& s) { return s.has_value(); });
    f_.registerIn(store_, deck.solver.artificial_viscosity.balsara, solids,
                  solids && deck.solver.velocity_gradient == VelocityGradient::Corrected,
                  deck.solver.method == "asph");
    if (!solids && (deck.solver.artificial_stress.enabled ||
                    deck.solver.velocity_gradient != VelocityGradient::Sph))
      throw DeckError(deck.solver.where,
                      "solver.artificial_stress and solver.velocity_gradient act on the stress of "
                      "materials with strength, and no material in this deck has one");
    for (std::size_t b = 0; b < deck.bodies.size(); ++b)
      if (deck.bodies[b].fixed) fixedBodies_.push_back(static_cast<std::int32_t>(b));
    // Neighbors per particle from the last search: the load-balancing cost. Migrates, never
    // written.
    // Checkpointed: a restart on the same rank count then rebalances exactly as the run would have.
    cost_ = store_.add<std::int32_t>("cost", kCheckpoint);
    parallel::DecompositionConfig dc;
    dc.curve =
        deck.decomposition.curve == "morton" ? parallel::Curve::Morton : parallel::Curve::Hilbert;
    dc.metis = deck.decomposition.partitioner == "metis";
    dc.rebalanceEvery = deck.decomposition.rebalance_every;
    dc.imbalanceThreshold = deck.decomposition.imbalance_threshold;
    decomposition_ =
        std::make_unique<parallel::Decomposition<Dim>>(mpi.comm(), dc, f_.id, f_.x, cost_);
    solver_ = solvers::makeSolver<Dim>({deck.solver, eos_, strength_}, store_, f_);
    boundaries_ = std::make_unique<solvers::Boundaries<Dim>>(deck.boundaries, f_);
    halo_ = std::make_unique<parallel::HaloExchange<Dim>>(mpi.comm(), boundaries_->periodicAxes());
    // What the neighbor search, the density sum and the force loop read of a ghost; after the
    // summation density only rho and the EOS's p and cs change.
    for (std::size_t c : {f_.id.index, f_.x.index, f_.v.index, f_.m.index, f_.h.index, f_.rho.index,
                          f_.p.index, f_.cs.index, f_.material.index})
      haloFields_.push_back(c);
    if (f_.anisotropic()) haloFields_.push_back(f_.H.index);
    if (f_.divv.valid())
      haloFields_.push_back(f_.divv.index), haloFields_.push_back(f_.curlv.index);
    if (f_.hasStrength()) haloFields_.push_back(f_.S.index); // the force loop reads S_j
    if (deck.solver.contact == Contact::Frictionless) haloFields_.push_back(f_.body.index);
    refreshFields_ = {f_.rho.index, f_.p.index, f_.cs.index};
    probes_ = std::make_unique<diagnostics::Probes<Dim>>(deck.probes);
    resolveOutputFields();
  }

  // A new run: every rank generates the same particles (ids, jitter and energy deposits
  // therefore do not depend on the rank count), keeps a slice and hands the rest to their owners.
  void generate() {
    bodies_ = generateBodies<Dim>(deck_, eos_, store_, f_);
    applyEnergySources<Dim>(deck_, store_, f_);
    if (f_.anisotropic()) // round to start with: the ideal-H update finds the shape
      for (std::size_t i = 0; i < store_.localCount(); ++i)
        store_[f_.H][i] = Tensor<Dim>::Identity() / store_[f_.h][i];
    if (f_.hasStrength()) {
      // Unstressed at t = 0; Johnson-Cook materials start at their room temperature (the only
      // model that tracks temperature).
      const auto mat = store_[f_.material];
      const auto T = store_[f_.temperature];
      for (std::size_t i = 0; i < store_.localCount(); ++i) {
        store_[f_.S][i].setZero();
        store_[f_.L][i].setZero();
        store_[f_.plasticStrain][i] = 0.0;
        const auto& c = deck_.materials[static_cast<std::size_t>(mat[i])].strength;
        T[i] = c.type == "johnson_cook" ? c.room_temperature : 0.0;
      }
    }
    decomposition_->distributeInitial(store_);
    totalParticles_ = mpi_.sum(static_cast<std::uint64_t>(store_.localCount()));
    solver_->equationOfState();
  }

  // A continued run: the first of `candidates` that reads back completely. Throws
  // CheckpointError when none does, UsageError when the checkpoint belongs to another deck.
  void resume(const RestartCandidates& candidates) {
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
        const auto diffs = deckPhysicsDifferences(header.state.text("deck"), deck_.resolved_toml);
        if (!diffs.empty()) {
          std::string list;
          for (std::size_t d = 0; d < diffs.size() && d < 12; ++d) list += "\n  " + diffs[d];
          if (diffs.size() > 12) list += fmt::format("\n  ... and {} more", diffs.size() - 12);
          throw UsageError(fmt::format(
              "{} was written by a different deck; a restart may change only run.end_time, "
              "run.max_steps, run.title and the [output], [checkpoint] and [decomposition] "
              "tables:{}",
              path, list));
        }
        const bool sameLayout =
            static_cast<int>(header.rankCounts.size()) == mpi_.size() &&
            header.state.text("decomposition_curve") == deck_.decomposition.curve &&
            header.state.text("decomposition_partitioner") == deck_.decomposition.partitioner;
        const std::uint64_t bytes =
            io::readCheckpointParticles(mpi_.comm(), header, store_, sameLayout);
        restoreState(header, sameLayout);
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

  // All ranks' owned particles.
  std::size_t particles() const { return totalParticles_; }
  const std::vector<BodySummary>& bodies() const { return bodies_; }
  const std::vector<std::string>& warnings() const { return deferredWarnings_; }

  // A rough peak estimate: stored fields, ghosts (~10%) and neighbor indices at the target n_h.
  std::size_t memoryEstimate() const {
    const double neighbors =
        std::pow(2.0 * 2.0 * deck_.solver.nodes_per_h, Dim) * (Dim == 3   ? std::numbers::pi / 6.0
                                                               : Dim == 2 ? std::numbers::pi / 4.0
                                                                          : 1.0);
    const double perParticle =
        1.1 * static_cast<double>(store_.bytesPerParticle()) + 4.0 * neighbors + 16.0;
    return static_cast<std::size_t>(perParticle * static_cast<double>(particles()));
  }
  double firstTimeStep() const {
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

  void run(const RunOptions& options, const fs::path& dir) {
    RunLog log(mpi_.root() && !options.quiet);
    log_ = &log;
    const auto wall0 = Clock::now();
    for (const auto& w : deferredWarnings_) log.warning(w);
    banner(log, dir);
    dir_ = dir;
    const bool resumed = !resumedFrom_.empty();
    if (resumed) {
      // A chain restarted from a checkpoint in another directory lacks the earlier snapshots
      // here: series.xmf lists only what this directory holds.
      std::vector<char> keep(series_.size(), 1);
      if (mpi_.root())
        for (std::size_t k = 0; k < series_.size(); ++k)
          keep[k] = fs::exists(dir / "snapshots" / series_[k].second) ? 1 : 0;
      MPI_Bcast(keep.data(), static_cast<int>(keep.size()), MPI_CHAR, 0, mpi_.comm());
      std::size_t kept = 0;
      for (std::size_t k = 0; k < series_.size(); ++k)
        if (keep[k]) series_[kept++] = series_[k];
      if (kept < series_.size())
        log.note(fmt::format("{} earlier snapshot{} of this chain are not in {}: series.xmf "
                             "lists the ones that are",
                             series_.size() - kept, series_.size() - kept > 1 ? "s" : "",
                             (dir / "snapshots").string()));
      series_.resize(kept);
    }
    if (mpi_.root()) {
      fs::create_directories(dir / "snapshots");
      fs::create_directories(dir / "checkpoints");
      std::ofstream(dir / "deck.toml") << deck_.resolved_toml;
      const std::string historyHeader =
          "step,time,dt,particles,mass,momentum_x,momentum_y,momentum_z,kinetic_energy,"
          "internal_energy,total_energy,wall_seconds,imbalance,ghosts,migrated";
      if (resumed) {
        // Whatever a crashed run wrote after its checkpoint goes; the rest continues.
        truncateHistory(dir / "history.csv", step_);
        truncateProbes(dir / "probes.csv", time_);
        removeSnapshotsFrom(dir / "snapshots", snapshotIndex_);
        io::writeSeriesXdmf((dir / "snapshots" / "series.xmf").string(), series_);
        removeStaleTemporaries(dir / "checkpoints");
        history_ = io::CsvLog::append((dir / "history.csv").string(), historyHeader);
        if (!probes_->empty())
          probesCsv_ = io::CsvLog::append((dir / "probes.csv").string(), "time,probe,field,value");
      } else {
        history_ = io::CsvLog((dir / "history.csv").string(), historyHeader);
        if (!probes_->empty())
          probesCsv_ = io::CsvLog((dir / "probes.csv").string(), "time,probe,field,value");
      }
    }
    MPI_Barrier(mpi_.comm());
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
      evaluate();
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
      advance(dt);
      record(dt, step_, wall0);
      if (snapshotDue()) writeSnapshot();
      const double wall = std::chrono::duration<double>(Clock::now() - wall0).count();
      if (wall - lastProgress > 0.0) {
        log.progress(step_, time_, end, dt, particles(), wall,
                     mpi_.size() > 1 ? fmt::format("  imbalance {:.2f}", imbalance_) : "");
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

private:
  // ---- one force evaluation: ghosts, neighbors, density, rates -------------------------------
  void evaluate() {
    if (!solver_->usesSummationDensity()) solver_->equationOfState();
    Phases::time(phases_.exchange, [&] {
      const std::size_t n = store_.localCount();
      const auto h = store_[f_.h];
      if (f_.anisotropic()) {
        // The bounding box of the support |H x| < k: half-width k |row d of H^-1| along axis d.
        // Its enclosing sphere: k times the longest axis, h.
        const auto H = store_[f_.H];
        boxReach_.resize(n);
        reach_.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
          boxReach_[i] = solver_->support() * H[i].inverse().rowwise().norm();
          reach_[i] = solver_->support() * h[i];
        }
        halo_->build(store_, f_.x, reach_, std::span<const Vec<Dim>>(boxReach_), haloFields_);
      } else {
        reach_.resize(n);
        for (std::size_t i = 0; i < n; ++i) reach_[i] = solver_->support() * h[i];
        halo_->build(store_, f_.x, reach_, haloFields_);
      }
    });
    Phases::time(phases_.boundaries, [&] {
      double hmax = 0.0;
      for (double h : store_[f_.h]) hmax = std::max(hmax, h); // owned and remote ghosts
      boundaries_->buildGhosts(store_, solver_->support() * mpi_.max(hmax));
    });
    Phases::time(phases_.neighbors, [&] {
      // ASPH searches each support's ellipsoid (its bounding box), SPH its sphere.
      const auto H = f_.anisotropic() ? store_[f_.H] : std::span<Tensor<Dim>>{};
      const auto build = [&](const neighbors::CanonicalOrder<Dim>* order) {
        return f_.anisotropic()
                   ? neighbors::buildNeighborList<Dim>(
                         store_[f_.x], store_[f_.h], std::span<const Tensor<Dim>>(H),
                         store_.localCount(), solver_->support(), grid_, neighbors_, order)
                   : neighbors::buildNeighborList<Dim>(store_[f_.x], store_[f_.h],
                                                       store_.localCount(), solver_->support(),
                                                       grid_, neighbors_, order);
      };
      if (deck_.decomposition.reproducible) {
        const neighbors::CanonicalOrder<Dim> order{store_[f_.id], store_[f_.x], canonicalH()};
        if (!build(&order)) canonicalLost_ = true;
      } else {
        build(nullptr);
      }
      const auto cost = store_[cost_];
      for (std::size_t i = 0; i < store_.localCount(); ++i)
        cost[i] = static_cast<std::int32_t>(1 + neighbors_.offsets[i + 1] - neighbors_.offsets[i]);
    });
    pairCount_ += neighbors_.pairs();
    ++evaluations_;
    ghostCount_ = halo_->ghosts();
    if (mpi_.size() > 1 && step_ % 10 == 0) {
      // Interacting pairs whose partner lives on another rank (or is a periodic image): the
      // communication a partition causes, comparable between the SFC and METIS partitioners.
      const std::size_t lo = store_.localCount(), hi = lo + halo_->ghosts();
      std::uint64_t cut = 0;
      for (std::uint32_t j : neighbors_.indices) cut += j >= lo && j < hi;
      crossPairs_ = cut;
    }
    ghostFractionMax_ =
        std::max(ghostFractionMax_, mpi_.size() == 1 || store_.localCount() == 0
                                        ? 0.0
                                        : static_cast<double>(halo_->ghosts()) /
                                              static_cast<double>(store_.localCount()));
    if (solver_->usesSummationDensity()) {
      Phases::time(phases_.density, [&] {
        solver_->computeDensity(neighbors_);
        solver_->equationOfState();
      });
      Phases::time(phases_.exchange, [&] { halo_->refresh(store_, refreshFields_); });
      Phases::time(phases_.boundaries, [&] { boundaries_->refreshGhosts(store_); });
    }
    if (solver_->correctsKernel())
      Phases::time(phases_.forces, [&] {
        solver_->computeKernelCorrection(neighbors_);
        const std::size_t fields[] = {f_.B.index};
        halo_->refresh(store_, fields);
        boundaries_->refreshGhosts(store_, {f_.B});
      });
    Phases::time(phases_.forces, [&] {
      solver_->computeRates(neighbors_);
      holdFixedBodies();
    });
  }

  // Particles of a `fixed` body (a clamp) stay where they are: no acceleration, so the leapfrog
  // keeps their zero velocity and their position. They still carry density, stress and energy,
  // and the forces they exert on the rest are the reaction of the support.
  void holdFixedBodies() {
    if (fixedBodies_.empty()) return;
    const auto body = store_[f_.body];
    const auto a = store_[f_.a];
    for (std::size_t i = 0; i < store_.localCount(); ++i)
      if (std::binary_search(fixedBodies_.begin(), fixedBodies_.end(), body[i])) a[i].setZero();
  }

  // The geometric mean of the owned particles' h over all ranks, summed exactly (log2 h in fixed
  // point, integer allreduce): the same value on any rank count, which a canonical neighbor
  // order needs for its grid.
  double canonicalH() const {
    std::int64_t sum[2] = {0, 0};
    for (double h : store_[f_.h].first(store_.localCount())) {
      if (!(h > 0.0) || !std::isfinite(h)) continue;
      sum[0] += std::llround(std::log2(h) * 1048576.0);
      ++sum[1];
    }
    MPI_Allreduce(MPI_IN_PLACE, sum, 2, MPI_INT64_T, MPI_SUM, mpi_.comm());
    if (sum[1] == 0) return 1.0;
    return std::exp2(static_cast<double>(sum[0]) / 1048576.0 / static_cast<double>(sum[1]));
  }

  // ---- kick-drift-kick leapfrog ------------------------------------------------------------
  // v_{n+1/2} = v_n + dt/2 a_n; x_{n+1} = x_n + dt v_{n+1/2}; v_{n+1} = v_{n+1/2} + dt/2 a_{n+1}
  // (Lam et al. 2001, Sec. 4.2, in its kick-drift-kick form), with e and, for the continuity
  // density, rho advanced the same way. The second half-kick is taken first with the old rates
  // (a prediction for the force evaluation) and then corrected by dt/2 (new - old).
  void advance(double dt) {
    const bool continuity = !solver_->usesSummationDensity();
    Phases::time(phases_.integration, [&] {
      auto x = store_[f_.x];
      auto v = store_[f_.v];
      auto e = store_[f_.e];
      auto rho = store_[f_.rho];
      const auto a = store_[f_.a];
      const auto dedt = store_[f_.dedt];
      const auto drhodt = store_[f_.drhodt];
      const std::size_t n = store_.localCount();
      for (std::size_t i = 0; i < n; ++i) {
        x[i] += dt * v[i] + (0.5 * dt * dt) * a[i];
        v[i] += dt * a[i];
        e[i] += dt * dedt[i];
      }
      if (continuity)
        for (std::size_t i = 0; i < n; ++i) rho[i] += dt * drhodt[i];
      // S_{n+1} from S_n and the velocity gradient of the last evaluation (explicit, like the
      // drift): the force evaluation below then sees the new stress.
      solver_->updateStrength(dt);
      store_.swapValues(f_.a, f_.aOld);
      store_.swapValues(f_.dedt, f_.dedtOld);
      store_.swapValues(f_.drhodt, f_.drhodtOld);
      boundaries_->wrapPeriodic(store_);
    });
    Phases::time(phases_.exchange, [&] {
      const auto m = decomposition_->migrate(store_, step_);
      migrated_ = m.moved;
      migratedTotal_ += m.moved;
      maxRankDistance_ = std::max(maxRankDistance_, m.maxRankDistance);
    });
    evaluate();
    Phases::time(phases_.integration, [&] {
      auto v = store_[f_.v];
      auto e = store_[f_.e];
      auto rho = store_[f_.rho];
      const auto a = store_[f_.a], aOld = store_[f_.aOld];
      const auto dedt = store_[f_.dedt], dedtOld = store_[f_.dedtOld];
      const auto drhodt = store_[f_.drhodt], drhodtOld = store_[f_.drhodtOld];
      const double half = 0.5 * dt;
      const std::size_t n = store_.localCount();
      for (std::size_t i = 0; i < n; ++i) {
        v[i] += half * (a[i] - aOld[i]);
        e[i] += half * (dedt[i] - dedtOld[i]);
      }
      if (continuity)
        for (std::size_t i = 0; i < n; ++i) rho[i] += half * (drhodt[i] - drhodtOld[i]);
      solver_->equationOfState(); // p, cs of the corrected state (output, probes, next dt)
      solver_->updateSmoothing();
    });
    time_ += dt;
    ++step_;
    checkFinite();
    if (mpi_.size() > 1) Phases::time(phases_.exchange, [&] { balance(); });
  }

  // Measures the imbalance of the neighbor cost and re-cuts the key axis when due (the rows of
  // the last neighbor search still match the store here, which the METIS graph needs).
  void balance() {
    imbalance_ = decomposition_->imbalance(store_);
    if (!decomposition_->rebalanceDue(step_, imbalance_)) return;
    const auto r = decomposition_->rebalance(store_, neighbors_.offsets, neighbors_.indices);
    ++rebalances_;
    imbalance_ = r.imbalanceAfter;
    if (r.metisEdgeCut >= 0) metisEdgeCut_ = r.metisEdgeCut;
    // Scheduled rebalances are routine; one forced by the threshold is worth a line.
    if (log_ && r.imbalanceBefore > deck_.decomposition.imbalance_threshold)
      log_->note(fmt::format(
          "rebalance at step {}: cost max/mean {:.3f} -> {:.3f}, {} particles moved{}", step_,
          r.imbalanceBefore, r.imbalanceAfter, r.moved,
          r.metisEdgeCut >= 0 ? fmt::format(", METIS edge cut {} pairs", r.metisEdgeCut) : ""));
  }

  double nextTimeStep() {
    const auto [dtLocal, which] = solver_->stableTimeStep();
    const double dt = mpi_.min(dtLocal);
    if (!(dt > 1e-14 * deck_.run.end_time) || !std::isfinite(dt)) {
      std::string who = "no particle";
      if (dtLocal == dt && store_.localCount() > 0) {
        who = fmt::format(
            "particle id {} (h = {:.3e} m, sound speed {:.3e} m/s, density {:.3e} kg/m^3)",
            store_[f_.id][which], store_[f_.h][which], store_[f_.cs][which], store_[f_.rho][which]);
      }
      throw RunError(
          fmt::format("time step collapsed to {:.3e} s at step {} (t = {:.6e} s), set by {}", dt,
                      step_, time_, who));
    }
    return dt;
  }

  // Shortens dt so that snapshot times and the end time are hit exactly; splits the last two
  // steps before a target evenly rather than leaving a sliver.
  double clampToTargets(double dt) const {
    double target = deck_.run.end_time;
    if (deck_.output.every > 0.0) target = std::min(target, nextSnapshotTime_);
    const double left = target - time_;
    if (left <= 0.0) return dt;
    if (dt >= left) return left;
    if (1.5 * dt > left) return 0.5 * left;
    return dt;
  }

  void checkFinite() {
    const auto id = store_[f_.id];
    const auto x = store_[f_.x];
    const auto v = store_[f_.v];
    const auto e = store_[f_.e];
    const auto rho = store_[f_.rho];
    const auto h = store_[f_.h];
    ParticleId bad = std::numeric_limits<ParticleId>::max();
    int field = 0;
    for (std::size_t i = 0;
         i < store_.localCount() && bad == std::numeric_limits<ParticleId>::max(); ++i) {
      int fld = 0;
      if (!x[i].allFinite())
        fld = 1;
      else if (!v[i].allFinite())
        fld = 2;
      else if (!std::isfinite(e[i]))
        fld = 3;
      else if (!(rho[i] > 0.0) || !std::isfinite(rho[i]))
        fld = 4;
      else if (!(h[i] > 0.0) || !std::isfinite(h[i]))
        fld = 5;
      if (fld) bad = id[i], field = fld;
    }
    ParticleId first;
    MPI_Allreduce(&bad, &first, 1, MPI_UINT64_T, MPI_MIN, mpi_.comm());
    if (first == std::numeric_limits<ParticleId>::max()) return;
    int code = first == bad ? field : 0, fieldCode = 0;
    MPI_Allreduce(&code, &fieldCode, 1, MPI_INT, MPI_MAX, mpi_.comm());
    static const char* names[] = {"",
                                  "position",
                                  "velocity",
                                  "specific_internal_energy",
                                  "density (non-positive or non-finite)",
                                  "smoothing_length"};
    throw RunError(
        fmt::format("non-finite state: field '{}' of particle id {} at step {} (t = {:.6e} s)",
                    names[fieldCode], first, step_, time_));
  }

  // ---- checkpoints ------------------------------------------------------------------------------
  int checkpointKeep() const { return deck_.checkpoint ? deck_.checkpoint->keep : 2; }

  // Writes ckpt_<step>.h5 (atomically), then points `latest` at it, then prunes old ones. The
  // logs are flushed first, so every row up to this step is on disk before the checkpoint is.
  void checkpoint(double dtNext, Clock::time_point wall0) {
    Phases::time(phases_.checkpoint, [&] {
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

  // Everything besides the particle fields that the run needs to continue exactly: identical
  // on every rank (the checkpoint writer stores rank 0's copy).
  io::CheckpointState saveState(double dtNext, double wall) const {
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
    st.texts["decomposition_curve"] = deck_.decomposition.curve;
    st.texts["decomposition_partitioner"] = deck_.decomposition.partitioner;
    st.integers["rebalances"] = {rebalances_};
    return st;
  }

  void restoreState(const io::CheckpointHeader& h, bool sameLayout) {
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
      throw io::CheckpointError(h.path +
                                ": state/probe_particles does not match the deck's probes");
    probes_->restoreTracked(probes);
    rebalances_ = static_cast<int>(st.integer("rebalances"));
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

  // ---- output ---------------------------------------------------------------------------------
  void resolveOutputFields() {
    std::vector<std::string> available;
    for (const auto& c : store_.columns())
      if (c->info().flags & kOutput) available.push_back(c->info().name);
    available.push_back("smoothing");
    available.push_back("stress");
    if (deck_.output.fields.empty()) {
      outputFields_ = available;
      return;
    }
    for (const auto& name : deck_.output.fields) {
      if (std::find(available.begin(), available.end(), name) == available.end()) {
        std::string list;
        for (const auto& a : available) list += (list.empty() ? "" : ", ") + a;
        throw DeckError(
            deck_.output.where,
            fmt::format("output field '{}' does not exist (available: {})", name, list));
      }
    }
    outputFields_ = deck_.output.fields;
    // Ids and positions are always written: without them a snapshot cannot be read.
    for (const char* must : {"position", "id"})
      if (std::find(outputFields_.begin(), outputFields_.end(), must) == outputFields_.end())
        outputFields_.insert(outputFields_.begin(), must);
  }

  bool snapshotDue() const {
    if (deck_.output.every_steps > 0 && step_ % deck_.output.every_steps == 0) return true;
    return deck_.output.every > 0.0 && time_ >= nextSnapshotTime_ * (1.0 - 1e-12);
  }

  void writeSnapshot() {
    Phases::time(phases_.output, [&] {
      const std::size_t n = store_.localCount();
      std::vector<io::SnapshotField> fields;
      std::vector<FieldInfo> infos;
      for (const auto& name : outputFields_) {
        const FieldInfo tensor{name, ScalarType::F64, {Dim, Dim}, kOutput};
        if (name == "smoothing") {
          // H = I/h for SPH, the full tensor for ASPH (INTERFACE.md: the H tensor).
          const auto h = store_[f_.h];
          const auto Hs = f_.anisotropic() ? store_[f_.H] : std::span<const Tensor<Dim>>{};
          // The rows buffer has no alignment guarantee for fixed-size Eigen types: write doubles.
          fields.push_back({tensor, nullptr, [h, Hs, n](void* rows) {
                              auto* out = static_cast<double*>(rows);
                              for (std::size_t i = 0; i < n; ++i) {
                                const Tensor<Dim> H =
                                    Hs.empty() ? (Tensor<Dim>::Identity() / h[i]).eval() : Hs[i];
                                std::memcpy(out + i * Dim * Dim, H.data(), sizeof(H));
                              }
                            }});
        } else if (name == "stress") {
          // Full Cauchy stress -p I + S (the Dim x Dim block); S = 0 on the hydro path.
          const auto p = store_[f_.p];
          const auto S = f_.hasStrength() ? store_[f_.S] : std::span<const Tensor<3>>{};
          fields.push_back({tensor, nullptr, [p, S, n](void* rows) {
                              auto* sigma = static_cast<Tensor<Dim>*>(rows);
                              for (std::size_t i = 0; i < n; ++i) {
                                sigma[i] = -p[i] * Tensor<Dim>::Identity();
                                if (!S.empty()) sigma[i] += S[i].template topLeftCorner<Dim, Dim>();
                              }
                            }});
        } else {
          const ColumnBase* c = store_.find(name);
          fields.push_back({c->info(), c->raw()});
        }
        infos.push_back(fields.back().info);
      }
      const std::string base = fmt::format("snap_{:06d}", snapshotIndex_);
      const fs::path snapDir = dir_ / "snapshots";
      io::writeSnapshot(mpi_.comm(), (snapDir / (base + ".h5")).string(),
                        {time_, step_, Dim, BuildInfo::version()}, n, fields);
      const std::uint64_t global = mpi_.sum(static_cast<std::uint64_t>(n));
      if (mpi_.root()) {
        io::writeSnapshotXdmf((snapDir / (base + ".xmf")).string(), base + ".h5", time_, global,
                              Dim, infos);
      }
      // Kept on every rank alike: it is part of the checkpointed state.
      series_.emplace_back(time_, base + ".xmf");
      if (mpi_.root()) io::writeSeriesXdmf((snapDir / "series.xmf").string(), series_);
      ++snapshotIndex_;
      lastSnapshotStep_ = step_;
      if (deck_.output.every > 0.0)
        while (nextSnapshotTime_ <= time_ * (1.0 + 1e-12)) nextSnapshotTime_ += deck_.output.every;
    });
  }

  void record(double dt, std::int64_t step, Clock::time_point wall0) {
    Phases::time(phases_.output, [&] {
      if (step % deck_.output.history_every_steps != 0 && time_ < deck_.run.end_time) return;
      const auto t = diagnostics::computeTotals(store_, f_, mpi_);
      last_ = t;
      const std::uint64_t n = mpi_.sum(static_cast<std::uint64_t>(store_.localCount()));
      const std::uint64_t ghosts = mpi_.sum(static_cast<std::uint64_t>(ghostCount_));
      // Wall seconds of the whole chain, so a restarted run's history reads on.
      const double wall = wallOffset_ + std::chrono::duration<double>(Clock::now() - wall0).count();
      if (history_.open())
        history_.row(fmt::format("{},{:.17g},{:.17g},{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:."
                                 "17g},{:.17g},{:.3f},{:.4f},{},{}",
                                 step, time_, dt, n, t.mass, t.momentum[0], t.momentum[1],
                                 t.momentum[2], t.kinetic, t.internal, t.total(), wall, imbalance_,
                                 ghosts, migrated_));
      if (!probes_->empty()) {
        const auto samples = probes_->sample(store_, f_, mpi_, solver_->support());
        if (probesCsv_.open())
          for (const auto& s : samples)
            probesCsv_.row(fmt::format("{:.17g},{},{},{:.17g}", time_, s.probe, s.field, s.value));
      }
    });
  }

  void banner(RunLog& log, const fs::path& dir) {
    std::vector<std::string> lines;
    lines.push_back(fmt::format("spall {} (git {}): {}", BuildInfo::version(),
                                BuildInfo::gitRevision(),
                                deck_.run.title.empty() ? deck_.path : deck_.run.title));
    lines.push_back(
        fmt::format("deck {} | {}D | {} {} n_h {:g} | density {} | {} rank{}", deck_.path, Dim,
                    deck_.solver.method, kernelName(deck_.solver.kernel), deck_.solver.nodes_per_h,
                    densityName(deck_.solver.density), mpi_.size(), mpi_.size() > 1 ? "s" : ""));
    for (const auto& b : bodies_)
      lines.push_back(
          fmt::format("  body {:<16} {:>10} particles  mass {:.6g} kg  spacing {:.4g} m", b.name,
                      b.particles, b.mass, b.spacing));
    lines.push_back(fmt::format("particles {} | memory ~{:.1f} MB | end time {:.6g} s | output {}",
                                particles(), memoryEstimate() / 1048576.0, deck_.run.end_time,
                                dir.string()));
    log.banner(lines);
  }

  void finish(RunLog& log, const RunOptions& options, Clock::time_point wall0, int stopSignal) {
    const double wall = std::chrono::duration<double>(Clock::now() - wall0).count();
    // The stepping rate of this job: checkpoint writing is reported on its own line.
    const std::int64_t steps = step_ - startStep_;
    const double pSteps = static_cast<double>(particles()) * static_cast<double>(steps);
    const double stepping = wall - phases_.checkpoint;
    const double rate = stepping > 0.0 ? pSteps / stepping : 0.0;
    const auto& t = last_;
    const double massErr = std::abs(t.mass - totals0_.mass) / totals0_.mass;
    double momScale = 0.0, momErr = 0.0;
    for (int d = 0; d < 3; ++d) {
      momScale = std::max({momScale, std::abs(totals0_.momentum[d]), t.momentumScale[d],
                           totals0_.momentumScale[d]});
      momErr = std::max(momErr, std::abs(t.momentum[d] - totals0_.momentum[d]));
    }
    momErr = momScale > 0.0 ? momErr / momScale : 0.0;
    const double e0 = totals0_.total();
    const double energyErr = std::abs(t.total() - e0) / std::max(std::abs(e0), 1e-300);
    const std::size_t peak =
        static_cast<std::size_t>(mpi_.sum(static_cast<double>(peakResidentBytes())));
    const std::size_t base = static_cast<std::size_t>(mpi_.sum(static_cast<double>(baselineRss_)));
    const double pairs = mpi_.sum(static_cast<double>(pairCount_));
    const double ghostFraction = mpi_.max(ghostFractionMax_);
    const std::uint64_t crossPairs = mpi_.sum(crossPairs_) / 2;
    const bool reproducible =
        deck_.decomposition.reproducible && mpi_.max(canonicalLost_ ? 1.0 : 0.0) == 0.0;
    const double meanNeighbors =
        evaluations_ > 0 ? pairs / (static_cast<double>(evaluations_) *
                                    std::max<double>(1.0, static_cast<double>(particles())))
                         : 0.0;
    const double phaseSum = phases_.neighbors + phases_.density + phases_.forces +
                            phases_.integration + phases_.boundaries + phases_.exchange +
                            phases_.output + phases_.checkpoint;
    std::vector<std::string> lines = {
        fmt::format("{}: {} steps to t = {:.6g} s (step {}) in {:.2f} s wall | {:.3g} "
                    "particle-steps/s ({:.3g} per core)",
                    stopSignal ? "stopped" : "done", steps, time_, step_, wall, rate,
                    rate / mpi_.size()),
        fmt::format("conservation: mass {:.1e} | momentum {:.1e} | total energy {:.1e} (relative)",
                    massErr, momErr, energyErr),
        fmt::format("time: neighbors {:.1f}% density {:.1f}% forces {:.1f}% integration {:.1f}% "
                    "boundaries {:.1f}% exchange {:.1f}% output {:.1f}%",
                    100 * phases_.neighbors / wall, 100 * phases_.density / wall,
                    100 * phases_.forces / wall, 100 * phases_.integration / wall,
                    100 * phases_.boundaries / wall, 100 * phases_.exchange / wall,
                    100 * phases_.output / wall)};
    if (checkpointsWritten_ > 0)
      lines.push_back(fmt::format(
          "checkpoints: {} written, {:.1f} MB each ({:.0f} B/particle), {:.2f} s in all "
          "({:.0f} MB/s); latest {}",
          checkpointsWritten_, checkpointBytes_ / 1e6,
          static_cast<double>(checkpointBytes_) /
              std::max<double>(1.0, static_cast<double>(particles())),
          checkpointWriteSeconds_,
          checkpointWriteSeconds_ > 0 ? checkpointWriteBytes_ / 1e6 / checkpointWriteSeconds_ : 0.0,
          (dir_ / "checkpoints" / checkpointFileName(lastCheckpointStep_)).string()));
    if (stopSignal)
      lines.push_back(fmt::format("stopped by {} at step {}: resume with\n  {}",
                                  StopSignals::name(stopSignal), step_, resumeCommand(options)));
    if (mpi_.size() > 1)
      lines.push_back(fmt::format(
          "decomposition: {} {} on {} ranks | {} rebalances, cost max/mean {:.3f} | ghosts up to "
          "{:.1f}% of a rank's particles, {} pairs across ranks | {} migrations, up to {} ranks in "
          "one step{}",
          deck_.decomposition.curve, deck_.decomposition.partitioner, mpi_.size(), rebalances_,
          imbalance_, 100.0 * ghostFraction, crossPairs, migratedTotal_, maxRankDistance_,
          metisEdgeCut_ >= 0 ? fmt::format(" | METIS edge cut {} pairs", metisEdgeCut_) : ""));
    if (deck_.decomposition.reproducible && !reproducible)
      lines.push_back("note: a rank's particles were too sparse for the canonical neighbor grid; "
                      "other rank counts agree with this run to round-off, not bit for bit");
    lines.push_back(
        fmt::format("output in {} (open snapshots/series.xmf in ParaView)", dir_.string()));
    log.summary(lines);
    if (!mpi_.root()) return;
    std::ofstream js(dir_ / "summary.json");
    js << fmt::format(
        "{{\n  \"deck\": \"{}\",\n  \"title\": \"{}\",\n  \"ranks\": {},\n  \"dimension\": {},\n"
        "  \"particles\": {},\n  \"steps\": {},\n  \"time\": {:.17g},\n  \"wall_seconds\": "
        "{:.6f},\n"
        "  \"particle_steps_per_second\": {:.6g},\n  \"particle_steps_per_second_per_core\": "
        "{:.6g},\n"
        "  \"status\": \"{}\",\n  \"steps_this_run\": {},\n"
        "  \"mean_neighbors\": {:.3f},\n  \"peak_rss_bytes\": {},\n  \"baseline_rss_bytes\": {},\n"
        "  \"bytes_per_particle\": {:.1f},\n"
        "  \"phases\": {{\"neighbors\": {:.6f}, \"density\": {:.6f}, \"forces\": {:.6f}, "
        "\"integration\": {:.6f}, "
        "\"boundaries\": {:.6f}, \"exchange\": {:.6f}, \"output\": {:.6f}, \"checkpoint\": "
        "{:.6f}, \"other\": {:.6f}}},\n"
        "  \"checkpoint\": {{\"written\": {}, \"bytes\": {}, \"bytes_per_particle\": {:.1f}, "
        "\"write_seconds\": {:.6f}, \"write_bytes\": {}, \"read_seconds\": {:.6f}, "
        "\"read_bytes\": {}, \"restarted_from\": \"{}\", \"ranks_written\": {}}},\n"
        "  \"decomposition\": {{\"curve\": \"{}\", \"partitioner\": \"{}\", \"rebalances\": {}, "
        "\"imbalance\": {:.6f}, \"ghost_fraction_max\": {:.6f}, \"migrated\": {}, "
        "\"max_rank_distance\": {}, \"pairs_across_ranks\": {}, \"metis_edge_cut\": {}, "
        "\"reproducible\": {}}},\n"
        "  \"conservation\": {{\"mass_relative\": {:.6e}, \"momentum_relative\": {:.6e}, "
        "\"energy_relative\": {:.6e}}}\n}}\n",
        jsonEscape(options.deckPath), jsonEscape(deck_.run.title), mpi_.size(), Dim, particles(),
        step_, time_, wall, rate, rate / mpi_.size(), stopSignal ? "stopped" : "finished", steps,
        meanNeighbors, peak, base,
        particles() > 0
            ? static_cast<double>(peak - std::min(peak, base)) / static_cast<double>(particles())
            : 0.0,
        phases_.neighbors, phases_.density, phases_.forces, phases_.integration, phases_.boundaries,
        phases_.exchange, phases_.output, phases_.checkpoint, std::max(0.0, wall - phaseSum),
        checkpointsWritten_, checkpointBytes_,
        static_cast<double>(checkpointBytes_) /
            std::max<double>(1.0, static_cast<double>(particles())),
        checkpointWriteSeconds_, checkpointWriteBytes_, checkpointReadSeconds_,
        checkpointReadBytes_, jsonEscape(resumedFrom_), checkpointRanks_, deck_.decomposition.curve,
        deck_.decomposition.partitioner, rebalances_, imbalance_, ghostFraction, migratedTotal_,
        maxRankDistance_, crossPairs, metisEdgeCut_, reproducible, massErr, momErr, energyErr);
  }

  // The command that continues this run, as the user would type it (any rank count will do).
  static std::string resumeCommand(const RunOptions& o) {
    auto quote = [](const std::string& a) {
      if (a.find_first_of(" \t'\"$`\\[]*?{}()<>|&;") == std::string::npos) return a;
      std::string q = "'";
      for (char c : a) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
      return q + "'";
    };
    std::string cmd = "spall run " + quote(o.deckPath);
    for (const auto& v : o.overrides) cmd += " --set " + quote(v);
    if (o.outputDir) cmd += " --output " + quote(*o.outputDir);
    return cmd + " --restart latest";
  }

  static std::string jsonEscape(const std::string& s) {
    std::string o;
    for (char c : s) {
      if (c == '"' || c == '\\') o += '\\';
      o += c;
    }
    return o;
  }

  const Deck& deck_;
  const parallel::MpiContext& mpi_;
  std::vector<materials::Eos> eos_;
  std::vector<std::optional<materials::Strength>> strength_;
  ParticleStore store_;
  solvers::SphFields<Dim> f_;
  std::vector<BodySummary> bodies_;
  std::unique_ptr<solvers::Solver<Dim>> solver_;
  std::unique_ptr<solvers::Boundaries<Dim>> boundaries_;
  std::unique_ptr<diagnostics::Probes<Dim>> probes_;
  Field<std::int32_t> cost_;
  std::unique_ptr<parallel::Decomposition<Dim>> decomposition_;
  std::unique_ptr<parallel::HaloExchange<Dim>> halo_;
  std::vector<double> reach_;
  std::vector<Vec<Dim>> boxReach_; // ASPH: the supports' bounding boxes
  std::vector<std::size_t> haloFields_, refreshFields_;
  std::size_t totalParticles_ = 0, ghostCount_ = 0;
  std::uint64_t migrated_ = 0, migratedTotal_ = 0;
  int maxRankDistance_ = 0, rebalances_ = 0;
  double imbalance_ = 1.0, ghostFractionMax_ = 0.0;
  std::int64_t metisEdgeCut_ = -1;
  std::uint64_t crossPairs_ = 0;
  bool canonicalLost_ = false; // a coarsened grid broke the rank-count-independent sum order
  RunLog* log_ = nullptr;
  neighbors::CellGrid<Dim> grid_;
  std::vector<std::int32_t> fixedBodies_; // sorted body indices with `fixed = true`
  neighbors::NeighborList neighbors_;
  std::vector<std::string> outputFields_;
  std::vector<std::string> deferredWarnings_;
  std::vector<std::pair<double, std::string>> series_;
  io::CsvLog history_, probesCsv_;
  fs::path dir_;
  Phases phases_;
  diagnostics::Totals totals0_, last_;
  double time_ = 0.0;
  double nextSnapshotTime_ = 0.0;
  std::int64_t step_ = 0;
  std::int64_t lastSnapshotStep_ = -1;
  int snapshotIndex_ = 0;
  std::size_t pairCount_ = 0;
  std::size_t evaluations_ = 0;
  std::size_t baselineRss_ = 0;
  // Restart chain bookkeeping.
  std::string resumedFrom_;    // checkpoint this run continued from ("" for a new run)
  double resumeDt_ = 0.0;      // the time step the checkpointed run would have taken next
  double wallOffset_ = 0.0;    // wall seconds of the chain before this job
  std::int64_t startStep_ = 0; // first step of this job
  std::int64_t lastCheckpointStep_ = -1;
  Clock::time_point lastCheckpointWall_;
  int checkpointsWritten_ = 0, checkpointRanks_ = 0;
  std::uint64_t checkpointBytes_ = 0, checkpointWriteBytes_ = 0, checkpointReadBytes_ = 0;
  double checkpointWriteSeconds_ = 0.0, checkpointReadSeconds_ = 0.0;
};

// Refuses to touch a directory that holds results, unless asked to; with --overwrite, removes
// only what a run writes there. A restart continues the results in place.
void prepareOutputDirectory(const fs::path& dir, const RunOptions& options) {
  static const char* ours[] = {"deck.toml",    "history.csv", "probes.csv",
                               "summary.json", "snapshots",   "checkpoints"};
  if (!fs::exists(dir)) return;
  if (!fs::is_directory(dir))
    throw UsageError(fmt::format("output path '{}' exists and is not a directory", dir.string()));
  if (options.restart) return;
  bool hasResults = false;
  for (const char* name : ours) hasResults = hasResults || fs::exists(dir / name);
  if (!hasResults) return;
  if (!options.overwrite)
    throw UsageError(
        fmt::format("output directory '{}' already holds results; pass --overwrite to replace "
                    "them, --output DIR to write elsewhere or --restart latest to continue them",
                    dir.string()));
  for (const char* name : ours) fs::remove_all(dir / name);
}

template <int Dim>
void runDim(const Deck& deck, const RunOptions& options, const parallel::MpiContext& mpi) {
  if (options.restart && options.overwrite)
    throw UsageError("--restart continues the results in the output directory; --overwrite "
                     "would delete them: pass one or the other");
  const fs::path dir =
      options.outputDir ? fs::path(*options.outputDir) : fs::path(deck.output.directory);
  Simulation<Dim> sim(deck, mpi); // every deck error surfaces here, before anything is written
  if (options.restart) {
    // Rank 0 looks at the directory; every rank needs the same list (one line each: the
    // fallback flag, what is wrong with `latest`, then the files).
    std::string text;
    parallel::onRoot<UsageError>(mpi.comm(), [&] {
      const RestartCandidates c = restartCandidates(dir, *options.restart);
      text = (c.fallback ? "1\n" : "0\n") + c.problem + "\n";
      for (const auto& f : c.files) text += f.string() + "\n";
    });
    parallel::broadcast(text, 0, mpi.comm());
    RestartCandidates candidates;
    std::istringstream lines(text);
    std::string line;
    std::getline(lines, line);
    candidates.fallback = line == "1";
    std::getline(lines, candidates.problem);
    while (std::getline(lines, line)) candidates.files.emplace_back(line);
    sim.resume(candidates); // nothing written yet: a bad checkpoint leaves the directory as it was
  } else {
    sim.generate();
  }
  parallel::onRoot<UsageError>(mpi.comm(), [&] { prepareOutputDirectory(dir, options); });
  sim.run(options, dir);
}

template <int Dim> void checkDim(const Deck& deck, const parallel::MpiContext& mpi) {
  Simulation<Dim> sim(deck, mpi);
  sim.generate();
  const double dt = sim.firstTimeStep();
  if (!mpi.root()) return;
  fmt::print("deck {}: OK\n", deck.path);
  if (!deck.run.title.empty()) fmt::print("  title      {}\n", deck.run.title);
  fmt::print("  dimension  {}D, solver {} ({}, n_h {:g}, density {})\n", Dim, deck.solver.method,
             kernelName(deck.solver.kernel), deck.solver.nodes_per_h,
             densityName(deck.solver.density));
  for (const auto& b : sim.bodies())
    fmt::print("  body       {:<16} {:>10} particles  mass {:.6g} kg  spacing {:.4g} m\n", b.name,
               b.particles, b.mass, b.spacing);
  fmt::print("  particles  {}\n  memory     ~{:.1f} MB (estimate)\n", sim.particles(),
             sim.memoryEstimate() / 1048576.0);
  fmt::print("  first dt   {:.4g} s (before viscosity; end time {:.6g} s)\n", dt,
             deck.run.end_time);
  fmt::print("  output     {}\n", deck.output.directory);
  for (const auto& w : sim.warnings()) fmt::print("  warning    {}\n", w);
}

} // namespace

void runDeck(const Deck& deck, const RunOptions& options, const parallel::MpiContext& mpi) {
  switch (deck.run.dimension) {
  case 1:
    return runDim<1>(deck, options, mpi);
  case 2:
    return runDim<2>(deck, options, mpi);
  default:
    return runDim<3>(deck, options, mpi);
  }
}

void checkDeck(const Deck& deck, const parallel::MpiContext& mpi) {
  switch (deck.run.dimension) {
  case 1:
    return checkDim<1>(deck, mpi);
  case 2:
    return checkDim<2>(deck, mpi);
  default:
    return checkDim<3>(deck, mpi);
  }
}

} // namespace spall::app
