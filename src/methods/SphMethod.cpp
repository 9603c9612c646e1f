#include "spall/methods/SphMethod.hpp"
#include "spall/core/Threads.hpp"

#include "spall/core/Error.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <type_traits>

namespace spall::methods {

template <int Dim>
SphMethod<Dim>::SphMethod(const parallel::MpiContext& mpi, MethodSetup setup,
                          materials::MaterialUpdate materials,
                          std::vector<std::unique_ptr<Module<Dim>>> modules, ParticleStore& store,
                          const ParticleFields<Dim>& f, Field<std::int32_t> cost,
                          parallel::Decomposition<Dim>& decomposition)
    : ParticleMethod<Dim>(mpi, sharedSetup(setup), std::move(materials), std::move(modules), store,
                          f, cost, decomposition),
      setup_(std::move(setup)), boundaries_(setup_.boundaries, store, f),
      verlet_(setup_.solver.neighbor_skin) {
  std::vector<bool> solid, failedNoTension;
  for (const auto& m : materials_.materials()) {
    solid.push_back(m.solid());
    failedNoTension.push_back(m.failedCarriesNoTension());
  }
  if (!materials_.anyDamage()) failedNoTension.clear();
  solver_ = solvers::makeSolver<Dim>({setup_.solver, solid, failedNoTension}, store, f);
  haloFields_ = store.columnsWith(kHalo);
  refreshFields_ = store.columnsWith(kRefresh);
  if (f.B.valid()) correctionFields_ = {f.B.index};
}

// ---- the step ------------------------------------------------------------------------------
// Kick-drift-kick leapfrog (Lam et al. 2001, Sec. 4.2): v_{n+1/2} = v_n + dt/2 a_n;
// x_{n+1} = x_n + dt v_{n+1/2}; v_{n+1} = v_{n+1/2} + dt/2 a_{n+1}, with e and (continuity) rho
// advanced the same way. The second half-kick is first taken with the old rates (the state the
// forces see) and corrected by dt/2 (new - old) once the new rates are known.
template <int Dim> double SphMethod<Dim>::advance(double dt, std::int64_t step, double time) {
  if (f_.binned()) return advanceInBins(dt, step, time);
  stats_.stepSubsteps = 1, stats_.stepRowEvaluations = s_.localCount();
  ++stats_.substeps, stats_.rowEvaluations += s_.localCount();
  std::size_t wrapped = 0; // particles wrapped or folded by this step
  stats_.phases.time(kIntegration, [&] {
    kickDrift(dt);
    // S_{n+1} from S_n and the last velocity gradient (explicit, like the drift), then p and cs
    // of the drifted state: the force evaluation below sees the new stress, and the new pressure
    // (with summation density, the density pass recomputes it from the new density).
    for (const auto& m : modules_) m->beforeMaterials(s_, f_, dt);
    materials_.update(materialFields(), dt);
    s_.swapValues(f_.a, f_.aOld);
    s_.swapValues(f_.dedt, f_.dedtOld);
    s_.swapValues(f_.drhodt, f_.drhodtOld);
    wrapped = boundaries_.wrapPeriodic(s_);
  });
  stats_.phases.time(kNeighbors, [&] { rebuild_ = listsStale(wrapped > 0); });
  // Particles change ranks when the lists are built: until then each stays within its ghosts'
  // reach of its domain (the skin's bound covers its travel).
  stats_.migrated = 0;
  if (rebuild_)
    stats_.phases.time(kExchange, [&] {
      const auto m = decomposition_.migrate(s_, step);
      stats_.migrated = m.moved;
      stats_.migratedTotal += m.moved;
      stats_.maxRankDistance = std::max(stats_.maxRankDistance, m.maxRankDistance);
    });
  rates(step, time + dt);
  stats_.phases.time(kIntegration, [&] {
    kick(dt);
    const std::size_t n = s_.localCount();
    boundaries_.holdVelocity(s_[f_.x].first(n), std::span<const double>(s_[f_.h]).first(n),
                             s_[f_.v].first(n), s_[f_.e].first(n));
    materials_.evaluate(materialFields()); // p, cs of the corrected state (output, next dt)
    solver_->updateSmoothing();
  });
  bookExternal(dt, externalLoad(time + dt));
  checkFinite(step + 1, time + dt);
  if (mpi_.size() > 1) stats_.phases.time(kExchange, [&] { balance(step + 1, &lists()); });
  return dt;
}

// One force evaluation: ghosts, neighbors, density, kernel correction, rates.
template <int Dim> void SphMethod<Dim>::evaluate(std::int64_t step, double time) {
  rebuild_ = true; // the first evaluation of a run (or a resumed one)
  rates(step, time);
  external_ = externalLoad(time);
  if (f_.binned()) {
    measureApproach();
    assignBins();
  }
}

template <int Dim> void SphMethod<Dim>::rates(std::int64_t step, double time) {
  if (rebuild_) {
    stats_.phases.time(kExchange, [&] { exchangeHalo(); });
    stats_.phases.time(kBoundaries, [&] {
      double hmax = 0.0;
      for (double h : s_[f_.h]) hmax = std::max(hmax, h); // owned and remote ghosts
      boundaries_.buildGhosts(s_, verlet_.widened(solver_->support()) * mpi_.max(hmax));
    });
    stats_.phases.time(kNeighbors, [&] { buildLists(); });
  } else {
    // The same ghosts, their fields as they are now.
    stats_.phases.time(kExchange, [&] { halo_.refresh(s_, haloFields_); });
    stats_.phases.time(kBoundaries, [&] { boundaries_.refreshGhosts(s_, haloFields_); });
  }
  stats_.phases.time(kNeighbors, [&] { findNeighbors(step); });
  if (solver_->usesSummationDensity()) densityPass();
  if (solver_->correctsKernel()) stats_.phases.time(kForces, [&] { kernelCorrection(); });
  stats_.phases.time(kForces, [&] { forces(time); });
}

// Whether the neighbor lists must be searched again, on every rank alike: the skin is used up
// (VerletList.hpp), or some rank's rows changed (a migration, a rebalance, friends of friends'
// ghosts), a particle was wrapped into a periodic box or folded, or crossed a wall.
template <int Dim> bool SphMethod<Dim>::listsStale(bool wrapped) {
  if (verlet_.skin() <= 0.0) return true;
  double forced = wrapped || s_.layout() != builtLayout_ ? 1.0 : 0.0;
  std::array<double, 4> m{forced, 0.0, 0.0, 0.0};
  if (forced == 0.0) {
    const std::size_t n = s_.localCount();
    const auto x = std::span<const Vec<Dim>>(s_[f_.x]).first(n);
    if (boundaries_.crossedWall(verlet_.builtPositions(), x)) m[0] = 1.0;
    const auto drift = verlet_.drift(x, s_[f_.h], anisotropicH(), solver_->support());
    std::copy(drift.begin(), drift.end(), m.begin() + 1);
  }
  MPI_Allreduce(MPI_IN_PLACE, m.data(), 4, MPI_DOUBLE, MPI_MAX, mpi_.comm());
  return m[0] > 0.0 || !verlet_.holds({m[1], m[2], m[3]});
}

template <int Dim> std::span<const Tensor<Dim>> SphMethod<Dim>::anisotropicH() const {
  return f_.anisotropic() ? std::span<const Tensor<Dim>>(s_[f_.H]) : std::span<const Tensor<Dim>>{};
}

// t = 0: the modules' initial values (H = I/h, unstressed solids), then p and cs.
template <int Dim> void SphMethod<Dim>::start(const RunStart& run) {
  for (const auto& m : modules_) m->initialise(s_, f_, run);
  materials_.evaluate(materialFields());
}

template <int Dim> void SphMethod<Dim>::kickDrift(double dt) {
  auto x = s_[f_.x];
  auto v = s_[f_.v];
  auto e = s_[f_.e];
  auto rho = s_[f_.rho];
  const auto a = s_[f_.a];
  const auto dedt = s_[f_.dedt];
  const auto drhodt = s_[f_.drhodt];
  const std::size_t n = s_.localCount();
#pragma omp parallel for schedule(static) if (threaded(n))
  for (std::size_t i = 0; i < n; ++i) {
    x[i] += dt * v[i] + (0.5 * dt * dt) * a[i];
    v[i] += dt * a[i];
    e[i] += dt * dedt[i];
  }
  if (!solver_->usesSummationDensity())
#pragma omp parallel for schedule(static) if (threaded(n))
    for (std::size_t i = 0; i < n; ++i) rho[i] += dt * drhodt[i];
}

template <int Dim> void SphMethod<Dim>::kick(double dt) {
  const double half = 0.5 * dt;
  kickRows({s_.localCount()}, [half](std::size_t) { return half; });
}

// Time bins: the closing half-kick of each active row over its own step, (s - start) delta.
template <int Dim> void SphMethod<Dim>::kickActive(double delta, std::int32_t s) {
  const auto start = s_[f_.stepStart];
  kickRows({s_.localCount(), &active_},
           [&](std::size_t i) { return 0.5 * (static_cast<double>(s - start[i]) * delta); });
}

// v, e (and with continuity rho) corrected by half(i) (new - old) rates, on `rows`.
template <int Dim>
template <class Half>
void SphMethod<Dim>::kickRows(const EvaluatedRows& rows, Half half) {
  auto v = s_[f_.v];
  auto e = s_[f_.e];
  auto rho = s_[f_.rho];
  const auto a = s_[f_.a], aOld = s_[f_.aOld];
  const auto dedt = s_[f_.dedt], dedtOld = s_[f_.dedtOld];
  const auto drhodt = s_[f_.drhodt], drhodtOld = s_[f_.drhodtOld];
  const std::size_t n = rows.size();
#pragma omp parallel for schedule(static) if (threaded(n))
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = rows[k];
    v[i] += half(i) * (a[i] - aOld[i]);
    e[i] += half(i) * (dedt[i] - dedtOld[i]);
  }
  if (!solver_->usesSummationDensity())
#pragma omp parallel for schedule(static) if (threaded(n))
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t i = rows[k];
      rho[i] += half(i) * (drhodt[i] - drhodtOld[i]);
    }
}

// Remote and periodic ghosts within each owned particle's support (widened by the skin): its
// sphere (SPH), or the bounding box of |H x| < k, half-width k |row d of H^-1| along axis d, with
// the enclosing sphere k h (ASPH).
template <int Dim> void SphMethod<Dim>::exchangeHalo() {
  const std::size_t n = s_.localCount();
  const double support = verlet_.widened(solver_->support());
  const auto h = s_[f_.h];
  resizeWithHeadroom(reach_, n);
  if (f_.anisotropic()) {
    const auto H = s_[f_.H];
    resizeWithHeadroom(boxReach_, n);
    for (std::size_t i = 0; i < n; ++i) {
      boxReach_[i] = support * H[i].inverse().rowwise().norm();
      reach_[i] = support * h[i];
    }
    halo_.build(s_, f_.x, reach_, std::span<const Vec<Dim>>(boxReach_), haloFields_);
  } else {
    for (std::size_t i = 0; i < n; ++i) reach_[i] = support * h[i];
    halo_.build(s_, f_.x, reach_, haloFields_);
  }
  stats_.ghosts = halo_.ghosts();
  stats_.ghostFractionMax = std::max(
      stats_.ghostFractionMax, mpi_.size() == 1 || n == 0
                                   ? 0.0
                                   : static_cast<double>(halo_.ghosts()) / static_cast<double>(n));
}

// The search: ASPH searches each support's ellipsoid (its bounding box), SPH its sphere; with a
// skin, wider by it, into the wide list the steps filter.
template <int Dim> void SphMethod<Dim>::buildLists() {
  const std::size_t n = s_.localCount();
  const auto H = anisotropicH();
  const bool skin = verlet_.skin() > 0.0;
  // (With a skin, the places of the order stay: the filter keeps rows in it.)
  const neighbors::CanonicalOrder<Dim> order{s_[f_.id], s_[f_.x],
                                             skin ? &verlet_.places() : nullptr};
  const auto* o = setup_.reproducible ? &order : nullptr;
  auto& list = skin ? verlet_.wide() : neighbors_;
  const double support = verlet_.widened(solver_->support());
  if (f_.anisotropic())
    neighbors::buildNeighborList<Dim>(s_[f_.x], s_[f_.h], H, n, support, grid_, list, o);
  else
    neighbors::buildNeighborList<Dim>(s_[f_.x], s_[f_.h], n, support, grid_, list, o);
  if (skin) verlet_.record(s_[f_.x], s_[f_.h], H, n);
  builtLayout_ = s_.layout();
  ++stats_.listBuilds;
}

// The step's lists (filtered from the wide one with a skin); the neighbor count is the
// load-balancing cost.
template <int Dim> void SphMethod<Dim>::findNeighbors(std::int64_t step) {
  if (verlet_.skin() > 0.0) verlet_.filter(s_[f_.x], s_[f_.h], anisotropicH(), solver_->support());
  const auto& nl = lists();
  const auto cost = s_[cost_];
  for (std::size_t i = 0; i < s_.localCount(); ++i)
    cost[i] = static_cast<std::int32_t>(1 + nl.count(i));
  stats_.pairs += nl.pairs();
  ++stats_.evaluations;
  if (mpi_.size() > 1 && step % 10 == 0) {
    // Interacting pairs whose partner lives on another rank (or is a periodic image): the
    // communication a partition causes, comparable between the SFC and METIS partitioners.
    const std::size_t lo = s_.localCount(), hi = lo + halo_.ghosts();
    std::uint64_t cut = 0;
    std::vector<std::uint32_t> row;
    for (std::size_t i = 0; i < lo; ++i)
      for (std::uint32_t j : nl.of(i, row)) cut += j >= lo && j < hi;
    stats_.crossPairs = cut;
  }
}

// Summation density, then p and cs of the new density; the ghosts receive all three again.
template <int Dim> void SphMethod<Dim>::densityPass() {
  stats_.phases.time(kDensity, [&] {
    solver_->computeDensity(lists());
    materials_.evaluate(materialFields());
  });
  stats_.phases.time(kExchange, [&] { halo_.refresh(s_, refreshFields_); });
  stats_.phases.time(kBoundaries, [&] { boundaries_.refreshGhosts(s_, refreshFields_); });
}

template <int Dim> void SphMethod<Dim>::kernelCorrection() {
  solver_->computeKernelCorrection(lists());
  halo_.refresh(s_, correctionFields_);
  boundaries_.refreshGhosts(s_, correctionFields_);
}

template <int Dim> void SphMethod<Dim>::forces(double time) {
  for (const auto& m : modules_) m->beforeRates(s_, f_, time);
  solver_->computeRates(lists(), boundaries_.firstWallImage());
  const EvaluatedRows rows{s_.localCount(), allActive_ ? nullptr : &active_};
  for (const auto& m : modules_) m->afterRates(s_, f_, time, rows);
  const std::size_t n = s_.localCount();
  boundaries_.holdAcceleration(std::span<const Vec<Dim>>(s_[f_.x]).first(n),
                               std::span<const double>(s_[f_.h]).first(n), s_[f_.a].first(n));
}

template class SphMethod<1>;
template class SphMethod<2>;
template class SphMethod<3>;

} // namespace spall::methods
