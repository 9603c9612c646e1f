// SPH and ASPH in time bins (solver.time_bins > 1; the scheme: methods/TimeBins.hpp). The run's
// step is 2^K substeps of the finest bin's step delta. Every substep drifts every particle (x,
// v, e, rho by their last rates, S by the material update with its last velocity gradient): the
// state a neighbor reads is each particle's prediction at that time. Only the particles whose
// own step ends at the substep (the active rows) sum and evaluate their rates, and take the
// closing half-kick over their own step; the others keep the rates they were predicted with.
// A particle's step is the kick-drift-kick leapfrog of SphMethod::advance over its own dt, so a
// run whose particles all sit in the finest bin takes the same steps as without bins. The run's
// step ends with every particle synchronised: output, checkpoints, insertions and rebalancing
// happen there only, and a restart from any checkpoint continues bit for bit.
#include "spall/core/Threads.hpp"
#include "spall/methods/SphMethod.hpp"
#include "spall/methods/TimeBins.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace spall::methods {

// The run's step with bins: the slowest bin's, the finest step (the global stable one) 2^K.
template <int Dim>
double SphMethod<Dim>::stableTimeStep(double floor, std::int64_t step, double time) {
  const double dtMin = Base::stableTimeStep(floor, step, time);
  if (!f_.binned()) return dtMin;
  int K = 0;
  const auto bin = s_[f_.timeBin];
  for (std::size_t i = 0; i < s_.localCount(); ++i) K = std::max(K, int{bin[i]});
  return std::ldexp(dtMin, static_cast<int>(mpi_.max(static_cast<double>(K))));
}

// Every particle's bin from its own stable step over the finest (the global one), limited so
// that neighbors differ by at most kSpread: after an evaluation of all rows, while the lists
// hold the rows (before a rebalance moves them).
template <int Dim> void SphMethod<Dim>::assignBins() {
  const std::size_t n = s_.localCount();
  resizeWithHeadroom(ownStep_, n);
  solver_->particleTimeSteps(std::span<double>(ownStep_).first(n));
  double dtMin = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) dtMin = std::min(dtMin, ownStep_[i]);
  dtMin = mpi_.min(dtMin);
  const int count = setup_.solver.time_bins;
  const auto bin = s_[f_.timeBin];
  for (std::size_t i = 0; i < n; ++i)
    bin[i] = bins::binOf(std::min(ownStep_[i], approach_[i]), dtMin, count);
  refreshBins();
  resizeWithHeadroom(nextBin_, n);
  // A sweep moves the limit one neighbor on; a bin only falls, so the sweeps end.
  for (;;) {
    const bool changed = bins::limitSweep(lists(), n, bin, std::span<std::int32_t>(nextBin_));
    std::copy_n(nextBin_.begin(), n, bin.begin());
    refreshBins();
    if (mpi_.max(changed ? 1.0 : 0.0) == 0.0) break;
  }
}

// The run's step dt (the slowest bin's, or shorter where an output time cuts it): 2^K substeps
// of dt / 2^K, every particle starting its own step at the first. Where a particle's own stable
// step falls below kCloseBelow of that finest step, every particle closes its step at the next
// substep, and the run's step ends there (the next one begins with the finer step).
template <int Dim> double SphMethod<Dim>::advanceInBins(double dt, std::int64_t step, double time) {
  const std::size_t n = s_.localCount();
  const auto bin = s_[f_.timeBin];
  const auto start = s_[f_.stepStart], end = s_[f_.stepEnd];
  const int count = setup_.solver.time_bins;
  std::vector<std::uint64_t> population(static_cast<std::size_t>(count), 0);
  int K = 0;
  for (std::size_t i = 0; i < n; ++i) {
    start[i] = 0, end[i] = std::int32_t{1} << bin[i];
    K = std::max(K, int{bin[i]});
    ++population[static_cast<std::size_t>(bin[i])];
  }
  K = static_cast<int>(mpi_.max(static_cast<double>(K)));
  MPI_Allreduce(MPI_IN_PLACE, population.data(), count, MPI_UINT64_T, MPI_SUM, mpi_.comm());
  stats_.binPopulation = population;
  stats_.migrated = 0;
  stats_.stepSubsteps = 0, stats_.stepRowEvaluations = 0;
  const std::int32_t last = std::int32_t{1} << K;
  const double delta = std::ldexp(dt, -K);
  double taken = dt;
  bool closeAll = false;
  for (std::int32_t s = 1; s <= last; ++s) {
    const bool closing = s == last || closeAll;
    taken = s == last ? dt : s * delta;
    substep(delta, s, step, time + taken);
    if (closing) break;
    stats_.phases.time(kIntegration, [&] { closeAll = rebinActive(delta, s, K); });
    closeAll = mpi_.max(closeAll ? 1.0 : 0.0) > 0.0;
    if (closeAll) {
      const auto ends = s_[f_.stepEnd]; // (rows may have moved: a migration)
      std::fill_n(ends.begin(), s_.localCount(), s + 1);
    } else {
      refreshBins();
      stats_.phases.time(kIntegration, [&] { wakeNeighbors(delta, s); });
    }
  }
  countWork(K);
  checkFinite(step + 1, time + taken);
  assignBins();
  if (mpi_.size() > 1) stats_.phases.time(kExchange, [&] { balance(step + 1, &lists()); });
  return taken;
}

// One substep to `time` (substep s of last): SphMethod::advance for the active rows, the drift
// for all.
template <int Dim>
void SphMethod<Dim>::substep(double delta, std::int32_t s, std::int64_t step, double time) {
  std::size_t wrapped = 0;
  stats_.phases.time(kIntegration, [&] {
    kickDrift(delta);
    if (solver_->usesSummationDensity()) predictDensity(delta, s);
    for (const auto& m : modules_) m->beforeMaterials(s_, f_, delta);
    materials_.update(materialFields(), delta);
    wrapped = boundaries_.wrapPeriodic(s_);
  });
  stats_.phases.time(kNeighbors, [&] { rebuild_ = listsStale(wrapped > 0); });
  if (rebuild_)
    stats_.phases.time(kExchange, [&] {
      const auto m = decomposition_.migrate(s_, step);
      stats_.migrated += m.moved;
      stats_.migratedTotal += m.moved;
      stats_.maxRankDistance = std::max(stats_.maxRankDistance, m.maxRankDistance);
    });
  selectActive(s);
  keepPredictingRates();
  // Every row's step pairs are filtered (the waking reads them of rows that are not active);
  // the evaluation is the active rows'.
  solver_->setActiveRows(allActive_ ? nullptr : &active_);
  rates(step, time);
  stats_.phases.time(kIntegration, [&] {
    measureApproach();
    kickActive(delta, s);
    const std::size_t n = s_.localCount();
    boundaries_.holdVelocity(s_[f_.x].first(n), std::span<const double>(s_[f_.h]).first(n),
                             s_[f_.v].first(n), s_[f_.e].first(n));
    materials_.evaluate(materialFields());
    solver_->updateSmoothing();
  });
  solver_->setActiveRows(nullptr);
  allActive_ = true; // (an evaluation between the run's steps is every row's)
  bookExternal(delta, externalLoad(time));
  ++stats_.substeps, ++stats_.stepSubsteps;
  stats_.rowEvaluations += active_.size(), stats_.stepRowEvaluations += active_.size();
}

// Summation density: the rows not summed at substep s carry their density predicted by its rate
// (the rows summed there are summed from the state as it is, as without bins).
template <int Dim> void SphMethod<Dim>::predictDensity(double delta, std::int32_t s) {
  const auto rho = s_[f_.rho];
  const auto drhodt = s_[f_.drhodt];
  const auto end = s_[f_.stepEnd];
  for (std::size_t i = 0; i < s_.localCount(); ++i)
    if (end[i] != s) rho[i] += delta * drhodt[i];
}

// The owned rows whose step ends at substep s, in order.
template <int Dim> void SphMethod<Dim>::selectActive(std::int32_t s) {
  const std::size_t n = s_.localCount();
  const auto end = s_[f_.stepEnd];
  active_.clear();
  for (std::size_t i = 0; i < n; ++i)
    if (end[i] == s) active_.push_back(static_cast<std::uint32_t>(i));
  allActive_ = active_.size() == n;
}

// The rates each active row's step was predicted with, which its closing kick corrects (the
// rows the evaluation skips keep theirs: the solver and the modules write the active rows only).
template <int Dim> void SphMethod<Dim>::keepPredictingRates() {
  const auto a = s_[f_.a], aOld = s_[f_.aOld];
  const auto dedt = s_[f_.dedt], dedtOld = s_[f_.dedtOld];
  const auto drhodt = s_[f_.drhodt], drhodtOld = s_[f_.drhodtOld];
  for (const std::uint32_t i : active_)
    aOld[i] = a[i], dedtOld[i] = dedt[i], drhodtOld[i] = drhodt[i];
}

// Each active row's next step from substep s: its own stable step's bin, at most the bin s is
// aligned to, at most kSpread above its lowest neighbor's (all read before any is changed).
// Returns whether some active row's own step is below kCloseBelow delta (the finest bin is too
// coarse for it).
template <int Dim> bool SphMethod<Dim>::rebinActive(double delta, std::int32_t s, int K) {
  const std::size_t n = s_.localCount();
  resizeWithHeadroom(ownStep_, n);
  solver_->particleTimeSteps(std::span<double>(ownStep_).first(n));
  const auto bin = s_[f_.timeBin];
  const auto start = s_[f_.stepStart], end = s_[f_.stepEnd];
  const int count = setup_.solver.time_bins, aligned = bins::alignedBin(s, K);
  resizeWithHeadroom(nextBin_, active_.size());
  const std::size_t rows = active_.size();
  bool finer = false;
#pragma omp parallel for schedule(dynamic, 256) reduction(|| : finer) if (threaded(rows))
  for (std::size_t k = 0; k < rows; ++k) {
    thread_local std::vector<std::uint32_t> buf; // each thread's own
    const std::uint32_t i = active_[k];
    finer = finer || ownStep_[i] < bins::kCloseBelow * delta;
    const int own = bins::binOf(std::min(ownStep_[i], approach_[i]), delta, count);
    const int limit = bins::neighborsBin(lists(), i, bin, buf, count) + bins::kSpread;
    nextBin_[k] = std::min({own, aligned, limit});
  }
  for (std::size_t k = 0; k < active_.size(); ++k) {
    const std::uint32_t i = active_[k];
    bin[i] = nextBin_[k];
    start[i] = s, end[i] = s + (std::int32_t{1} << bin[i]);
  }
  return finer;
}

// Each owned row's step were its fastest approaching neighbor already within reach: the single
// step's signal speed (Sph::crossingTime) with that approach as the viscosity's mu. Bins from it
// (and waking by it) keep a particle from sleeping through a body that arrives faster than the
// skin of the lists lets a neighbor's bin warn it. Measured from the state the evaluation saw
// (before the kick: the ghosts hold it too), so that it is the same on any rank count.
template <int Dim> void SphMethod<Dim>::measureApproach() {
  const std::size_t n = s_.localCount();
  const auto& c = setup_.solver;
  const double alpha = c.artificial_viscosity.alpha, beta = c.artificial_viscosity.beta;
  const auto x = std::span<const Vec<Dim>>(s_[f_.x]), v = std::span<const Vec<Dim>>(s_[f_.v]);
  const auto cs = s_[f_.cs], h = s_[f_.h];
  resizeWithHeadroom(approach_, n);
#pragma omp parallel for schedule(dynamic, 256) if (threaded(n))
  for (std::size_t i = 0; i < n; ++i) {
    thread_local std::vector<std::uint32_t> buf; // each thread's own
    const double w = bins::approachSpeed<Vec<Dim>>(lists(), i, x, v, buf);
    approach_[i] = w > 0.0 ? c.cfl * h[i] / (cs[i] + 1.2 * (alpha * cs[i] + beta * w))
                           : std::numeric_limits<double>::infinity();
  }
}

// A particle more than kSpread bins above a neighbor ends its step at that neighbor's bin + 2's
// next substep (Saitoh & Makino 2009): a shock arriving from a fast neighbor finds it awake.
template <int Dim> void SphMethod<Dim>::wakeNeighbors(double delta, std::int32_t s) {
  const std::size_t n = s_.localCount();
  const auto bin = s_[f_.timeBin];
  const auto end = s_[f_.stepEnd];
  const int count = setup_.solver.time_bins;
  // Each row's new bin (or -1: awake enough) from the bins as they are, then applied.
  resizeWithHeadroom(nextBin_, n);
#pragma omp parallel for schedule(dynamic, 256) if (threaded(n))
  for (std::size_t j = 0; j < n; ++j) {
    thread_local std::vector<std::uint32_t> buf; // each thread's own
    nextBin_[j] = -1;
    if (bin[j] == 0) continue;
    const int limit = std::min(bins::neighborsBin(lists(), j, bin, buf, count) + bins::kSpread,
                               bins::binOf(approach_[j], delta, count));
    if (bin[j] > limit) nextBin_[j] = limit;
  }
  for (std::size_t j = 0; j < n; ++j)
    if (nextBin_[j] >= 0) {
      bin[j] = nextBin_[j];
      end[j] = std::min(end[j], bins::wakeEnd(s, bin[j]));
    }
}

// The ghosts' bins as their owners hold them now.
template <int Dim> void SphMethod<Dim>::refreshBins() {
  const std::vector<std::size_t> column{f_.timeBin.index};
  stats_.phases.time(kExchange, [&] { halo_.refresh(s_, column); });
  stats_.phases.time(kBoundaries, [&] { boundaries_.refreshGhosts(s_, column); });
}

// The balancing cost of the step: a row's pairs times its evaluations, plus one per substep (the
// drift and the material update of every row).
template <int Dim> void SphMethod<Dim>::countWork(int K) {
  const auto cost = s_[cost_];
  const auto bin = s_[f_.timeBin];
  const auto& nl = lists();
  for (std::size_t i = 0; i < s_.localCount(); ++i)
    cost[i] = static_cast<std::int32_t>(((1 + nl.length(i)) << (K - std::min(K, int{bin[i]}))) +
                                        (std::size_t{1} << K));
}

template double SphMethod<1>::stableTimeStep(double, std::int64_t, double);
template double SphMethod<2>::stableTimeStep(double, std::int64_t, double);
template double SphMethod<3>::stableTimeStep(double, std::int64_t, double);
template double SphMethod<1>::advanceInBins(double, std::int64_t, double);
template double SphMethod<2>::advanceInBins(double, std::int64_t, double);
template double SphMethod<3>::advanceInBins(double, std::int64_t, double);
template void SphMethod<1>::assignBins();
template void SphMethod<2>::assignBins();
template void SphMethod<3>::assignBins();

} // namespace spall::methods
