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
      setup_(std::move(setup)), boundaries_(setup_.boundaries, store, f) {
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
template <int Dim> void SphMethod<Dim>::advance(double dt, std::int64_t step, double time) {
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
    boundaries_.wrapPeriodic(s_);
  });
  stats_.phases.time(kExchange, [&] {
    const auto m = decomposition_.migrate(s_, step);
    stats_.migrated = m.moved;
    stats_.migratedTotal += m.moved;
    stats_.maxRankDistance = std::max(stats_.maxRankDistance, m.maxRankDistance);
  });
  rates(step, time + dt);
  stats_.phases.time(kIntegration, [&] {
    kick(dt);
    materials_.evaluate(materialFields()); // p, cs of the corrected state (output, next dt)
    solver_->updateSmoothing();
  });
  bookExternal(dt, externalLoad(time + dt));
  checkFinite(step + 1, time + dt);
  if (mpi_.size() > 1)
    stats_.phases.time(kExchange,
                       [&] { balance(step + 1, neighbors_.offsets, neighbors_.indices); });
}

// One force evaluation: ghosts, neighbors, density, kernel correction, rates.
template <int Dim> void SphMethod<Dim>::evaluate(std::int64_t step, double time) {
  rates(step, time);
  external_ = externalLoad(time);
}

template <int Dim> void SphMethod<Dim>::rates(std::int64_t step, double time) {
  stats_.phases.time(kExchange, [&] { exchangeHalo(); });
  stats_.phases.time(kBoundaries, [&] {
    double hmax = 0.0;
    for (double h : s_[f_.h]) hmax = std::max(hmax, h); // owned and remote ghosts
    boundaries_.buildGhosts(s_, solver_->support() * mpi_.max(hmax));
  });
  stats_.phases.time(kNeighbors, [&] { findNeighbors(step); });
  if (solver_->usesSummationDensity()) densityPass();
  if (solver_->correctsKernel()) stats_.phases.time(kForces, [&] { kernelCorrection(); });
  stats_.phases.time(kForces, [&] { forces(time); });
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
  auto v = s_[f_.v];
  auto e = s_[f_.e];
  auto rho = s_[f_.rho];
  const auto a = s_[f_.a], aOld = s_[f_.aOld];
  const auto dedt = s_[f_.dedt], dedtOld = s_[f_.dedtOld];
  const auto drhodt = s_[f_.drhodt], drhodtOld = s_[f_.drhodtOld];
  const double half = 0.5 * dt;
  const std::size_t n = s_.localCount();
#pragma omp parallel for schedule(static) if (threaded(n))
  for (std::size_t i = 0; i < n; ++i) {
    v[i] += half * (a[i] - aOld[i]);
    e[i] += half * (dedt[i] - dedtOld[i]);
  }
  if (!solver_->usesSummationDensity())
#pragma omp parallel for schedule(static) if (threaded(n))
    for (std::size_t i = 0; i < n; ++i) rho[i] += half * (drhodt[i] - drhodtOld[i]);
}

// Remote and periodic ghosts within each owned particle's support: its sphere (SPH), or the
// bounding box of |H x| < k, half-width k |row d of H^-1| along axis d, with the enclosing
// sphere k h (ASPH).
template <int Dim> void SphMethod<Dim>::exchangeHalo() {
  const std::size_t n = s_.localCount();
  const auto h = s_[f_.h];
  reach_.resize(n);
  if (f_.anisotropic()) {
    const auto H = s_[f_.H];
    boxReach_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      boxReach_[i] = solver_->support() * H[i].inverse().rowwise().norm();
      reach_[i] = solver_->support() * h[i];
    }
    halo_.build(s_, f_.x, reach_, std::span<const Vec<Dim>>(boxReach_), haloFields_);
  } else {
    for (std::size_t i = 0; i < n; ++i) reach_[i] = solver_->support() * h[i];
    halo_.build(s_, f_.x, reach_, haloFields_);
  }
  stats_.ghosts = halo_.ghosts();
  stats_.ghostFractionMax = std::max(
      stats_.ghostFractionMax, mpi_.size() == 1 || n == 0
                                   ? 0.0
                                   : static_cast<double>(halo_.ghosts()) / static_cast<double>(n));
}

// ASPH searches each support's ellipsoid (its bounding box), SPH its sphere; the neighbor count
// is the load-balancing cost.
template <int Dim> void SphMethod<Dim>::findNeighbors(std::int64_t step) {
  const auto H = f_.anisotropic() ? s_[f_.H] : std::span<Tensor<Dim>>{};
  const auto build = [&](const neighbors::CanonicalOrder<Dim>* order) {
    return f_.anisotropic()
               ? neighbors::buildNeighborList<Dim>(s_[f_.x], s_[f_.h],
                                                   std::span<const Tensor<Dim>>(H), s_.localCount(),
                                                   solver_->support(), grid_, neighbors_, order)
               : neighbors::buildNeighborList<Dim>(s_[f_.x], s_[f_.h], s_.localCount(),
                                                   solver_->support(), grid_, neighbors_, order);
  };
  if (setup_.reproducible) {
    const neighbors::CanonicalOrder<Dim> order{s_[f_.id], s_[f_.x], canonicalH()};
    if (!build(&order)) stats_.canonicalLost = true;
  } else {
    build(nullptr);
  }
  const auto cost = s_[cost_];
  for (std::size_t i = 0; i < s_.localCount(); ++i)
    cost[i] = static_cast<std::int32_t>(1 + neighbors_.offsets[i + 1] - neighbors_.offsets[i]);
  stats_.pairs += neighbors_.pairs();
  ++stats_.evaluations;
  if (mpi_.size() > 1 && step % 10 == 0) {
    // Interacting pairs whose partner lives on another rank (or is a periodic image): the
    // communication a partition causes, comparable between the SFC and METIS partitioners.
    const std::size_t lo = s_.localCount(), hi = lo + halo_.ghosts();
    std::uint64_t cut = 0;
    for (std::uint32_t j : neighbors_.indices) cut += j >= lo && j < hi;
    stats_.crossPairs = cut;
  }
}

// Summation density, then p and cs of the new density; the ghosts receive all three again.
template <int Dim> void SphMethod<Dim>::densityPass() {
  stats_.phases.time(kDensity, [&] {
    solver_->computeDensity(neighbors_);
    materials_.evaluate(materialFields());
  });
  stats_.phases.time(kExchange, [&] { halo_.refresh(s_, refreshFields_); });
  stats_.phases.time(kBoundaries, [&] { boundaries_.refreshGhosts(s_, refreshFields_); });
}

template <int Dim> void SphMethod<Dim>::kernelCorrection() {
  solver_->computeKernelCorrection(neighbors_);
  halo_.refresh(s_, correctionFields_);
  boundaries_.refreshGhosts(s_, correctionFields_);
}

template <int Dim> void SphMethod<Dim>::forces(double time) {
  for (const auto& m : modules_) m->beforeRates(s_, f_, time);
  solver_->computeRates(neighbors_);
  for (const auto& m : modules_) m->afterRates(s_, f_, time);
}

// The geometric mean of the owned particles' h over all ranks, summed exactly (log2 h in fixed
// point, integer allreduce): the same value on any rank count, which a canonical neighbor
// order needs for its grid.
template <int Dim> double SphMethod<Dim>::canonicalH() const {
  std::int64_t sum[2] = {0, 0};
  for (double h : s_[f_.h].first(s_.localCount())) {
    if (!(h > 0.0) || !std::isfinite(h)) continue;
    sum[0] += std::llround(std::log2(h) * 1048576.0);
    ++sum[1];
  }
  MPI_Allreduce(MPI_IN_PLACE, sum, 2, MPI_INT64_T, MPI_SUM, mpi_.comm());
  if (sum[1] == 0) return 1.0;
  return std::exp2(static_cast<double>(sum[0]) / 1048576.0 / static_cast<double>(sum[1]));
}

template class SphMethod<1>;
template class SphMethod<2>;
template class SphMethod<3>;

} // namespace spall::methods
