#include "spall/methods/MpmMethod.hpp"
#include "spall/solvers/MpmShapes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <numeric>

namespace spall::methods {

namespace {
// CPDI's domains: at most a cell in half-width (2 cells across: the corners' cells still meet)
// and 4 times longer than wide. The stretching bar reaches 0.75 cells and 3 at stretch 3,
// untouched; a rod's penetration shears domains to 12 cells by 1/200 of one, which turned
// points inside out (decks/topics/mpm.md).
constexpr double kDomainLongest = 1.0, kDomainAspect = 4.0;
} // namespace

template <int Dim>
MpmMethod<Dim>::MpmMethod(const parallel::MpiContext& mpi, MethodSetup setup,
                          materials::MaterialUpdate materials,
                          std::vector<std::unique_ptr<Module<Dim>>> modules, ParticleStore& store,
                          const ParticleFields<Dim>& f, Field<std::int32_t> cost,
                          parallel::Decomposition<Dim>& decomposition)
    : ParticleMethod<Dim>(mpi, sharedSetup(setup), std::move(materials), std::move(modules), store,
                          f, cost, decomposition),
      setup_(std::move(setup)) {
  haloFields_ = store.columnsWith(kHalo);
  velocityField_ = {f.v.index};
  if (f.affine.valid()) velocityField_.push_back(f.affine.index);
  fixedBodies_ = setup_.fixedBodies;
  std::sort(fixedBodies_.begin(), fixedBodies_.end());
  loaded_ = !fixedBodies_.empty() || f.confiningPressure.valid() ||
            std::any_of(modules_.begin(), modules_.end(),
                        [](const auto& m) { return m->appliesExternalForces(); });
  if (loaded_) loadFields_.push_back(f.a.index);
  if (f.confiningPressure.valid()) loadFields_.push_back(f.confiningPressure.index);
  if (!fixedBodies_.empty()) loadFields_.push_back(f.body.index);
  if (f.damage.valid())
    for (const auto& m : materials_.materials())
      zeroStress_.push_back(m.damage.has_value() && m.erosion == materials::Erosion::ZeroStress);
  rubs_ = setup_.solver.contact == Contact::Friction ||
          std::any_of(setup_.boundaries.begin(), setup_.boundaries.end(), [](const auto& b) {
            return b.type == BoundaryType::RigidWall && b.friction > 0.0;
          });
}

// t = 0 (or a body joining): the modules' initial values (the points' half-widths among them),
// p and cs, and every point's box within half a cell (GIMP's weights need it); at t = 0 also the
// grid's origin (placeOrigin). A join must not place it again: a rank that held no particle
// then has run.first == 0 too.
template <int Dim> void MpmMethod<Dim>::start(const RunStart& run) {
  for (const auto& m : modules_) m->initialise(s_, f_, run);
  materials_.evaluate(materialFields());
  const auto& mpm = setup_.solver.mpm;
  if (mpm.shape != MpmShape::Linear) {
    // GIMP: the box within half a cell; CPDI: the domain within a cell of half-width.
    const bool gimp = mpm.shape != MpmShape::Cpdi;
    double lpMax = 0.0;
    for (double lp : s_[f_.halfWidth].first(s_.localCount())) lpMax = std::max(lpMax, lp);
    lpMax = mpi_.max(lpMax);
    if (lpMax > (gimp ? 0.5 : kDomainLongest) * mpm.cell_size * (1.0 + 1e-9))
      throw DeckError(mpm.where,
                      fmt::format("solver.mpm.cell_size: a point's box (its volume's side, {:g} m) "
                                  "is wider than {}the cell, {:g} m; {} (a larger cell_size, or "
                                  "shape = \"linear\")",
                                  2.0 * lpMax, gimp ? "" : "twice ", mpm.cell_size,
                                  gimp ? "GIMP needs it within half a cell"
                                       : "CPDI keeps a domain within a cell of half-width"));
  }
  if (!originPlaced_) placeOrigin();
  makeGrid();
}

// On each axis a wall is normal to, the first such wall's plane (its constraint acts on node
// planes: with the origin a sliver off it, a Taylor bar fell a cell through its wall), else the
// lowest corner of all the points' boxes (a body's face on a grid plane). Every other wall must
// then lie on a grid plane too: a deck error if not.
template <int Dim> void MpmMethod<Dim>::placeOrigin() {
  std::array<double, Dim> lo;
  lo.fill(std::numeric_limits<double>::infinity());
  const auto x = s_[f_.x];
  const auto lp = s_[f_.halfWidth];
  for (std::size_t i = 0; i < s_.localCount(); ++i)
    for (int a = 0; a < Dim; ++a)
      lo[static_cast<std::size_t>(a)] = std::min(lo[static_cast<std::size_t>(a)], x[i][a] - lp[i]);
  MPI_Allreduce(MPI_IN_PLACE, lo.data(), Dim, MPI_DOUBLE, MPI_MIN, mpi_.comm());
  for (int a = 0; a < Dim; ++a)
    origin_[a] =
        std::isfinite(lo[static_cast<std::size_t>(a)]) ? lo[static_cast<std::size_t>(a)] : 0.0;
  const auto axisOf = [](const BoundaryConfig& b) {
    int axis = -1;
    for (int a = 0; a < Dim; ++a)
      if (b.normal[static_cast<std::size_t>(a)] != 0.0) axis = axis < 0 ? a : Dim;
    return axis; // -1 or Dim: not along one axis
  };
  std::array<bool, Dim> aligned{};
  for (const auto& b : setup_.boundaries) {
    if (b.type != BoundaryType::RigidWall) continue; // a pressure boundary has no plane
    const int a = axisOf(b);
    if (a < 0 || a >= Dim || aligned[static_cast<std::size_t>(a)]) continue;
    origin_[a] = b.point[static_cast<std::size_t>(a)];
    aligned[static_cast<std::size_t>(a)] = true;
  }
  const double hc = setup_.solver.mpm.cell_size;
  for (const auto& b : setup_.boundaries) {
    if (b.type != BoundaryType::RigidWall) continue;
    const int a = axisOf(b);
    if (a < 0 || a >= Dim)
      throw DeckError(b.where, "a rigid wall with MPM is normal to a grid axis (its constraint "
                               "acts on node planes); this one is oblique");
    const double k = (b.point[static_cast<std::size_t>(a)] - origin_[a]) / hc;
    if (std::abs(k - std::round(k)) > 1e-6)
      throw DeckError(b.where, fmt::format("this rigid wall lies {:g} cells from the grid plane "
                                           "of the first wall along its axis: with MPM every "
                                           "wall must lie on a grid plane (walls a whole number "
                                           "of cells apart, solver.mpm.cell_size {:g} m)",
                                           k, hc));
  }
  originPlaced_ = true;
}

// The state alone determines the next step (the grid is made afresh from it): nothing to
// evaluate ahead.
template <int Dim> void MpmMethod<Dim>::evaluate(std::int64_t /*step*/, double /*time*/) {}

// One step of modified update-stress-last (Sulsky, Zhou & Schreyer 1995; Nairn 2003): the
// stress of the state at t_n moves the grid, the particles follow the grid, and the stress is
// updated last with the velocity gradient of the remapped grid velocities.
template <int Dim> double MpmMethod<Dim>::advance(double dt, std::int64_t step, double time) {
  if (!grid_) makeGrid();
  stats_.phases.time(kExchange, [&] { haloForStep(); });
  stats_.phases.time(kNeighbors, [&] { idOrder(); });
  if (loaded_) stats_.phases.time(kBoundaries, [&] { loads(time); });
  const auto P = particles();
  stats_.phases.time(kForces, [&] { grid_->project(P, order_, dt); });
  // Friction's work (between bodies' fields and on walls: solvers/MpmGrid.hpp) as heat.
  if (!P.heat.empty()) {
    const auto e = s_[f_.e];
    for (std::size_t i = 0; i < s_.localCount(); ++i) e[i] += heat_[i];
  }
  if (loaded_) {
    // The loads act through the whole step as the state at t_n set them (not the leapfrog's
    // two half-kicks): the step's work is dt times their power, with the points' new
    // velocities (damping: -c m v_n+1 . v_n+1 for -c m v_n . v, an error of order c dt).
    // A fixed point's a is the support's share it cancels (solvers/MpmGrid): -m a is the
    // support's force on it, booked as SPH's FixedBodies books it.
    support_.clear();
    if (!fixedBodies_.empty()) {
      const auto a = s_[f_.a];
      const auto m = s_[f_.m];
      support_.assign(s_.localCount(), Vec<Dim>::Zero());
      for (std::size_t i = 0; i < s_.localCount(); ++i)
        if (fixedRow_[i]) support_[i] = -m[i] * a[i], a[i].setZero();
    }
    bookExternalStep(dt, externalLoad(time, support_));
  }
  stats_.phases.time(kExchange, [&] { halo_.refresh(s_, velocityField_); });
  const std::size_t n = s_.localCount();
  std::span<Tensor<3>> L;
  if (f_.hasStrength()) {
    L = s_[f_.L].first(n);
  } else {
    L_.resize(n);
    L = L_;
  }
  stats_.phases.time(kForces, [&] { grid_->velocityGradient(P, order_, L); });
  stats_.phases.time(kIntegration, [&] { deform(dt); });
  ++stats_.evaluations;
  stats_.pairs += grid_->nodes();
  stats_.phases.time(kExchange, [&] { migrateIfStale(dt, step); });
  const auto cost = s_[cost_];
  for (std::size_t i = 0; i < s_.localCount(); ++i) cost[i] = 1; // every point costs the same
  checkFinite(step + 1, time + dt);
  if (mpi_.size() > 1)
    stats_.phases.time(kExchange, [&] {
      const int before = stats_.rebalances;
      balance(step + 1, nullptr);
      rebalanced_ = stats_.rebalances != before; // it migrated and sorted every point
      if (rebalanced_) travel_ = 0.0;
    });
  return dt;
}

// Points change ranks only when some point may have moved half a cell since they last did, and
// at the decomposition's reorders (unless the rebalance that ended the last step just sorted
// them). No sum depends on which rank owns a point (every node sums in id order, the ghosts are
// chosen by position): a lagging owner only widens its rank's boxes by the travel, and with them
// the halo. Migrating every step took 15% of a 2-rank Taylor bar's step (every point's key, and
// the exchange's collectives).
template <int Dim> void MpmMethod<Dim>::migrateIfStale(double dt, std::int64_t step) {
  stats_.migrated = 0;
  double vMax = 0.0;
  for (const Vec<Dim>& v : s_[f_.v].first(s_.localCount())) vMax = std::max(vMax, v.norm());
  const double stepTravel = dt * mpi_.max(vMax);
  travel_ += stepTravel;
  haloTravel_ += stepTravel;
  const int reorder = decomposition_.reorderEvery();
  const bool sortDue = reorder > 0 && step % reorder == 0 && !rebalanced_;
  rebalanced_ = false;
  if (travel_ < 0.5 * setup_.solver.mpm.cell_size && !sortDue) return;
  const auto m = decomposition_.migrate(s_, step);
  travel_ = 0.0;
  stats_.migrated = m.moved;
  stats_.migratedTotal += m.moved;
  stats_.maxRankDistance = std::max(stats_.maxRankDistance, m.maxRankDistance);
}

// The modules' loads on the state at `time`, as SPH's force evaluation takes them: each owned
// point's external acceleration (a = 0, then the hooks: damping -c v, none on a fixed body) and
// its body's confining pressure; the ghosts get them, and which rows are a fixed body's.
template <int Dim> void MpmMethod<Dim>::loads(double time) {
  const std::size_t n = s_.localCount();
  for (auto& a : s_[f_.a].first(n)) a.setZero();
  for (const auto& m : modules_) m->beforeRates(s_, f_, time);
  for (const auto& m : modules_) m->afterRates(s_, f_, time, {s_.localCount()});
  halo_.refresh(s_, loadFields_);
  if (fixedBodies_.empty()) return;
  const std::size_t rows = n + halo_.ghosts();
  const auto body = s_[f_.body];
  fixedRow_.resize(rows);
  for (std::size_t r = 0; r < rows; ++r)
    fixedRow_[r] = std::binary_search(fixedBodies_.begin(), fixedBodies_.end(), body[r]) ? 1 : 0;
}

// Density and energy with the step's velocity gradient, then the materials: rho_{n+1} = rho_n /
// det(I + dt L) (3 x 3: in plane strain its third row is 0, in rz it holds v_r / r) (the volume
// follows F_{n+1} = (I + dt L) F_n), and de = dt sigma : D / rho with sigma the mean of the
// stresses before and after the update (the trapezoidal rule, as SPH's kick), rho at the step's
// middle.
template <int Dim> void MpmMethod<Dim>::deform(double dt) {
  const std::size_t n = s_.localCount();
  const double hc = setup_.solver.mpm.cell_size;
  const bool cpdi = setup_.solver.mpm.shape == MpmShape::Cpdi;
  const auto rho = s_[f_.rho];
  const auto e = s_[f_.e];
  const auto p = s_[f_.p];
  const std::span<const Tensor<3>> L = f_.hasStrength()
                                           ? std::span<const Tensor<3>>(s_[f_.L].first(n))
                                           : std::span<const Tensor<3>>(L_);
  auto& work = work_;
  auto& rhoMid = rhoMid_;
  work.resize(n);
  rhoMid.resize(n);
  // The bulk viscosity q_n acts through the step as the grid force took it.
  const bool viscous = f_.viscousPressure.valid();
  const auto q = viscous ? s_[f_.viscousPressure].first(n) : std::span<double>();
  const auto power = [&](std::size_t i) {
    const Tensor<3> D = 0.5 * (L[i] + L[i].transpose());
    double w = -(viscous ? p[i] + q[i] : p[i]) * D.trace();
    if (f_.hasStrength()) w += s_[f_.S][i].cwiseProduct(D).sum();
    return w;
  };
  for (std::size_t i = 0; i < n; ++i) {
    // The whole 3 x 3 increment: in rz the hoop rate L_tt changes a ring's volume too.
    const Tensor<3> F = Tensor<3>::Identity() + dt * L[i];
    // CPDI and cpGIMP: the domain follows the in-plane motion, r_i <- (I + dt L) r_i; CPDI's is
    // kept within a cell of half-width and an aspect ratio of 4 (solvers/MpmShapes.hpp,
    // regulariseDomain), cpGIMP's box is bounded where it is taken (gimpBox).
    if (f_.domain.valid()) {
      Tensor<Dim>& R = s_[f_.domain][i];
      R = (F.template topLeftCorner<Dim, Dim>() * R).eval();
      if (cpdi) solvers::mpm::regulariseDomain<Dim>(R, kDomainLongest * hc, kDomainAspect);
    }
    const double rhoNew = rho[i] / F.determinant();
    rhoMid[i] = 0.5 * (rho[i] + rhoNew);
    work[i] = power(i);
    rho[i] = rhoNew;
    e[i] += dt * work[i] / rhoMid[i];
  }
  for (const auto& m : modules_) m->beforeMaterials(s_, f_, dt);
  materials_.update(materialFields(), dt);
  for (std::size_t i = 0; i < n; ++i) e[i] += 0.5 * dt * (power(i) - work[i]) / rhoMid[i];
  materials_.evaluate(materialFields());
  if (!viscous) return;
  // The next step's bulk viscosity from this step's rate of volume change (von Neumann &
  // Richtmyer 1950, with Landshoff's linear term; Wilkins 1980, Eq. 13): in compression
  // q = rho (C_Q (l tr D)^2 + C_L l c |tr D|), l the cell: a shock spreads over a few cells
  // instead of ringing behind its front.
  const auto& mpm = setup_.solver.mpm;
  const auto cs = s_[f_.cs];
  for (std::size_t i = 0; i < n; ++i) {
    const double d = L[i].trace();
    q[i] = d < 0.0 && !carriesNoStress(i)
               ? rho[i] * hc *
                     (mpm.viscosity_quadratic * hc * d * d - mpm.viscosity_linear * cs[i] * d)
               : 0.0;
  }
}

// A point failed under zero_stress erosion: it carries no stress, so it bears no wave and no
// viscous pressure. (Its EOS sound speed, at a density nothing resists, set the step: failed
// tungsten points in the grid's compression reached 96 times the density and 260 km/s, the
// step fell 40-fold and Austin's rod into sandstone could not be run; decks/topics/mpm.md.)
template <int Dim> bool MpmMethod<Dim>::carriesNoStress(std::size_t i) const {
  if (zeroStress_.empty() || !(s_[f_.damage][i] >= 1.0)) return false;
  const auto m = static_cast<std::size_t>(s_[f_.material][i]);
  return m < zeroStress_.size() && zeroStress_[m] != 0;
}

// The grid's stability limit: a wave or a point crosses a cell in no less than dt / cfl.
template <int Dim> std::pair<double, std::size_t> MpmMethod<Dim>::localTimeStep() const {
  const auto cs = s_[f_.cs];
  const auto rho = s_[f_.rho];
  const auto v = s_[f_.v];
  double dt = std::numeric_limits<double>::infinity();
  std::size_t which = 0;
  const auto& mpm = setup_.solver.mpm;
  const double hc = mpm.cell_size;
  const bool viscous = f_.viscousPressure.valid();
  for (std::size_t i = 0; i < s_.localCount(); ++i) {
    // With a bulk viscosity, the signal speed Q + sqrt(Q^2 + c^2), Q = C_L c + C_Q l |tr D|
    // (C_Q l |tr D| <= sqrt(C_Q q / rho): from q, which restarts carry).
    double c = carriesNoStress(i) ? 0.0 : cs[i];
    if (viscous) {
      const double Q = mpm.viscosity_linear * c +
                       std::sqrt(mpm.viscosity_quadratic * s_[f_.viscousPressure][i] / rho[i]);
      c = Q + std::sqrt(Q * Q + c * c);
    }
    const double d = setup_.solver.cfl * hc / (c + v[i].norm());
    if (d < dt) dt = d, which = i;
  }
  return {dt, which};
}

// How far ghosts must reach (per axis) for each node an owned point touches to sum all of its
// points here: the reach of an owned point's nodes' other points. Collective; `changed`: whether
// this rank's rows changed since the ghosts were chosen, answered for all ranks (the same
// reduction).
template <int Dim> double MpmMethod<Dim>::haloReachNeeded(bool* changed) const {
  const std::size_t n = s_.localCount();
  // How far a point's weights reach beyond a cell: GIMP its box, CPDI its domain's corners.
  double extent = 0.0;
  const double hc = setup_.solver.mpm.cell_size;
  if (setup_.solver.mpm.shape == MpmShape::CpGimp)
    for (const Tensor<Dim>& R : s_[f_.domain].first(n))
      extent = std::max(extent, solvers::mpm::gimpBox<Dim>(R, hc).maxCoeff());
  else if (f_.domain.valid())
    for (const Tensor<Dim>& R : s_[f_.domain].first(n))
      extent = std::max(extent, R.cwiseAbs().rowwise().sum().maxCoeff());
  else
    for (double lp : s_[f_.halfWidth].first(n)) extent = std::max(extent, lp);
  // At least the kernel support: friends of friends link within it over the same ghosts.
  double hMax = 0.0;
  for (double h : s_[f_.h].first(n)) hMax = std::max(hMax, h);
  std::array<double, 3> m{extent, hMax, s_.layout() != haloLayout_ ? 1.0 : 0.0};
  MPI_Allreduce(MPI_IN_PLACE, m.data(), 3, MPI_DOUBLE, MPI_MAX, mpi_.comm());
  if (changed) *changed = m[2] > 0.0;
  return std::max(grid_->haloReach(m[0]), support() * m[1]);
}

// Ghosts: every point within the reach of an owned point's nodes' other points (per axis),
// and a margin of a quarter cell, which lets the next steps keep them (haloForStep).
template <int Dim> void MpmMethod<Dim>::exchangeHalo() {
  const std::size_t n = s_.localCount();
  const double R = haloReachNeeded() + 0.25 * setup_.solver.mpm.cell_size;
  reach_.assign(n, std::sqrt(static_cast<double>(Dim)) * R);
  boxReach_.assign(n, Vec<Dim>::Constant(R));
  halo_.build(s_, f_.x, reach_, std::span<const Vec<Dim>>(boxReach_), haloFields_);
  haloReach_ = R;
  haloTravel_ = 0.0;
  haloLayout_ = s_.layout();
  stats_.ghosts = halo_.ghosts();
  stats_.ghostFractionMax = std::max(
      stats_.ghostFractionMax, mpi_.size() == 1 || n == 0
                                   ? 0.0
                                   : static_cast<double>(halo_.ghosts()) / static_cast<double>(n));
}

// The step's ghosts: the last ones, their fields sent again, while they still hold every point
// the step needs; else chosen anew. A point needed now lies within the reach needed now of an
// owned point, and so lay within that plus twice the travel bound of it when the ghosts were
// chosen (both may have moved): kept while that is within the reach they were chosen with, and
// the owned rows are the same. Extra ghosts change no sum: every node sums the points that touch
// it, in id order, whichever rank holds them (as on any rank count). Choosing them every step
// (the domains' boxes, the plan, a collective) cost 3% of a 2-rank Taylor bar's step
// (decks/topics/mpm.md).
template <int Dim> void MpmMethod<Dim>::haloForStep() {
  bool changed = true;
  const double need = haloReachNeeded(&changed);
  if (!changed && need + 2.0 * haloTravel_ <= haloReach_)
    halo_.refresh(s_, haloFields_);
  else
    exchangeHalo();
}

template <int Dim> void MpmMethod<Dim>::makeGrid() {
  std::vector<solvers::GridWall<Dim>> walls;
  for (const auto& b : setup_.boundaries) {
    if (b.type != BoundaryType::RigidWall) continue;
    solvers::GridWall<Dim> w;
    for (int a = 0; a < Dim; ++a) {
      w.point[a] = b.point[static_cast<std::size_t>(a)];
      w.normal[a] = b.normal[static_cast<std::size_t>(a)];
    }
    w.normal.normalize();
    w.friction = b.friction;
    walls.push_back(w);
  }
  grid_ = solvers::makeMpmGrid<Dim>(setup_.solver.mpm, origin_, std::move(walls),
                                    setup_.solver.geometry == Geometry::RZ);
}

template <int Dim> solvers::MpmParticles<Dim> MpmMethod<Dim>::particles() {
  const std::size_t rows = s_.localCount() + halo_.ghosts();
  solvers::MpmParticles<Dim> P;
  P.x = s_[f_.x].first(rows);
  P.v = s_[f_.v].first(rows);
  P.a = s_[f_.a].first(rows);
  P.m = s_[f_.m].first(rows);
  P.rho = s_[f_.rho].first(rows);
  P.p = s_[f_.p].first(rows);
  P.halfWidth = s_[f_.halfWidth].first(rows);
  if (f_.hasStrength()) P.S = s_[f_.S].first(rows);
  if (f_.domain.valid()) P.domain = s_[f_.domain].first(rows);
  if (f_.viscousPressure.valid()) P.q = s_[f_.viscousPressure].first(rows);
  if (f_.affine.valid()) P.affine = s_[f_.affine].first(rows);
  P.owned = s_.localCount();
  // contact "frictionless" or "friction": a velocity field per body (solvers/MpmGrid; "auto" is
  // one field).
  if (f_.contactGroup.valid()) P.field = s_[f_.contactGroup].first(rows);
  if (rubs_) {
    heat_.assign(P.owned, 0.0);
    P.heat = heat_;
  }
  if (loaded_) P.aExt = s_[f_.a].first(rows);
  if (!fixedBodies_.empty()) P.rigid = fixedRow_;
  if (f_.confiningPressure.valid()) {
    P.load = s_[f_.confiningPressure].first(rows);
    P.loadArea = s_[f_.surfaceArea].first(P.owned);
  }
  return P;
}

// Owned and ghost rows by particle id: the order of every node's sums, the same on any rank.
// Least-significant-digit radix passes of 11 bits over id - min id on (id, row) pairs (ids are
// unique; three passes cover 8.6e9 particles): a comparison sort through the id column took 3%
// of a 2-rank MPM step.
template <int Dim> void MpmMethod<Dim>::idOrder() {
  const std::size_t rows = s_.localCount() + halo_.ghosts();
  const auto id = s_[f_.id].first(rows);
  order_.resize(rows);
  if (rows == 0) return;
  const auto [lo, hi] = std::minmax_element(id.begin(), id.end());
  const ParticleId first = *lo, span = *hi - *lo;
  idRow_.resize(rows);
  idRowTmp_.resize(rows);
  for (std::size_t r = 0; r < rows; ++r) idRow_[r] = {id[r] - first, static_cast<std::uint32_t>(r)};
  constexpr unsigned kDigit = 11, kBuckets = 1u << kDigit;
  for (unsigned shift = 0; shift < 64 && (span >> shift) != 0; shift += kDigit) {
    std::array<std::uint32_t, kBuckets + 1> count{};
    for (const auto& e : idRow_) ++count[((e.first >> shift) & (kBuckets - 1)) + 1];
    for (unsigned d = 0; d < kBuckets; ++d) count[d + 1] += count[d];
    for (const auto& e : idRow_) idRowTmp_[count[(e.first >> shift) & (kBuckets - 1)]++] = e;
    idRow_.swap(idRowTmp_);
  }
  for (std::size_t k = 0; k < rows; ++k) order_[k] = idRow_[k].second;
}

// The grid a step from this state would make (P2G on its nodes), whether or not one follows:
// the same at t = 0, after a restart and on any rank count.
template <int Dim> solvers::GridNodes<Dim> MpmMethod<Dim>::gridNodes() {
  if (!grid_) makeGrid();
  exchangeHalo();
  idOrder();
  return grid_->snapshot(particles(), order_);
}

template <int Dim> void MpmMethod<Dim>::save(io::CheckpointState& st) const {
  Base::save(st);
  st.reals["mpm_grid_origin"] = std::vector<double>(origin_.data(), origin_.data() + Dim);
  st.reals["mpm_travel"] = {travel_};
}

template <int Dim> void MpmMethod<Dim>::restore(const io::CheckpointState& st) {
  Base::restore(st);
  const auto& o = st.realArray("mpm_grid_origin");
  for (int a = 0; a < Dim; ++a) origin_[a] = o.at(static_cast<std::size_t>(a));
  originPlaced_ = true;
  // (Checkpoints written before it have none: the migration schedule only moves owners.)
  const auto travel = st.reals.find("mpm_travel");
  travel_ = travel != st.reals.end() && !travel->second.empty() ? travel->second[0] : 0.0;
  makeGrid();
}

template class MpmMethod<1>;
template class MpmMethod<2>;
template class MpmMethod<3>;

} // namespace spall::methods
