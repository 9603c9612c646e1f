#include "spall/methods/SphMethod.hpp"

#include "spall/core/Error.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <type_traits>

namespace spall::methods {

template <int Dim>
SphMethod<Dim>::SphMethod(const parallel::MpiContext& mpi, SphSetup setup,
                          materials::MaterialUpdate materials,
                          std::vector<std::unique_ptr<Module<Dim>>> modules, ParticleStore& store,
                          const ParticleFields<Dim>& f, Field<std::int32_t> cost,
                          parallel::Decomposition<Dim>& decomposition)
    : mpi_(mpi), setup_(std::move(setup)), materials_(std::move(materials)),
      modules_(std::move(modules)), s_(store), f_(f), cost_(cost), decomposition_(decomposition),
      boundaries_(setup_.boundaries, store, f), halo_(mpi.comm(), boundaries_.periodicAxes()) {
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
  if (mpi_.size() > 1) stats_.phases.time(kExchange, [&] { balance(step + 1); });
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
  for (std::size_t i = 0; i < n; ++i) {
    x[i] += dt * v[i] + (0.5 * dt * dt) * a[i];
    v[i] += dt * a[i];
    e[i] += dt * dedt[i];
  }
  if (!solver_->usesSummationDensity())
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
  for (std::size_t i = 0; i < n; ++i) {
    v[i] += half * (a[i] - aOld[i]);
    e[i] += half * (dedt[i] - dedtOld[i]);
  }
  if (!solver_->usesSummationDensity())
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

// Friends of friends among the particles and fresh ghosts (a rebalance at the end of the step may
// have moved particles since the force evaluation), with pairs from a neighbor search of their
// own: the step's list, its cost and statistics stay as they were. Wall images are no particles
// and take no part. Labels travel to the ghosts in the `fragment` column, which then receives
// each particle's place in the catalogue. The next step builds its ghosts anew.
template <int Dim>
diagnostics::FragmentCatalogue SphMethod<Dim>::findFragments(double linkLength,
                                                             double damageThreshold) {
  exchangeHalo();
  const std::size_t n = s_.localCount(), rows = n + halo_.ghosts();
  neighbors::NeighborList pairs;
  neighbors::buildNeighborList<Dim>(s_[f_.x], s_[f_.h], n, solver_->support(), grid_, pairs,
                                    nullptr);
  const auto h = s_[f_.h];
  std::vector<double> radius(rows);
  std::vector<std::uint8_t> linkable(rows, 1);
  for (std::size_t r = 0; r < rows; ++r) radius[r] = linkLength * h[r] / setup_.solver.nodes_per_h;
  if (f_.hasDamage()) {
    const auto D = s_[f_.damage];
    for (std::size_t r = 0; r < rows; ++r) linkable[r] = D[r] < damageThreshold;
  }
  diagnostics::FragmentInput<Dim> in;
  in.id = s_[f_.id].first(rows);
  in.x = s_[f_.x].first(rows);
  in.v = s_[f_.v].first(rows);
  in.m = s_[f_.m].first(rows);
  in.linkRadius = radius;
  in.linkable = linkable;
  in.owned = n;
  in.pairs = &pairs;
  for (const auto& p : boundaries_.periodicAxes()) in.period[p.axis] = p.max - p.min;
  const auto carrier = s_[f_.fragment];
  const std::vector<std::size_t> column{f_.fragment.index};
  diagnostics::FragmentCatalogue cat = diagnostics::findFragments<Dim>(
      in,
      [&](std::vector<ParticleId>& labels) {
        for (std::size_t i = 0; i < n; ++i) carrier[i] = static_cast<std::int64_t>(labels[i]);
        halo_.refresh(s_, column);
        for (std::size_t r = n; r < rows; ++r) labels[r] = static_cast<ParticleId>(carrier[r]);
      },
      mpi_.comm());
  for (std::size_t i = 0; i < n; ++i) carrier[i] = cat.index[i];
  return cat;
}

template <int Dim> void SphMethod<Dim>::forces(double time) {
  for (const auto& m : modules_) m->beforeRates(s_, f_, time);
  solver_->computeRates(neighbors_);
  for (const auto& m : modules_) m->afterRates(s_, f_, time);
}

template <int Dim> ExternalLoad SphMethod<Dim>::externalLoad(double time) const {
  if (std::none_of(modules_.begin(), modules_.end(),
                   [](const auto& m) { return m->appliesExternalForces(); }))
    return {}; // no reduction
  ExternalLoad load;
  for (const auto& m : modules_) load += m->externalLoad(s_, f_, time);
  std::array<double, 4> sums{load.power, load.force[0], load.force[1], load.force[2]};
  mpi_.sumInRankOrder(sums);
  return {sums[0], {sums[1], sums[2], sums[3]}};
}

// The step's share by the trapezoidal rule: second order, as the leapfrog.
template <int Dim> void SphMethod<Dim>::bookExternal(double dt, const ExternalLoad& now) {
  externalWork_ += 0.5 * dt * (external_.power + now.power);
  for (std::size_t d = 0; d < 3; ++d)
    externalImpulse_[d] += 0.5 * dt * (external_.force[d] + now.force[d]);
  external_ = now;
}

template <int Dim> materials::MaterialFields SphMethod<Dim>::materialFields() {
  const std::size_t n = s_.localCount();
  materials::MaterialFields mf;
  mf.rho = s_[f_.rho].first(n);
  mf.e = s_[f_.e].first(n);
  mf.material = s_[f_.material].first(n);
  mf.p = s_[f_.p].first(n);
  mf.cs = s_[f_.cs].first(n);
  if (f_.hasStrength()) {
    mf.L = s_[f_.L].first(n);
    mf.S = s_[f_.S].first(n);
    mf.plasticStrain = s_[f_.plasticStrain].first(n);
    mf.temperature = s_[f_.temperature].first(n);
  }
  if (f_.hasDamage()) {
    mf.id = s_[f_.id].first(n);
    mf.damage = s_[f_.damage].first(n);
    mf.Sintact = s_[f_.Sintact].first(n);
  }
  if (f_.hasFlaws()) {
    mf.flawCount = s_[f_.flawCount].first(n);
    mf.flawsActive = s_[f_.flawsActive].first(n);
    mf.flawScale = s_[f_.flawScale].first(n);
    mf.flawNext = s_[f_.flawNext].first(n);
  }
  if (f_.hasCap()) {
    mf.volumetricStrain = s_[f_.volumetricStrain].first(n);
    mf.capPosition = s_[f_.capPosition].first(n);
    mf.porePressure = s_[f_.porePressure].first(n);
  }
  if (f_.porosity.valid()) mf.porosity = s_[f_.porosity].first(n);
  if (f_.hasPAlpha()) mf.alpha = s_[f_.alpha].first(n);
  if (f_.alphaPlastic.valid()) mf.alphaPlastic = s_[f_.alphaPlastic].first(n);
  if (f_.damageTensor.valid()) {
    mf.damageTensor = s_[f_.damageTensor].first(n);
    mf.strainTensor = s_[f_.strainTensor].first(n);
  }
  return mf;
}

// Measures the imbalance of the neighbor cost and re-cuts the key axis when due (the rows of
// the last neighbor search still match the store here, which the METIS graph needs).
template <int Dim> void SphMethod<Dim>::balance(std::int64_t step) {
  stats_.imbalance = decomposition_.imbalance(s_);
  if (!decomposition_.rebalanceDue(step, stats_.imbalance)) return;
  const auto r = decomposition_.rebalance(s_, neighbors_.offsets, neighbors_.indices);
  ++stats_.rebalances;
  stats_.imbalance = r.imbalanceAfter;
  if (r.metisEdgeCut >= 0) stats_.metisEdgeCut = r.metisEdgeCut;
  // Scheduled rebalances are routine; one forced by the threshold is worth a line.
  if (setup_.note && r.imbalanceBefore > setup_.imbalanceThreshold)
    setup_.note(fmt::format(
        "rebalance at step {}: cost max/mean {:.3f} -> {:.3f}, {} particles moved{}", step,
        r.imbalanceBefore, r.imbalanceAfter, r.moved,
        r.metisEdgeCut >= 0 ? fmt::format(", METIS edge cut {} pairs", r.metisEdgeCut) : ""));
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

template <int Dim>
double SphMethod<Dim>::stableTimeStep(double floor, std::int64_t step, double time) {
  const auto [dtLocal, which] = solver_->stableTimeStep();
  const double dt = mpi_.min(dtLocal);
  if (dt > floor && std::isfinite(dt)) return dt;
  ParticleReport fault;
  fault.kind = ParticleReport::Kind::Collapse;
  fault.step = step;
  fault.time = time;
  fault.dt = dt;
  raise(fault, setterId(dtLocal, dt, which), which);
}

// This rank's candidate for the particle that sets the global step dt (max() for none): the
// lowest id among the candidates of all ranks is the one named.
template <int Dim>
ParticleId SphMethod<Dim>::setterId(double dtLocal, double dt, std::size_t which) const {
  const bool setter = dtLocal == dt && s_.localCount() > 0;
  return setter ? s_[f_.id][which] : std::numeric_limits<ParticleId>::max();
}

template <int Dim> void SphMethod<Dim>::checkFinite(std::int64_t step, double time) const {
  const auto id = s_[f_.id];
  ParticleId bad = std::numeric_limits<ParticleId>::max();
  std::size_t row = 0;
  for (std::size_t i = 0; i < s_.localCount(); ++i) {
    bool any = false;
    if (id[i] < bad) forEachBadField(i, [&any](const char*) { any = true; });
    if (any) bad = id[i], row = i;
  }
  ParticleId first;
  MPI_Allreduce(&bad, &first, 1, MPI_UINT64_T, MPI_MIN, mpi_.comm());
  if (first == std::numeric_limits<ParticleId>::max()) return;
  ParticleReport fault;
  fault.kind = ParticleReport::Kind::NonFinite;
  fault.step = step;
  fault.time = time;
  raise(fault, bad, row);
}

template <int Dim> std::string SphMethod<Dim>::badFields(std::size_t i) const {
  std::string out;
  forEachBadField(
      i, [&out](const char* name) { out += (out.empty() ? "" : ", ") + std::string(name); });
  return out;
}

template <int Dim>
template <class Visit>
void SphMethod<Dim>::forEachBadField(std::size_t i, Visit&& visit) const {
  const auto add = [&visit](bool bad, const char* name) {
    if (bad) visit(name);
  };
  add(!s_[f_.x][i].allFinite(), "position");
  add(!s_[f_.v][i].allFinite(), "velocity");
  add(!std::isfinite(s_[f_.e][i]), "specific_internal_energy");
  add(!(s_[f_.rho][i] > 0.0) || !std::isfinite(s_[f_.rho][i]), "density");
  add(!(s_[f_.h][i] > 0.0) || !std::isfinite(s_[f_.h][i]), "smoothing_length");
  add(!std::isfinite(s_[f_.p][i]), "pressure");
  add(!std::isfinite(s_[f_.cs][i]), "sound_speed");
  if (f_.hasStrength()) add(!s_[f_.S][i].allFinite(), "stress");
  if (f_.anisotropic()) add(!s_[f_.H][i].allFinite(), "smoothing");
}

// Every rank calls this with its candidate (max() for none; `row` its owned row): the lowest
// candidate id's owner fills in the particle and every rank gets the same copy (and the owner's
// list of bad fields). Returns false when no rank had a candidate.
template <int Dim>
bool SphMethod<Dim>::gather(ParticleReport& fault, ParticleId mine, std::size_t row,
                            std::string& fields) const {
  ParticleId first;
  MPI_Allreduce(&mine, &first, 1, MPI_UINT64_T, MPI_MIN, mpi_.comm());
  if (first == std::numeric_limits<ParticleId>::max()) return false;
  int owner = mine == first ? mpi_.rank() : std::numeric_limits<int>::max();
  MPI_Allreduce(MPI_IN_PLACE, &owner, 1, MPI_INT, MPI_MIN, mpi_.comm());
  if (mpi_.rank() == owner) {
    fault.id = s_[f_.id][row];
    fault.material = s_[f_.material][row];
    fault.body = s_[f_.body][row];
    fault.neighbors = s_[cost_][row] - 1; // the cost counts the particle itself
    for (int d = 0; d < Dim; ++d) {
      fault.x[static_cast<std::size_t>(d)] = s_[f_.x][row][d];
      fault.v[static_cast<std::size_t>(d)] = s_[f_.v][row][d];
    }
    fault.rho = s_[f_.rho][row];
    fault.h = s_[f_.h][row];
    fault.p = s_[f_.p][row];
    fault.cs = s_[f_.cs][row];
    fault.e = s_[f_.e][row];
    fields = badFields(row);
  }
  static_assert(std::is_trivially_copyable_v<ParticleReport>);
  parallel::broadcast(fields, owner, mpi_.comm());
  MPI_Bcast(static_cast<void*>(&fault), sizeof(ParticleReport), MPI_BYTE, owner, mpi_.comm());
  return true;
}

template <int Dim>
void SphMethod<Dim>::raise(ParticleReport fault, ParticleId mine, std::size_t row) const {
  std::string fields;
  if (!gather(fault, mine, row, fields))
    throw StepFailure(fmt::format("time step {:.3e} s at step {} (t = {:.6e} s) and no particle "
                                  "sets it",
                                  fault.dt, fault.step, fault.time),
                      fault, "");
  const std::string what =
      fault.kind == ParticleReport::Kind::NonFinite
          ? fmt::format("non-finite state at step {} (t = {:.6e} s): {} of particle id {}",
                        fault.step, fault.time, fields, fault.id)
          : fmt::format("time step collapsed to {:.3e} s at step {} (t = {:.6e} s), set by "
                        "particle id {}",
                        fault.dt, fault.step, fault.time, fault.id);
  throw StepFailure(what, fault, fields);
}

template <int Dim> ParticleReport SphMethod<Dim>::timeStepSetter() const {
  const auto [dtLocal, which] = solver_->stableTimeStep();
  const double dt = mpi_.min(dtLocal);
  ParticleReport fault;
  fault.kind = ParticleReport::Kind::Collapse;
  fault.dt = dt;
  std::string fields;
  gather(fault, setterId(dtLocal, dt, which), which, fields);
  return fault;
}

template <int Dim> ParticleReport SphMethod<Dim>::particle(ParticleId id) const {
  const auto ids = s_[f_.id];
  std::size_t row = 0;
  ParticleId mine = std::numeric_limits<ParticleId>::max();
  for (std::size_t i = 0; i < s_.localCount(); ++i)
    if (ids[i] == id) mine = id, row = i;
  ParticleReport fault;
  std::string fields;
  gather(fault, mine, row, fields);
  return fault;
}

// The key is the checkpoint format's: unchanged since rebalances were first counted.
template <int Dim> void SphMethod<Dim>::save(io::CheckpointState& st) const {
  st.integers["rebalances"] = {stats_.rebalances};
  st.reals["external_work"] = {externalWork_,       externalImpulse_[0], externalImpulse_[1],
                               externalImpulse_[2], external_.power,     external_.force[0],
                               external_.force[1],  external_.force[2]};
  for (const auto& m : modules_) m->save(st);
}

template <int Dim> void SphMethod<Dim>::restore(const io::CheckpointState& st) {
  stats_.rebalances = static_cast<int>(st.integer("rebalances"));
  // Absent in checkpoints written before external work was booked: none was done.
  if (st.reals.count("external_work")) {
    const auto& w = st.realArray("external_work");
    externalWork_ = w.at(0);
    for (std::size_t d = 0; d < 3; ++d) externalImpulse_[d] = w.at(1 + d);
    external_.power = w.at(4);
    for (std::size_t d = 0; d < 3; ++d) external_.force[d] = w.at(5 + d);
  }
  for (const auto& m : modules_) m->restore(st);
}

template class SphMethod<1>;
template class SphMethod<2>;
template class SphMethod<3>;

} // namespace spall::methods
