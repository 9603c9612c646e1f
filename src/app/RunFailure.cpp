#include "Simulation.hpp"

#include "spall/app/FailureHint.hpp"
#include "spall/methods/modules/DeformationGradient.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <fstream>
#include <limits>

// When a run fails: the rescue point it keeps, the replay from it that records the failing
// particle's last steps and checkpoints the last good state, the message that explains; and the
// early warning when the time step falls.
namespace spall::app {

namespace fs = std::filesystem;

// A copy of the checkpointed state, taken every output.failure_history steps: at most that many
// steps to replay when a step fails.
template <int Dim> void Simulation<Dim>::keepRescuePoint(double dtNext, Clock::time_point wall0) {
  if (deck_.output.failure_history <= 0) return;
  method_->stats().phases.time(methods::kCheckpoint, [&] {
    store_.copyRows(kCheckpoint, rescue_.rows);
    rescue_.state = saveState(
        dtNext, wallOffset_ + std::chrono::duration<double>(Clock::now() - wall0).count());
    rescue_.time = time_;
    rescue_.step = step_;
    rescue_.valid = true;
  });
}

// Collective. Rewinds to the rescue point and steps again to the failure (the steps are
// deterministic: the same particles bit for bit), sampling the failing particle each step and
// writing a checkpoint of the last good state on the way; then throws the explaining RunError.
// A solid's failing particle is also recorded as `output.record_particles` would (its F-table
// from the rescue point, and its state), so that `spall element --state` replays what it saw.
template <int Dim>
void Simulation<Dim>::explainFailure(const StepFailure& failure, Clock::time_point wall0) {
  history_.flush();
  probesCsv_.flush();
  const FailureReplay replay = replayFailure(failure, wall0);
  writeFailureHistory(failure.fault(), replay);
  throw RunError(failureText(failure, replay), true);
}

// The failing particle's last steps again, from the rescue copy: its rows of the failure's
// history, its F-table (ParticleRecorder), and a checkpoint of the last good state.
template <int Dim>
typename Simulation<Dim>::FailureReplay Simulation<Dim>::replayFailure(const StepFailure& failure,
                                                                       Clock::time_point wall0) {
  const ParticleReport& f = failure.fault();
  const bool nonFinite = f.kind == ParticleReport::Kind::NonFinite;
  FailureReplay out;
  std::vector<std::string>& rows = out.rows;
  double& pMin = out.pMin; // over the good steps sampled
  std::int64_t& checkpointStep = out.checkpointStep;
  // The last state a normal step was taken from: the step before the failure. (A collapsed
  // step's own state is finite too, but its next dt is below the floor.)
  const std::int64_t lastGood = f.step - 1;
  const auto sample = [&](std::int64_t step, double time, double dt) {
    const ParticleReport s = method_->particle(f.id);
    if (step < f.step && std::isfinite(s.p)) pMin = std::min(pMin, s.p);
    // The rescue point's row has no step behind it in the file: its dt is nan.
    std::string row = fmt::format("{},{:.17g},{:.17g}", step, time, dt);
    for (int d = 0; d < Dim; ++d) row += fmt::format(",{:.17g}", s.x[static_cast<std::size_t>(d)]);
    for (int d = 0; d < Dim; ++d) row += fmt::format(",{:.17g}", s.v[static_cast<std::size_t>(d)]);
    rows.push_back(row + fmt::format(",{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{}", s.rho, s.h, s.p,
                                     s.cs, s.e, s.neighbors));
  };
  const std::string stem = fmt::format("failure_step{}_particle{}", f.step, f.id);
  std::unique_ptr<ParticleRecorder<Dim>> recorder;
  const auto record = [&](double time) {
    if (recorder) recorder->write(time, store_, f_, mpi_);
  };
  const auto checkpointOnce = [&](double dtNext) {
    if (checkpointStep >= 0 || step_ != lastGood) return;
    checkpoint(dtNext, wall0);
    checkpointStep = step_;
  };
  if (rescue_.valid && rescue_.step <= lastGood) {
    store_.restoreRows(rescue_.rows);
    io::CheckpointHeader h;
    h.path = "the rescue copy";
    h.dimension = Dim;
    h.time = rescue_.time;
    h.step = rescue_.step;
    h.particles = totalParticles_;
    h.rankCounts.assign(static_cast<std::size_t>(mpi_.size()), 0);
    h.state = rescue_.state;
    const double wallOffset = wallOffset_; // this job's start: the copy's wall time includes it
    restoreState(h, true);
    wallOffset_ = wallOffset;
    double dt = rescue_.state.real("dt");
    sample(step_, time_, std::numeric_limits<double>::quiet_NaN());
    // A restart that meets the failure again keeps the first run's (longer) recording.
    const bool recorded =
        mpi_.max(mpi_.root() && fs::exists(dir_ / (stem + ".ftable")) ? 1.0 : 0.0) > 0.0;
    if (f_.L.valid() && f.material >= 0 && !recorded) {
      if (!f_.Fdef.valid()) { // F = I at the rescue point: the table is relative to it
        methods::DeformationGradient<Dim>::addFields(store_, f_, true);
        auto F = std::make_unique<methods::DeformationGradient<Dim>>(true);
        method_->addModule(std::move(F));
        for (std::size_t i = 0; i < store_.localCount(); ++i) {
          store_[f_.Fdef][i].setIdentity();
          store_[f_.rhoUpdate][i] = store_[f_.rho][i];
          store_[f_.eUpdate][i] = store_[f_.e][i];
        }
      }
      recorder = std::make_unique<ParticleRecorder<Dim>>(f.id, stem);
      recorder->open(dir_, false, time_, store_, f_, mpi_);
      record(time_);
    }
    while (step_ < f.step) {
      checkpointOnce(dt);
      const double dtTaken = clampToTargets(dt).first;
      try {
        dt = stepOnce(dt, wall0, true);
      } catch (const StepFailure& again) {
        // As before (the steps are deterministic): the same particle, the same step.
        sample(again.fault().step, again.fault().time, dtTaken);
        record(again.fault().time);
        break;
      }
      sample(step_, time_, dtTaken);
      record(time_);
    }
    recorder.reset(); // the files complete
  } else if (!nonFinite) {
    // No copy to replay from (failure_history = 0, or the very first step): the state it has.
    checkpoint(f.dt, wall0);
    checkpointStep = step_;
  }

  return out;
}

// The particle's history, and what it looked like when it failed. A restart that meets the
// same failure again leaves the first run's (longer) file alone.
template <int Dim>
void Simulation<Dim>::writeFailureHistory(const ParticleReport& f, const FailureReplay& replay) {
  const std::vector<std::string>& rows = replay.rows;
  const std::string historyFile = fmt::format("failure_step{}_particle{}.csv", f.step, f.id);
  if (!rows.empty()) {
    parallel::onRoot<RunError>(mpi_.comm(), [&] {
      if (fs::exists(dir_ / historyFile)) return;
      std::ofstream out(dir_ / historyFile);
      const char* axes = "xyz";
      std::string header = "step,time,dt";
      for (int d = 0; d < Dim; ++d) header += fmt::format(",position_{}", axes[d]);
      for (int d = 0; d < Dim; ++d) header += fmt::format(",velocity_{}", axes[d]);
      out << header
          << ",density,smoothing_length,pressure,sound_speed,specific_internal_energy,neighbors\n";
      for (const auto& r : rows) out << r << "\n";
      if (!out) throw RunError("cannot write " + (dir_ / historyFile).string());
    });
  }
}

// What failed, where, the files that show it, and what usually causes it.
template <int Dim>
std::string Simulation<Dim>::failureText(const StepFailure& failure,
                                         const FailureReplay& replay) const {
  const ParticleReport& f = failure.fault();
  const std::vector<std::string>& rows = replay.rows;
  const std::int64_t checkpointStep = replay.checkpointStep;
  const std::string stem = fmt::format("failure_step{}_particle{}", f.step, f.id);
  const std::string historyFile = stem + ".csv";
  if (f.material < 0) throw RunError(failure.what(), true); // no particle: nothing to explain
  const auto& material = deck_.materials.at(static_cast<std::size_t>(f.material));
  const auto& body = bodies_.at(static_cast<std::size_t>(f.body));
  const double compression = f.rho / material.density;
  const double hRatio = f.h / body.spacing;
  std::string position, velocity;
  for (int d = 0; d < Dim; ++d) {
    position += fmt::format("{}{:.4e}", d ? ", " : "", f.x[static_cast<std::size_t>(d)]);
    velocity += fmt::format("{}{:.4e}", d ? ", " : "", f.v[static_cast<std::size_t>(d)]);
  }
  std::string text = fmt::format(
      "{} (material '{}', body '{}')\n  at x = ({}) m, v = ({}) m/s: density {:.4e} kg/m^3 "
      "({:.3g} x reference), h {:.3e} m ({:.3g} x its body's spacing), pressure {:.4e} Pa, "
      "sound speed {:.4e} m/s, {} neighbors",
      failure.what(), material.name, body.name, position, velocity, f.rho, compression, f.h, hRatio,
      f.p, f.cs, f.neighbors);
  if (checkpointStep >= 0)
    text += fmt::format("\n  last good state: {} (step {}; --restart latest runs into the failure "
                        "again, with output.every_steps = 1 say, to watch it)",
                        (dir_ / "checkpoints" / checkpointFileName(checkpointStep)).string(),
                        checkpointStep);
  else
    text += "\n  no checkpoint of a good state: output.failure_history = 0 keeps none";
  if (!rows.empty())
    text += fmt::format("\n  its history (position, velocity, density, h, pressure, neighbors) "
                        "over the last steps: {}",
                        (dir_ / historyFile).string());
  if (fs::exists(dir_ / (stem + ".ftable")))
    text += fmt::format(
        "\n  its F-table over the last steps: {0}.ftable; its material alone replays them: spall "
        "element {1} --material {2} --table {0}.ftable --state {0}_state.csv --substeps 1 "
        "--output {0}_replay.csv",
        (dir_ / stem).string(), (dir_ / "deck.toml").string(), material.name);
  // What usually causes it, judged from the particle.
  FailureSigns signs;
  signs.mpm = deck_.solver.method == SolverMethod::Mpm;
  signs.asph = deck_.solver.method == SolverMethod::Asph;
  signs.frictionless = fieldPerBody(deck_.solver.contact);
  signs.nonFinite = f.kind == ParticleReport::Kind::NonFinite;
  signs.energy = f.kind == ParticleReport::Kind::Energy;
  signs.dimension = Dim;
  signs.compression = compression;
  signs.hRatio = hRatio;
  signs.speed = std::hypot(f.v[0], f.v[1], f.v[2]);
  signs.neighbors = static_cast<int>(f.neighbors);
  signs.pMin = replay.pMin;
  signs.collapseFraction = kCollapse;
  signs.endTime = deck_.run.end_time;
  text += "\n  " + failureHint(signs);
  return text;
}

// The energy's books at each history row: the total against the initial energy (with the bodies
// that joined since) plus the work of external forces, judged against the scale K0 + |U0| + |W|.
// Beyond output.max_energy_error the run fails as a collapse does, explained by the particle that
// sets the time step (in a run that creates energy, the pair that blows up sets it). The totals
// are order-free sums: every rank, and every rank count, stops at the same step. Not before step
// 100: a load that starts from rest has W ~ 0 at first, and the trapezoidal W of one step is
// half the work its state shows (0.5 of the scale at step 1 of sandstone_confinement_rz, 2e-4 by
// step 100).
template <int Dim> void Simulation<Dim>::watchEnergy(double dt) {
  if (!energyDue_) return;
  energyDue_ = false;
  const double limit = deck_.output.max_energy_error;
  if (limit <= 0.0 || step_ < 100) return;
  const double work = method_->externalWork();
  const double expected = totals0_.total() + work;
  const double scale = totals0_.kinetic + std::abs(totals0_.internal) + std::abs(work);
  const double error = std::abs(last_.total() - expected);
  if (!(scale > 0.0) || error <= limit * scale) return;
  ParticleReport f = method_->timeStepSetter();
  f.kind = ParticleReport::Kind::Energy;
  f.step = step_;
  f.time = time_;
  throw StepFailure(
      fmt::format("total energy {:.6e} J at step {} (t = {:.6e} s) is {:.3g} times the energy "
                  "scale ({:.3e} J, initial kinetic + |internal| + |external work|) away from the "
                  "initial energy plus the external work ({:.6e} J), beyond output."
                  "max_energy_error = {:g}: the run {} energy. The time step, {:.3e} s, is set "
                  "by particle id {}",
                  last_.total(), step_, time_, error / scale, scale, expected, limit,
                  last_.total() > expected ? "creates" : "loses", dt, f.id),
      f, "");
}

// An early warning: dt below output.dt_warning times its median over the last 100 steps.
template <int Dim> void Simulation<Dim>::watchTimeStep(double dt) {
  if (deck_.output.dt_warning <= 0.0) return;
  constexpr std::size_t kWindow = 100;
  if (recentDt_.size() == kWindow) {
    std::vector<double> sorted(recentDt_.begin(), recentDt_.end());
    std::nth_element(sorted.begin(), sorted.begin() + kWindow / 2, sorted.end());
    const double median = sorted[kWindow / 2];
    // Warn once per fall: again only after dt recovered.
    if (dt < deck_.output.dt_warning * median) {
      if (!dtLow_) {
        const ParticleReport s = method_->timeStepSetter();
        if (log_ && s.material >= 0) {
          const auto& material = deck_.materials.at(static_cast<std::size_t>(s.material));
          log_->warning(fmt::format(
              "step {}: dt {:.3e} s is {:.2g} of its median over the last {} steps ({:.3e} s); "
              "set by particle id {} (material '{}', body '{}', density {:.3g} x reference, "
              "h {:.3g} x its body's spacing, sound speed {:.3e} m/s)",
              step_, dt, dt / median, kWindow, median, s.id, material.name,
              bodies_.at(static_cast<std::size_t>(s.body)).name, s.rho / material.density,
              s.h / bodies_.at(static_cast<std::size_t>(s.body)).spacing, s.cs));
        }
        ++dtWarnings_;
      }
      dtLow_ = true;
    } else if (dt > 2.0 * deck_.output.dt_warning * median) {
      dtLow_ = false;
    }
    recentDt_.pop_front();
  }
  recentDt_.push_back(dt);
}

template class Simulation<1>;
template class Simulation<2>;
template class Simulation<3>;

} // namespace spall::app
