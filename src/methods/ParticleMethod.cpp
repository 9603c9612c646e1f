#include "spall/methods/ParticleMethod.hpp"

#include "spall/core/Error.hpp"
#include "spall/diagnostics/Conservation.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <type_traits>

namespace spall::methods {

ParticleMethodSetup sharedSetup(const MethodSetup& s) {
  ParticleMethodSetup c;
  for (const auto& b : s.boundaries)
    if (b.type == BoundaryType::Periodic) c.periodic.push_back({b.axis, b.min, b.max});
  c.imbalanceThreshold = s.imbalanceThreshold;
  c.timedCost = s.timedCost;
  c.nodesPerH = s.solver.nodes_per_h;
  c.note = s.note;
  return c;
}

template <int Dim>
ParticleMethod<Dim>::ParticleMethod(const parallel::MpiContext& mpi, ParticleMethodSetup setup,
                                    materials::MaterialUpdate materials,
                                    std::vector<std::unique_ptr<Module<Dim>>> modules,
                                    ParticleStore& store, const ParticleFields<Dim>& f,
                                    Field<std::int32_t> cost,
                                    parallel::Decomposition<Dim>& decomposition)
    : mpi_(mpi), common_(std::move(setup)), materials_(std::move(materials)),
      modules_(std::move(modules)), s_(store), f_(f), cost_(cost), decomposition_(decomposition),
      halo_(mpi.comm(), common_.periodic) {}

// Friends of friends among the particles and fresh ghosts (a rebalance at the end of the step may
// have moved particles since the force evaluation), with pairs from a neighbor search of their
// own: the step's list, its cost and statistics stay as they were. Wall images are no particles
// and take no part. Labels travel to the ghosts in the `fragment` column, which then receives
// each particle's place in the catalogue. The next step builds its ghosts anew.
template <int Dim>
diagnostics::FragmentCatalogue ParticleMethod<Dim>::findFragments(double linkLength,
                                                                  double damageThreshold) {
  exchangeHalo();
  const std::size_t n = s_.localCount(), rows = n + halo_.ghosts();
  neighbors::NeighborList pairs;
  neighbors::buildNeighborList<Dim>(s_[f_.x], s_[f_.h], n, this->support(), grid_, pairs, nullptr);
  const auto h = s_[f_.h];
  std::vector<double> radius(rows);
  std::vector<std::uint8_t> linkable(rows, 1);
  for (std::size_t r = 0; r < rows; ++r) radius[r] = linkLength * h[r] / common_.nodesPerH;
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
  for (const auto& p : common_.periodic) in.period[p.axis] = p.max - p.min;
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

template <int Dim>
ExternalLoad ParticleMethod<Dim>::externalLoad(double time, std::span<const Vec<Dim>> extra) const {
  if (extra.empty() && std::none_of(modules_.begin(), modules_.end(),
                                    [](const auto& m) { return m->appliesExternalForces(); }))
    return {}; // no reduction
  const std::size_t n = s_.localCount();
  externalForce_.assign(n, Vec<Dim>::Zero());
  for (const auto& m : modules_) m->addExternalForces(s_, f_, time, externalForce_);
  for (std::size_t i = 0; i < std::min(n, extra.size()); ++i) externalForce_[i] += extra[i];
  // Power F . v and force, summed independently of the particles' order and ranks.
  const auto v = s_[f_.v];
  const auto sums = diagnostics::orderFreeSums<4>(
      n,
      [&](std::size_t i, std::span<double> t) {
        const Vec<Dim>& F = externalForce_[i];
        std::fill(t.begin(), t.end(), 0.0);
        t[0] = F.dot(v[i]);
        for (int d = 0; d < Dim; ++d) t[1 + static_cast<std::size_t>(d)] = F[d];
      },
      mpi_.comm());
  return {sums[0], {sums[1], sums[2], sums[3]}};
}

// The step's share by the trapezoidal rule: second order, as the leapfrog.
template <int Dim> void ParticleMethod<Dim>::bookExternal(double dt, const ExternalLoad& now) {
  externalWork_ += 0.5 * dt * (external_.power + now.power);
  for (std::size_t d = 0; d < 3; ++d)
    externalImpulse_[d] += 0.5 * dt * (external_.force[d] + now.force[d]);
  external_ = now;
}

template <int Dim> void ParticleMethod<Dim>::bookExternalStep(double dt, const ExternalLoad& load) {
  externalWork_ += dt * load.power;
  for (std::size_t d = 0; d < 3; ++d) externalImpulse_[d] += dt * load.force[d];
  external_ = load;
}

template <int Dim> materials::MaterialFields ParticleMethod<Dim>::materialFields() {
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
    if (f_.capOverstress.valid()) {
      mf.capOverstress = s_[f_.capOverstress].first(n);
      mf.capOverstressI1 = s_[f_.capOverstressI1].first(n);
    }
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

template <int Dim>
void ParticleMethod<Dim>::balance(std::int64_t step, const neighbors::NeighborList* pairs) {
  if (common_.timedCost)
    for (std::int32_t c : s_[cost_].first(s_.localCount())) countedWork_ += c;
  stats_.imbalance = decomposition_.imbalance(s_);
  if (!decomposition_.rebalanceDue(step, stats_.imbalance)) return;
  if (common_.timedCost) weighByTime();
  const auto r = decomposition_.rebalance(s_, pairs);
  ++stats_.rebalances;
  stats_.imbalance = r.imbalanceAfter;
  if (r.metisEdgeCut >= 0) stats_.metisEdgeCut = r.metisEdgeCut;
  // Scheduled rebalances are routine; one forced by the threshold is worth a line.
  if (common_.note && r.imbalanceBefore > common_.imbalanceThreshold)
    common_.note(fmt::format(
        "rebalance at step {}: cost max/mean {:.3f} -> {:.3f}, {} particles moved{}", step,
        r.imbalanceBefore, r.imbalanceAfter, r.moved,
        r.metisEdgeCut >= 0 ? fmt::format(", METIS edge cut {} pairs", r.metisEdgeCut) : ""));
}

template <int Dim> void ParticleMethod<Dim>::weighByTime() {
  // The phases that grow with a rank's particles and pairs (not the exchanges: they wait).
  const auto& p = stats_.phases;
  const double seconds =
      p[kNeighbors] + p[kDensity] + p[kForces] + p[kIntegration] + p[kBoundaries];
  std::array<double, 2> mine{seconds - secondsAtCut_, countedWork_}, all = mine;
  MPI_Allreduce(MPI_IN_PLACE, all.data(), 2, MPI_DOUBLE, MPI_SUM, mpi_.comm());
  secondsAtCut_ = seconds;
  countedWork_ = 0.0;
  if (!(mine[0] > 0.0 && mine[1] > 0.0 && all[0] > 0.0 && all[1] > 0.0)) return;
  // A rank's seconds per counted unit over the mean; bounded, so that one stalled step (the
  // machine busy elsewhere) cannot empty a rank.
  const double weight = std::clamp((mine[0] / mine[1]) / (all[0] / all[1]), 0.25, 4.0);
  for (std::int32_t& c : s_[cost_].first(s_.localCount()))
    c = static_cast<std::int32_t>(std::max(1.0, std::round(c * weight)));
}

template <int Dim>
double ParticleMethod<Dim>::stableTimeStep(double floor, std::int64_t step, double time) {
  const auto [dtLocal, which] = localTimeStep();
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
ParticleId ParticleMethod<Dim>::setterId(double dtLocal, double dt, std::size_t which) const {
  const bool setter = dtLocal == dt && s_.localCount() > 0;
  return setter ? s_[f_.id][which] : std::numeric_limits<ParticleId>::max();
}

template <int Dim> void ParticleMethod<Dim>::checkFinite(std::int64_t step, double time) const {
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

template <int Dim> std::string ParticleMethod<Dim>::badFields(std::size_t i) const {
  std::string out;
  forEachBadField(
      i, [&out](const char* name) { out += (out.empty() ? "" : ", ") + std::string(name); });
  return out;
}

template <int Dim>
template <class Visit>
void ParticleMethod<Dim>::forEachBadField(std::size_t i, Visit&& visit) const {
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
  // CPDI: a domain turned inside out (det R <= 0) has no weights (MPM's negative Jacobian).
  if (f_.viscousPressure.valid())
    add(!std::isfinite(s_[f_.viscousPressure][i]), "viscous_pressure");
  if (f_.affine.valid()) add(!s_[f_.affine][i].allFinite(), "affine_velocity");
  if (f_.domain.valid())
    add(!(s_[f_.domain][i].determinant() > 0.0) || !s_[f_.domain][i].allFinite(),
        "particle_domain");
}

// Every rank calls this with its candidate (max() for none; `row` its owned row): the lowest
// candidate id's owner fills in the particle and every rank gets the same copy (and the owner's
// list of bad fields). Returns false when no rank had a candidate.
template <int Dim>
bool ParticleMethod<Dim>::gather(ParticleReport& fault, ParticleId mine, std::size_t row,
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
void ParticleMethod<Dim>::raise(ParticleReport fault, ParticleId mine, std::size_t row) const {
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

template <int Dim> ParticleReport ParticleMethod<Dim>::timeStepSetter() const {
  const auto [dtLocal, which] = localTimeStep();
  const double dt = mpi_.min(dtLocal);
  ParticleReport fault;
  fault.kind = ParticleReport::Kind::Collapse;
  fault.dt = dt;
  std::string fields;
  gather(fault, setterId(dtLocal, dt, which), which, fields);
  return fault;
}

template <int Dim> ParticleReport ParticleMethod<Dim>::particle(ParticleId id) const {
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
template <int Dim> void ParticleMethod<Dim>::save(io::CheckpointState& st) const {
  st.integers["rebalances"] = {stats_.rebalances};
  st.reals["external_work"] = {externalWork_,       externalImpulse_[0], externalImpulse_[1],
                               externalImpulse_[2], external_.power,     external_.force[0],
                               external_.force[1],  external_.force[2]};
  for (const auto& m : modules_) m->save(st);
}

template <int Dim> void ParticleMethod<Dim>::restore(const io::CheckpointState& st) {
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

template class ParticleMethod<1>;
template class ParticleMethod<2>;
template class ParticleMethod<3>;

} // namespace spall::methods
