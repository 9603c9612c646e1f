#pragma once
// The grid behind solvers/MpmGrid.hpp, one class per dimension and shape (the transfers' loops
// unroll over a block's fixed count of nodes): the transfers and the nodes' numbering here, the
// contact between velocity fields in MpmGridContact.hpp, the walls and friction in
// MpmGridWalls.hpp, the pressure loads in MpmGridLoads.hpp. Private to src/solvers (MpmGrid.cpp
// makes them).
#include "spall/core/Threads.hpp"
#include "spall/solvers/MpmGrid.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace spall::solvers::grid {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max(); // the end of a list

template <int Dim, MpmShape Shape> class Grid final : public MpmGrid<Dim> {
  // A point's nodes: a fixed block (the tent, GIMP) or CPDI's list, at most K.
  static constexpr bool kBlock = Shape != MpmShape::Cpdi;
  static constexpr int K = kBlock ? mpm::kNodesPerParticle<Shape, Dim> : mpm::kCpdiEntries<Dim>;
  using Key = std::array<std::int64_t, Dim>;

public:
  Grid(const MpmConfig& c, const Vec<Dim>& origin, std::vector<GridWall<Dim>> walls, bool rz)
      : c_(c), origin_(origin), walls_(std::move(walls)), rz_(rz) {}

  double haloReach(double extent) const override {
    return Shape == MpmShape::Linear ? 2.0 * c_.cell_size : 2.0 * (c_.cell_size + extent);
  }
  std::size_t nodes() const override { return key_.size(); }
  std::size_t bytes() const override {
    return allocatedBytes(walls_, radius_, start_, X_, begin_, entryKey_, node_, S_, grad_, first_,
                          key_, box_, head_, site_, next_, fieldOf_, mass_, volume_, momentum_,
                          force_, velocity_, increment_, gradV_, beforeContact_, heat_, nodeLoad_,
                          nodeMass_, area_, rigid_, rigidV_, fixedMass_, fixedMomentum_, support_);
  }

  void project(const MpmParticles<Dim>& P, std::span<const std::uint32_t> order,
               double dt) override {
    connect(P, order.size());
    if (!P.load.empty()) nodeLoads(P, order.size());
    particleToGrid(P, order);
    updateGrid(P, dt);
    gridToParticle(P, dt);
  }

private:
  // Particle to grid (P2G), in id order: mass, momentum, internal (and external) force; with
  // contact each field's volume gradient for its normal and volume for the contact check; a fixed
  // body's velocity on its nodes (its first point's in id order); the pressure loads' areas.
  void particleToGrid(const MpmParticles<Dim>& P, std::span<const std::uint32_t> order) {
    const bool loaded = !P.load.empty(), external = !P.aExt.empty(), rigid = !P.rigid.empty();
    const std::size_t N = fields();
    mass_.assign(N, 0.0);
    momentum_.assign(N, Vec<Dim>::Zero());
    force_.assign(N, Vec<Dim>::Zero());
    if (multi_) gradV_.assign(N, Vec<Dim>::Zero()), volume_.assign(N, 0.0);
    if (loaded) area_.assign(key_.size(), Vec<Dim>::Zero());
    if (rigid) {
      rigid_.assign(N, 0), rigidV_.assign(N, Vec<Dim>::Zero());
      fixedMass_.assign(N, 0.0), fixedMomentum_.assign(N, Vec<Dim>::Zero());
    } else {
      rigid_.clear();
    }
    const bool solid = !P.S.empty(), viscous = !P.q.empty(), affine = !P.affine.empty();
    if (affine) { // each node's place (with contact, each field's)
      X_.resize(N);
      for (std::size_t I = 0; I < N; ++I) X_[I] = place(key_[lattice(I)]);
    }
    for (const std::uint32_t r : order) {
      // The stress as stress() has it, written out: this loop is the step's hottest, and the
      // call, returning a pair, was not inlined (P2G 10% slower).
      const double p = viscous ? P.p[r] + P.q[r] : P.p[r];
      Tensor<Dim> sigma = -p * Tensor<Dim>::Identity();
      if (solid) sigma += P.S[r].template topLeftCorner<Dim, Dim>();
      const double V = P.m[r] / P.rho[r];
      const Vec<Dim> mv = P.m[r] * P.v[r];
      const Tensor<Dim> mC = affine ? Tensor<Dim>(P.m[r] * P.affine[r]) : Tensor<Dim>::Zero();
      Vec<Dim> hoop = Vec<Dim>::Zero();
      const double rp = rz_ ? radius(P, r) : 1.0;
      if (rz_) hoop[0] = ((solid ? P.S[r](2, 2) : 0.0) - p) / rp;
      // The contact normal's weight: the point's area in the r-z plane in rz (its ring's volume
      // over 2 pi r_p), for its ring's volume grows with r wherever the body is, not only at
      // its surface: weighted by it, a normal one cell off the axis leaned outward by up to 45
      // degrees, and the rod's axial rings slid past the block's (rz penetration at 1.05 U_B).
      const double A = rz_ ? V / rp : V;
      for (std::size_t e = from(r); e < to(r); ++e) {
        const std::uint32_t I = node_[e];
        mass_[I] += S_[e] * P.m[r];
        if (affine)
          momentum_[I] += S_[e] * (mv + mC * (X_[I] - P.x[r]));
        else
          momentum_[I] += S_[e] * mv;
        force_[I] -= V * (sigma * grad_[e] + S_[e] * hoop);
        if (multi_) gradV_[I] += A * grad_[e], volume_[I] += S_[e] * V;
        if (external) force_[I] += (S_[e] * P.m[r]) * P.aExt[r];
        if (loaded) {
          // The load's area at the node: the shift sigma + P_I I's force is -P_I of it (with
          // its hoop part in rz), summed over every field there (applyLoads).
          const std::size_t L = lattice(I);
          if (nodeLoad_[L] > 0.0) {
            Vec<Dim> g = grad_[e];
            if (rz_) g[0] += S_[e] / rp;
            area_[L] += V * g;
          }
        }
        if (rigid && P.rigid[r]) {
          if (S_[e] > kHolds && !rigid_[I]) rigid_[I] = 1, rigidV_[I] = P.v[r];
          fixedMass_[I] += S_[e] * P.m[r];
          if (affine)
            fixedMomentum_[I] += S_[e] * (mv + mC * (X_[I] - P.x[r]));
          else
            fixedMomentum_[I] += S_[e] * mv;
        }
      }
    }
    if (loaded) applyLoads();
  }

  // The grid update: the nodes' velocities before and after the step's forces, contact between
  // the fields, walls and fixed bodies, and the FLIP increment.
  void updateGrid(const MpmParticles<Dim>& P, double dt) {
    const bool loaded = !P.load.empty(), rigid = !P.rigid.empty();
    const std::size_t N = fields();
    // The grid's velocities before and after the step's forces (with contact, each corrected:
    // the force acts on the contact-corrected velocity). Walls and fixed bodies take the normal
    // part of both, so the FLIP increment vL - v carries what acts after the force, not their
    // correction before it (a point next to a wall keeps its approach, which the remap's
    // correction takes out of L). Contact's correction before the force is the bodies' momentum
    // exchange, and the increment carries it: the points it was taken from must lose it.
    // (Kept out, as for walls, a rod's tip points kept the rod's speed while the grid moved them
    // at the interface's, the rock ahead kept its rest, and eroded tip material leaving the
    // contact went on at the rod's speed: the rod drove 43 mm into rod_into_sandstone_rz's rock
    // in 40 us against SPH's 31, through a crater no wider than itself; decks/README.md.)
    velocity_.assign(N, Vec<Dim>::Zero());
    increment_.assign(N, Vec<Dim>::Zero());
#pragma omp parallel for schedule(static) if (threaded(N))
    for (std::size_t I = 0; I < N; ++I)
      if (mass_[I] > 0.0) increment_[I] = momentum_[I] / mass_[I];
    if (rigid) prescribe(increment_);
    // Friction's work (contact()) at each field node, which G2P hands its points as heat.
    std::vector<double>* heat = nullptr;
    if (!P.heat.empty()) heat_.assign(N, 0.0), heat = &heat_;
    if (multi_) {
      beforeContact_ = increment_;
      contact(increment_, heat, nullptr);
    }
#pragma omp parallel for schedule(static) if (threaded(N))
    for (std::size_t I = 0; I < N; ++I)
      if (mass_[I] > 0.0) velocity_[I] = increment_[I] + (dt / mass_[I]) * force_[I];
    if (rigid) prescribe(velocity_);
    if (multi_) contact(velocity_, heat, &increment_);
    std::vector<Vec<Dim>>& before = multi_ ? beforeContact_ : increment_;
    // (Threads: each node writes its own entries, the heat among them.)
#pragma omp parallel for schedule(static) if (threaded(N))
    for (std::size_t I = 0; I < N; ++I) {
      if (rubs_) rub(I, before[I], velocity_[I], heat);
      constrain(I, before[I]);
      constrain(I, velocity_[I]);
      increment_[I] = velocity_[I] - before[I];
    }
    if (loaded) shareLoads(P);
    if (rigid) supports(dt);
  }

  // Grid to particle (G2P): each owned point's position, velocity (FLIP/PIC blend, or APIC's
  // velocity and affine part) and acceleration from its nodes.
  void gridToParticle(const MpmParticles<Dim>& P, double dt) {
    const bool rigid = !P.rigid.empty(), affine = !P.affine.empty();
    // The owned rows (rz: their radii at the step's start kept for the hoop rate).
    if (rz_) {
      radius_.resize(P.owned);
      for (std::size_t r = 0; r < P.owned; ++r) radius_[r] = radius(P, r);
    }
    // APIC: the owned rows' positions at the step's start, where the remap's affine part is
    // taken (the ghosts keep theirs: only owned rows move here).
    if (affine) start_.assign(P.x.begin(), P.x.begin() + static_cast<std::ptrdiff_t>(P.owned));
    const double flip = c_.flip;
    // G2P: each owned row gathers from its nodes (threads: core/Threads.hpp).
#pragma omp parallel for schedule(static) if (threaded(P.owned))
    for (std::size_t r = 0; r < P.owned; ++r) {
      if (rigid && P.rigid[r]) { // a fixed body moves at its own velocity
        P.x[r] += dt * P.v[r];
        // What the support cancels (supports()): its share of the nodes' support impulse.
        Vec<Dim> a = Vec<Dim>::Zero();
        for (std::size_t e = from(r); e < to(r); ++e)
          if (fixedMass_[node_[e]] > 0.0) a += (S_[e] / fixedMass_[node_[e]]) * support_[node_[e]];
        P.a[r] = a;
        continue;
      }
      Vec<Dim> vPic = Vec<Dim>::Zero(), dv = Vec<Dim>::Zero();
      for (std::size_t e = from(r); e < to(r); ++e) {
        vPic += S_[e] * velocity_[node_[e]];
        dv += S_[e] * increment_[node_[e]];
      }
      // Friction's heat: each (field) node's by the point's share of its mass (S_Ip m_p / m_I).
      if (!P.heat.empty()) {
        double q = 0.0;
        for (std::size_t e = from(r); e < to(r); ++e)
          if (mass_[node_[e]] > 0.0) q += S_[e] * heat_[node_[e]] / mass_[node_[e]];
        P.heat[r] = q;
      }
      P.x[r] += dt * vPic;
      P.a[r] = dv / dt;
      if (affine) { // APIC: PIC's velocity and the grid's gradient of it
        Tensor<Dim> C = Tensor<Dim>::Zero();
        for (std::size_t e = from(r); e < to(r); ++e)
          C += velocity_[node_[e]] * grad_[e].transpose();
        P.v[r] = vPic;
        P.affine[r] = C;
      } else {
        P.v[r] = flip * (P.v[r] + dv) + (1.0 - flip) * vPic;
      }
      // rz: the axis nodes keep v_r = 0, but a point's box reaches past them; one that would
      // cross the axis is folded back, as SPH's rings are.
      if (rz_ && P.x[r][0] < 0.0) {
        P.x[r][0] = -P.x[r][0];
        P.v[r][0] = -P.v[r][0];
        // CPDI: the domain's mirror image, D R D (D = diag(-1, 1); the second D keeps it
        // right-handed and its corners the same set).
        if (!P.domain.empty()) {
          Tensor<Dim>& R = P.domain[r];
          R.row(0) = -R.row(0);
          R.col(0) = -R.col(0);
        }
        if (affine) { // the velocity field's mirror image: C_rz, C_zr change sign
          Tensor<Dim>& C = P.affine[r];
          C.row(0) = -C.row(0);
          C.col(0) = -C.col(0);
        }
      }
    }
  }

public:
  void velocityGradient(const MpmParticles<Dim>& P, std::span<const std::uint32_t> order,
                        std::span<Tensor<3>> L) override {
    const std::size_t N = fields();
    momentum_.assign(N, Vec<Dim>::Zero());
    const bool affine = !P.affine.empty();
    for (const std::uint32_t r : order) {
      const Vec<Dim> mv = P.m[r] * P.v[r];
      if (affine) { // the affine part about the point's place on these weights' grid
        const Tensor<Dim> mC = P.m[r] * P.affine[r];
        const Vec<Dim>& xp = r < P.owned ? start_[r] : P.x[r];
        for (std::size_t e = from(r); e < to(r); ++e)
          momentum_[node_[e]] += S_[e] * (mv + mC * (X_[node_[e]] - xp));
        continue;
      }
      for (std::size_t e = from(r); e < to(r); ++e) {
        momentum_[node_[e]] += S_[e] * mv;
      }
    }
#pragma omp parallel for schedule(static) if (threaded(N))
    for (std::size_t I = 0; I < N; ++I)
      velocity_[I] = mass_[I] > 0.0 ? Vec<Dim>(momentum_[I] / mass_[I]) : Vec<Dim>::Zero();
    if (!rigid_.empty()) prescribe(velocity_);
    if (multi_) contact(velocity_, nullptr, nullptr); // the remap's: L only, no point's velocity
#pragma omp parallel for schedule(static) if (threaded(N))
    for (std::size_t I = 0; I < N; ++I) constrain(I, velocity_[I]);
#pragma omp parallel for schedule(static) if (threaded(P.owned))
    for (std::size_t r = 0; r < P.owned; ++r) {
      Tensor<Dim> l = Tensor<Dim>::Zero();
      double vr = 0.0; // rz: the point's radial velocity, for the hoop rate v_r / r
      for (std::size_t e = from(r); e < to(r); ++e) {
        l += velocity_[node_[e]] * grad_[e].transpose();
        vr += S_[e] * velocity_[node_[e]][0];
      }
      L[r].setZero();
      L[r].template topLeftCorner<Dim, Dim>() = l;
      if (rz_) L[r](2, 2) = vr / radius_[r];
    }
  }

  GridNodes<Dim> snapshot(const MpmParticles<Dim>& P,
                          std::span<const std::uint32_t> order) override {
    connect(P, order.size());
    const std::size_t N = fields(), nodes = key_.size();
    mass_.assign(N, 0.0);
    momentum_.assign(N, Vec<Dim>::Zero());
    force_.assign(N, Vec<Dim>::Zero());
    // Each lattice node's first row in id order with a weight there: 1 owned, 2 a ghost.
    std::vector<std::uint8_t> first(nodes, 0);
    for (const std::uint32_t r : order) {
      const auto [sigma, hoop] = stress(P, r);
      const double V = P.m[r] / P.rho[r];
      const Vec<Dim> mv = P.m[r] * P.v[r];
      for (std::size_t e = from(r); e < to(r); ++e) {
        const std::uint32_t I = node_[e];
        if (S_[e] > 0.0 && first[lattice(I)] == 0) first[lattice(I)] = r < P.owned ? 1 : 2;
        mass_[I] += S_[e] * P.m[r];
        momentum_[I] += S_[e] * mv;
        force_[I] -= V * (sigma * grad_[e] + S_[e] * hoop);
      }
    }
    std::vector<std::uint32_t> mine;
    for (std::size_t L = 0; L < nodes; ++L)
      if (first[L] == 1) mine.push_back(static_cast<std::uint32_t>(L));
    std::sort(mine.begin(), mine.end(),
              [this](std::uint32_t a, std::uint32_t b) { return key_[a] < key_[b]; });
    GridNodes<Dim> g;
    for (const std::uint32_t L : mine) {
      double m = 0.0;
      Vec<Dim> mv = Vec<Dim>::Zero(), f = Vec<Dim>::Zero();
      std::int32_t present = 0;
      // With contact, the node's fields in ascending order (numberFields), on every rank alike.
      for (std::uint32_t I = multi_ ? head_[L] : L; I != kNone; I = multi_ ? next_[I] : kNone) {
        m += mass_[I];
        mv += momentum_[I];
        f += force_[I];
        present += mass_[I] > 0.0 ? 1 : 0;
      }
      g.index.push_back(key_[L]);
      g.x.push_back(place(key_[L]));
      g.mass.push_back(m);
      g.velocity.push_back(mv / m);
      g.force.push_back(f);
      g.fields.push_back(present);
    }
    return g;
  }

private:
  // A row's Cauchy stress (the Dim x Dim block of -(p + q) I + S) and, in rz, the hoop stress's
  // share of the radial force per unit volume, sigma_tt / r (the weak form's 2 pi r dA is in the
  // ring's mass and volume: Sulsky & Schreyer 1996).
  std::pair<Tensor<Dim>, Vec<Dim>> stress(const MpmParticles<Dim>& P, std::size_t r) const {
    const bool solid = !P.S.empty();
    const double p = P.q.empty() ? P.p[r] : P.p[r] + P.q[r];
    Tensor<Dim> sigma = -p * Tensor<Dim>::Identity();
    if (solid) sigma += P.S[r].template topLeftCorner<Dim, Dim>();
    Vec<Dim> hoop = Vec<Dim>::Zero();
    if (rz_) hoop[0] = ((solid ? P.S[r](2, 2) : 0.0) - p) / radius(P, r);
    return {sigma, hoop};
  }

  // rz: a ring's radius at the step's start, and at least its box's half-width (a ring closer
  // to the axis than that lies on it; its mass, made at its first radius, would otherwise turn
  // sigma_tt / r and v_r / r infinite).
  static double radius(const MpmParticles<Dim>& P, std::size_t r) {
    return std::max(P.x[r][0], P.halfWidth[r]);
  }

  // Each row's block of nodes and weights, and the nodes numbered: densely over the rows'
  // bounding box of nodes when it is small against the entries, else by sorting the keys.
  void connect(const MpmParticles<Dim>& P, std::size_t rows) {
    begin_.resize(rows + 1);
    if constexpr (kBlock) {
      first_.resize(rows);
      S_.resize(rows * K);
      grad_.resize(rows * K);
    } else { // as many entries as the points' nodes (a 3D point's list holds up to 64)
      S_.clear();
      grad_.clear();
      entryKey_.clear();
    }
    Key lo, hi;
    lo.fill(std::numeric_limits<std::int64_t>::max());
    hi.fill(std::numeric_limits<std::int64_t>::min());
    std::size_t e = 0;
    if constexpr (kBlock) {
      // A block's K entries at r K: rows in parallel, the box's bounds (exact minima and maxima)
      // merged from each thread's.
#pragma omp parallel if (threaded(rows))
      {
        Key loT = lo, hiT = hi;
#pragma omp for schedule(static) nowait
        for (std::size_t r = 0; r < rows; ++r) {
          // GIMP: uGIMP's box, or cpGIMP's from the point's domain.
          const Vec<Dim> lp = P.domain.empty() ? Vec<Dim>::Constant(P.halfWidth[r])
                                               : mpm::gimpBox<Dim>(P.domain[r], c_.cell_size);
          const auto b = mpm::block<Shape, Dim>(P.x[r], origin_, c_.cell_size, lp);
          first_[r] = b.first;
          begin_[r] = r * K;
          for (int q = 0; q < K; ++q) {
            S_[r * K + static_cast<std::size_t>(q)] = b.S[static_cast<std::size_t>(q)];
            grad_[r * K + static_cast<std::size_t>(q)] = b.grad[static_cast<std::size_t>(q)];
          }
          for (int a = 0; a < Dim; ++a) {
            const auto sa = static_cast<std::size_t>(a);
            loT[sa] = std::min(loT[sa], b.first[sa]);
            hiT[sa] = std::max(hiT[sa], b.first[sa] + mpm::kNodesPerAxis<Shape> - 1);
          }
        }
#pragma omp critical(spall_mpm_box)
        for (std::size_t a = 0; a < Dim; ++a)
          lo[a] = std::min(lo[a], loT[a]), hi[a] = std::max(hi[a], hiT[a]);
      }
      e = rows * K;
    }
    if constexpr (!kBlock) {
      for (std::size_t r = 0; r < rows; ++r) {
        begin_[r] = e;
        const auto w = mpm::cpdi<Dim>(P.x[r], P.domain[r], origin_, c_.cell_size);
        for (int q = 0; q < w.count; ++q, ++e) {
          const auto sq = static_cast<std::size_t>(q);
          S_.push_back(w.S[sq]);
          grad_.push_back(w.grad[sq]);
          entryKey_.push_back(w.key[sq]);
          for (std::size_t a = 0; a < Dim; ++a) {
            lo[a] = std::min(lo[a], w.key[sq][a]);
            hi[a] = std::max(hi[a], w.key[sq][a]);
          }
        }
      }
    }
    begin_[rows] = e;
    node_.resize(e);
    key_.clear();
    multi_ = !P.field.empty();
    if (rows == 0) {
      site_.clear();
      head_.clear();
      return;
    }
    double boxSize = 1.0;
    for (int a = 0; a < Dim; ++a)
      boxSize *= static_cast<double>(hi[static_cast<std::size_t>(a)] -
                                     lo[static_cast<std::size_t>(a)] + 1);
    const double entries = static_cast<double>(e);
    if (boxSize <= std::max(4.0 * entries, 65536.0))
      numberDense(rows, lo, hi, static_cast<std::size_t>(boxSize));
    else
      numberSorted(rows);
    if (multi_) numberFields(P, rows);
  }

  void numberFields(const MpmParticles<Dim>& P, std::size_t rows); // MpmGridContact.hpp
  // A field node's lattice node.
  std::size_t lattice(std::size_t I) const {
    return multi_ ? site_[I] : I;
  }

  void nodeLoads(const MpmParticles<Dim>& P, std::size_t rows); // MpmGridLoads.hpp
  void applyLoads();                                            // MpmGridLoads.hpp
  void shareLoads(const MpmParticles<Dim>& P);                  // MpmGridLoads.hpp
  // A fixed body's nodes move at its velocity, whatever else weighs on them.
  void prescribe(std::vector<Vec<Dim>>& v) const {
    for (std::size_t I = 0; I < v.size(); ++I)
      if (rigid_[I]) v[I] = rigidV_[I];
  }
  // The support's impulse at each node a fixed body holds (MpmGridLoads.hpp).
  void supports(double dt);

  std::size_t fields() const {
    return multi_ ? site_.size() : key_.size();
  }

  // Corrects the fields' velocities where they meet; friction's work into *heat, with the
  // slides at the step's start from `start` if given (MpmGridContact.hpp).
  void contact(std::vector<Vec<Dim>>& v, std::vector<double>* heat,
               const std::vector<Vec<Dim>>* start) const;
  // Row r's entries [from(r), to(r)): a block's a fixed count (the loops unroll), CPDI's a list.
  std::size_t from(std::size_t r) const {
    if constexpr (kBlock)
      return r * K;
    else
      return begin_[r];
  }
  std::size_t to(std::size_t r) const {
    if constexpr (kBlock)
      return r * K + K;
    else
      return begin_[r + 1];
  }

  // A lattice node's place.
  Vec<Dim> place(const Key& k) const {
    Vec<Dim> X;
    for (int a = 0; a < Dim; ++a)
      X[a] = origin_[a] + static_cast<double>(k[static_cast<std::size_t>(a)]) * c_.cell_size;
    return X;
  }

  // Entry e's (of row r) lattice node.
  Key keyOf(std::size_t r, std::size_t e) const {
    if constexpr (!kBlock) {
      (void)r;
      return entryKey_[e];
    } else {
      const auto off = mpm::blockOffset<Shape, Dim>(static_cast<int>(e - from(r)));
      Key k = first_[r];
      for (int a = 0; a < Dim; ++a)
        k[static_cast<std::size_t>(a)] += off[static_cast<std::size_t>(a)];
      return k;
    }
  }

  void numberDense(std::size_t rows, const Key& lo, const Key& hi, std::size_t size) {
    box_.assign(size, std::numeric_limits<std::uint32_t>::max());
    for (std::size_t r = 0; r < rows; ++r)
      for (std::size_t e = from(r); e < to(r); ++e) {
        const Key k = keyOf(r, e);
        std::size_t flat = 0;
        for (int a = Dim - 1; a >= 0; --a) {
          const auto sa = static_cast<std::size_t>(a);
          flat = flat * static_cast<std::size_t>(hi[sa] - lo[sa] + 1) +
                 static_cast<std::size_t>(k[sa] - lo[sa]);
        }
        std::uint32_t& slot = box_[flat];
        if (slot == std::numeric_limits<std::uint32_t>::max()) {
          slot = static_cast<std::uint32_t>(key_.size());
          key_.push_back(k);
        }
        node_[e] = slot;
      }
  }

  void numberSorted(std::size_t rows) {
    std::vector<std::pair<Key, std::uint32_t>> all(begin_[rows]);
    for (std::size_t r = 0; r < rows; ++r)
      for (std::size_t e = from(r); e < to(r); ++e)
        all[e] = {keyOf(r, e), static_cast<std::uint32_t>(e)};
    std::sort(all.begin(), all.end());
    for (std::size_t i = 0; i < all.size(); ++i) {
      if (i == 0 || all[i].first != all[i - 1].first) key_.push_back(all[i].first);
      node_[all[i].second] = static_cast<std::uint32_t>(key_.size() - 1);
    }
  }

  double capacity(std::size_t L) const; // MpmGridContact.hpp
  // Coulomb friction of the walls the node lies on, into v^L (MpmGridWalls.hpp).
  void rub(std::size_t I, const Vec<Dim>& v, Vec<Dim>& vL, std::vector<double>* heat) const;
  // The walls (MpmGridWalls.hpp): whether a node lies on or behind one, and its velocity with
  // no part along the normal of any it does.
  bool onWall(const Vec<Dim>& X, const GridWall<Dim>& w) const;
  void constrainAt(const Key& k, Vec<Dim>& v) const;
  void constrain(std::size_t I, Vec<Dim>& v) const {
    constrainAt(key_[lattice(I)], v);
  }

  MpmConfig c_;
  Vec<Dim> origin_;
  std::vector<GridWall<Dim>> walls_;
  bool rubs_ = std::any_of(walls_.begin(), walls_.end(),
                           [](const auto& w) { return w.friction > 0.0; }); // a wall with friction
  bool rz_;                         // axisymmetric: x = r, y = z, the points rings
  std::vector<double> radius_;      // rz: the owned rings' radii for the hoop rate
  std::vector<Vec<Dim>> start_, X_; // APIC: the owned rows' places at the step's start; the nodes'
  // Per row its entries [begin_[r], begin_[r + 1]) (a block: r K + q), and per entry the node's
  // number (with contact, its (node, field) pair's), S and grad S; CPDI's lattice node.
  std::vector<std::size_t> begin_;
  std::vector<Key> entryKey_;
  std::vector<std::uint32_t> node_;
  std::vector<double> S_;
  std::vector<Vec<Dim>> grad_;
  std::vector<Key> first_;         // each row's first node
  std::vector<Key> key_;           // each numbered node's lattice index
  std::vector<std::uint32_t> box_; // dense numbering scratch
  // Contact: per node its first (node, field) pair; per pair its node, field and the next pair
  // at the node (ascending field).
  bool multi_ = false;
  std::vector<std::uint32_t> head_, site_, next_;
  std::vector<std::int32_t> fieldOf_;
  // Per node (with contact, per (node, field) pair).
  std::vector<double> mass_, volume_;
  std::vector<Vec<Dim>> momentum_, force_, velocity_, increment_, gradV_;
  std::vector<Vec<Dim>> beforeContact_; // contact: the fields' velocities before its correction
  std::vector<double> heat_;            // friction's work this step (J)
  // Loads, per lattice node: P, the loaded area sum_p V_p grad S_Ip (+ rz hoop), the mass.
  std::vector<double> nodeLoad_, nodeMass_;
  std::vector<Vec<Dim>> area_;
  // Fixed bodies: per node whether one weighs on it, and its velocity. A fixed point holds a node
  // where its weight there is more than rounding: a point on the edge of a node's support (a
  // lattice's face point, one cell and a box from the node) has S = 0 or 1e-30 by the last bit,
  // and a node held for it set the velocity that the frictionless contact compares against:
  // Lam's striker, held so by a node one cell inside it as it left a fixed anvil, flew off at
  // -15.7 to -19.6 m/s over resolutions instead of -20 (RodImpact.Case2WithMpmOnAFixedAnvil).
  static constexpr double kHolds = 1e-12;
  std::vector<std::uint8_t> rigid_;
  std::vector<Vec<Dim>> rigidV_;
  // Fixed points' mass and momentum at each node, and the support's force there (supports()).
  std::vector<double> fixedMass_;
  std::vector<Vec<Dim>> fixedMomentum_, support_;
};

} // namespace spall::solvers::grid
