#pragma once
// SPH's and ASPH's solver (solvers/SphSolver.hpp's makeSolver): the class, its density, kernel
// correction and smoothing updates; its force loop is in SphRatesLoop.hpp. Private to
// src/solvers (one translation unit instantiates it).
#include "spall/core/Threads.hpp"
#include "spall/solvers/SphSolver.hpp"

#include "spall/core/MemoryAccounting.hpp"
#include "spall/core/SymmetricEigen.hpp"
#include "spall/core/SymmetricTensor.hpp"
#include "spall/kernels/Kernels.hpp"
#include "spall/kernels/PsiTable.hpp"
#include "spall/solvers/Axisymmetric.hpp"
#include "spall/solvers/CrackedPairs.hpp"
#include "spall/solvers/IdealH.hpp"
#include "spall/solvers/SphPairTerms.hpp"
#include "spall/solvers/VoronoiCell.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

namespace spall::solvers::sph {

template <int Dim> double ipow(double x) {
  if constexpr (Dim == 1)
    return x;
  else if constexpr (Dim == 2)
    return x * x;
  else
    return x * x * x;
}

// What the force loop carries: pressure alone (no material has strength), the full Cauchy stress
// -p I + S, or the full stress with the corrected kernel gradient B_i grad W.
enum class Stress { Pressure, Cauchy, CorrectedCauchy };

// Aniso: ASPH (Owen 2010, Sec. II): a symmetric tensor H per particle instead of 1/h, kernels
// evaluated at eta = |H x| with the normalisation det H, and their gradients
// grad_x W(|H x|) = det(H) W'(eta) H^T H x / eta. With H = I/h every expression below is the SPH
// one (unit-tested), so the SPH instantiation keeps its own scalar arithmetic.
template <int Dim, class K, bool Aniso> class Sph final : public Solver<Dim> {
  using KW = kernels::Kernel<K, Dim>;

public:
  Sph(const SolverSetup& setup, ParticleStore& store, const ParticleFields<Dim>& f)
      : cfg_(setup.config), solid_(setup.solid), failedNoTension_(setup.failedCarriesNoTension),
        s_(store), f_(f), psi_(kernels::PsiTable::build<KW, Dim>()) {}

  double support() const override { return K::support; }
  bool usesSummationDensity() const override { return cfg_.density != DensityMethod::Continuity; }

  void computeDensity(const neighbors::NeighborList& nl) override {
    const auto x = s_[f_.x];
    const auto h = s_[f_.h];
    const auto m = planarMass();
    const auto rho = s_[f_.rho];
    const std::size_t n = s_.localCount();
    const bool normalise = cfg_.density == DensityMethod::NormalizedSummation;
    // Lam et al. (2001) Eq. 25 divides by the kernel sum of volumes m_j/rho_j, which needs the
    // previous densities of all particles (ghosts included): keep them while rho is overwritten.
    if (normalise) rhoPrev_.assign(rho.begin(), rho.end());
    const double W0 = K::sigma() * K::f(0.0);
    const auto Hs = Aniso ? s_[f_.H] : std::span<Tensor<Dim>>{};
    const EvaluatedRows rows = this->passRows(n);
#pragma omp parallel for schedule(dynamic, 64) if (threaded(rows.size()))
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const std::size_t i = rows[k];
      const double hinv = 1.0 / h[i];
      const double norm = Aniso ? Hs[i].determinant() : ipow<Dim>(hinv);
      double sum = m[i] * W0;
      double vol = normalise ? m[i] / rhoPrev_[i] * W0 : 0.0;
      thread_local std::vector<std::uint32_t> rowBuf; // each thread's own
      for (std::uint32_t j : nl.of(i, rowBuf)) {
        const double q = Aniso ? (Hs[i] * (x[i] - x[j])).norm() : (x[i] - x[j]).norm() * hinv;
        if (q >= K::support) continue;
        const double w = K::sigma() * K::f(q);
        sum += m[j] * w;
        if (normalise) vol += m[j] / rhoPrev_[j] * w;
      }
      rho[i] = normalise ? sum / vol : sum * norm;
    }
  }

  // Randles & Libersky (1996): M_i = -sum_j V_j x_ij (x) grad_i W_ij is I for a full, even
  // neighborhood; B_i = M_i^-T makes B_i grad W exact for linear fields whatever the neighbors,
  // free surfaces included. A particle with neighbors on too few sides to invert M (|det M| <
  // 0.01: a lone particle, a chain) keeps the plain gradient (B = I), and so does a particle at a
  // crack (a failed particle or a neighbor of one; so both rows of a cracked pair): the field it
  // would fit is not linear across an open crack, the cracked pairs it would be normalised over
  // are left out of its velocity gradient, and a failed particle whose neighbors have flown off
  // has an ill-conditioned M (the damaged stretching rod launched one at km/s by B times its
  // contact pressure).
  void computeKernelCorrection(const neighbors::NeighborList& nl) override {
    if (!f_.B.valid()) return;
    const bool cracks = markCracks();
    const auto x = s_[f_.x];
    const auto h = s_[f_.h];
    const auto m = planarMass();
    const auto rho = s_[f_.rho];
    const auto B = s_[f_.B];
    const double sigma = K::sigma();
    if constexpr (Aniso) prepareAnisoRows();
    const EvaluatedRows rows = this->passRows(s_.localCount());
#pragma omp parallel for schedule(dynamic, 64) if (threaded(rows.size()))
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const std::size_t i = rows[k];
      const double hiInv = 1.0 / h[i], gradNormI = sigma * ipow<Dim>(hiInv) * hiInv;
      Tensor<Dim> M = Tensor<Dim>::Zero();
      bool atCrack = cracks && cracks_.failed(i);
      thread_local std::vector<std::uint32_t> rowBuf; // each thread's own
      for (std::uint32_t j : nl.of(i, rowBuf)) {
        if (cracks) atCrack = atCrack || cracks_.failed(j);
        const Vec<Dim> xij = x[i] - x[j];
        const double r = xij.norm();
        if (r == 0.0) continue;
        Vec<Dim> gradW; // the force loop's gradient
        if constexpr (Aniso) {
          gradW = 0.5 * (anisoGradient(i, xij) + anisoGradient(j, xij));
        } else {
          const double hjInv = 1.0 / h[j];
          const double qi = r * hiInv, qj = r * hjInv;
          const double dWi = qi < K::support ? gradNormI * K::df(qi) : 0.0;
          const double dWj = qj < K::support ? sigma * ipow<Dim>(hjInv) * hjInv * K::df(qj) : 0.0;
          gradW = (0.5 * (dWi + dWj) / r) * xij;
        }
        M.noalias() -= (m[j] / rho[j]) * (xij * gradW.transpose());
      }
      B[i].setIdentity();
      if (!atCrack && std::abs(M.determinant()) > 1.0e-2)
        B[i].template topLeftCorner<Dim, Dim>() = M.inverse().transpose();
    }
  }
  bool correctsKernel() const override {
    return f_.B.valid();
  }

  void computeRates(const neighbors::NeighborList& nl, std::size_t firstWallImage) override {
    if (!f_.hasStrength())
      ratesLoop<Stress::Pressure>(nl, firstWallImage);
    else if (f_.B.valid())
      ratesLoop<Stress::CorrectedCauchy>(nl, firstWallImage);
    else
      ratesLoop<Stress::Cauchy>(nl, firstWallImage);
    if constexpr (Aniso) cutVoronoiCells(nl);
  }

  // Owen (2010) Eqs. 1-4 (solvers/IdealH.hpp): n_h from the last loop's Psi_0, then h, or H with
  // its shape from the Voronoi cells of the same loop.
  void updateSmoothing() override {
    const auto h = s_[f_.h];
    const auto m = planarMass();
    const auto rho = s_[f_.rho];
    const auto sumWH = s_[f_.sumWH];
    const SmoothingLimits lim{cfg_.nodes_per_h, cfg_.h_min,       cfg_.h_max,
                              cfg_.h_min_ratio, cfg_.h_max_ratio, cfg_.max_aspect_ratio};
    const EvaluatedRows rows = this->passRows(s_.localCount());
#pragma omp parallel for schedule(static) if (threaded(rows.size()))
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const std::size_t i = rows[k];
      const double factor = sizeFactor(psi_.nodesPerH(root<Dim>(sumWH[i])), cfg_.nodes_per_h);
      if constexpr (Aniso) {
        const Tensor<Dim>& C = s_[f_.cellMoment][i]; // zero where the cell was open
        idealHTensor<Dim>(s_[f_.H][i], h[i], factor, C(0, 0) > 0.0 ? &C : nullptr, m[i], rho[i],
                          lim);
      } else {
        h[i] = idealH<Dim>(h[i], factor, m[i], rho[i], lim);
      }
    }
  }

  std::pair<double, std::size_t> stableTimeStep() const override {
    // The smallest step and, among equal ones, the first particle: each thread's own over its
    // rows, then the threads' in a fixed order (the sequential loop's answer on any count).
    double dt = std::numeric_limits<double>::infinity();
    std::size_t which = 0;
#pragma omp parallel if (threaded(s_.localCount()))
    {
      double dtT = std::numeric_limits<double>::infinity();
      std::size_t whichT = 0;
#pragma omp for schedule(static) nowait
      for (std::size_t i = 0; i < s_.localCount(); ++i) {
        const double dti = crossingTime(i);
        if (dti < dtT) dtT = dti, whichT = i;
      }
#pragma omp critical(spall_sph_dt)
      if (dtT < dt || (dtT == dt && whichT < which)) dt = dtT, which = whichT;
    }
    return {cfg_.cfl * dt, which};
  }

  void particleTimeSteps(std::span<double> dt) const override {
#pragma omp parallel for schedule(static) if (threaded(s_.localCount()))
    for (std::size_t i = 0; i < s_.localCount(); ++i) dt[i] = cfg_.cfl * crossingTime(i);
  }

  double nodesPerH(std::size_t i) const override {
    return psi_.nodesPerH(root<Dim>(s_[f_.sumWH][i]));
  }

  std::size_t scratchBytes() const override {
    return allocatedBytes(areaMass_, ringR_, rowScratch_, sOverRho_, artificialStress_, tensile_,
                          strainRate_, isochoric_, rhoPrev_, divNew_, curlNew_, anisoRow_) +
           cracks_.bytes();
  }

private:
  // Particle i's step at cfl 1: Monaghan (1992), the signal speed c + 1.2 (alpha c + beta max
  // mu_ij) across h, and the force limit sqrt(h / |a|).
  double crossingTime(std::size_t i) const {
    const double alpha = cfg_.artificial_viscosity.alpha, beta = cfg_.artificial_viscosity.beta;
    const double cs = s_[f_.cs][i];
    const double signal = cs + 1.2 * (alpha * cs + beta * s_[f_.muMax][i]);
    // ASPH: the shortest axis of the smoothing ellipsoid, 1/lambda_max(H).
    const double hi = Aniso ? 1.0 / largestEigenvalue<Dim>(s_[f_.H][i]) : s_[f_.h][i];
    double dti = signal > 0.0 ? hi / signal : std::numeric_limits<double>::infinity();
    const double an = s_[f_.a][i].norm();
    if (an > 0.0) dti = std::min(dti, std::sqrt(hi / an));
    return dti;
  }

  // Lam et al. (2001) Eqs. 20-21 in tensor form, dv_i/dt = sum_j m_j (sigma_i/rho_i^2 +
  // sigma_j/rho_j^2 - Pi_ij I) . grad_i W_ij, with sigma = -p I + S. Hydro decks have S = 0, so
  // the contraction is the scalar pressure term below (strength adds S in its own instantiation).
  // RhoProduct replaces the bracket by (sigma_i + sigma_j)/(rho_i rho_j): at an interface with
  // a density ratio of ~8 (copper/PMMA) the rho^2 form lets the heavy particles penetrate the
  // light ones under tension, this one does not. The energy rate below is the matching one, so
  // either form conserves total energy exactly in the semi-discrete sense.
  // grad_i W_ij is the average of both supports' gradients, which keeps the pair force
  // antisymmetric (momentum conserved to round-off) for unequal h.
  // With the corrected kernel gradient (Bonet & Lok 1999) every grad W that multiplies a
  // particle's own quantity becomes B grad W with that particle's B: sigma_i/rho_i^2 B_i grad W +
  // sigma_j/rho_j^2 B_j grad W. The pair force stays antisymmetric (momentum is conserved), and
  // e_i's own share -sigma_i/rho_i^2 : (m_j v_ij (x) B_i grad W) is sigma_i : L_i/rho_i with the
  // same corrected L_i, so total energy stays conserved pair by pair too. At a free surface the
  // plain form under-reads the stress divergence, and the velocity divergence that drives the
  // density, by the missing part of the support: a clamped plate bends 20% too easily with
  // 10 particles through its thickness (elastic_plate_2d); corrected, it is within a few percent.
  // The Balsara switch and the product form are per-particle factors (rowScratch_), not
  // instantiations.
  template <Stress Mode>
  void ratesLoop(const neighbors::NeighborList& nl, std::size_t firstWallImage);
  // The loop itself, a term a function (SphRatesLoop.hpp).
  template <Stress Mode> class RatesLoop;

  // ---- ASPH -------------------------------------------------------------------------------
  struct AnisoRow {
    Tensor<Dim> G;   // H^T H, the metric of eta: eta^2 = x . G x
    double normGrad; // sigma det H, the kernel's normalisation
  };
  // H^T H and sigma det H of every row, ghosts included, once per loop (what the pair loop
  // gathers of a neighbor, packed).
  void prepareAnisoRows() {
    const auto Hs = s_[f_.H];
    resizeWithHeadroom(anisoRow_, s_.size());
#pragma omp parallel for schedule(static) if (threaded(s_.size()))
    for (std::size_t j = 0; j < s_.size(); ++j)
      anisoRow_[j] = {Hs[j].transpose() * Hs[j], K::sigma() * Hs[j].determinant()};
  }
  // ASPH: the Voronoi cells of the owned rows, the target shapes of their next H, a pass after
  // the force loop (SphVoronoiCells.hpp).
  void cutVoronoiCells(const neighbors::NeighborList& nl);
  void cutVoronoiCell(std::size_t i, std::span<const std::uint32_t> row);
  // grad_x W(|H_k x|) at x = x_ij with row k's tensor: det(H) W'(eta) H^T H x / eta.
  Vec<Dim> anisoGradient(std::size_t k, const Vec<Dim>& xij) const {
    const AnisoRow& row = anisoRow_[k];
    const Vec<Dim> g = row.G * xij;
    const double eta = std::sqrt(xij.dot(g));
    if (eta >= K::support || eta == 0.0) return Vec<Dim>::Zero();
    return (row.normGrad * K::df(eta) / eta) * g;
  }

  // The mass the planar loops weigh a row with: m, or in rz the ring's area mass m/(2 pi r) (of
  // every row, ghosts and axis images included; solvers/Axisymmetric.hpp).
  std::span<const double> planarMass() {
    const auto m = s_[f_.m];
    if (cfg_.geometry != Geometry::RZ) return m;
    const auto x = s_[f_.x];
    const auto h = s_[f_.h];
    resizeWithHeadroom(areaMass_, s_.size());
    resizeWithHeadroom(ringR_, s_.size());
#pragma omp parallel for schedule(static) if (threaded(s_.size()))
    for (std::size_t j = 0; j < s_.size(); ++j) {
      ringR_[j] = rz::radius(x[j][0], h[j]);
      areaMass_[j] = rz::areaMass(m[j], ringR_[j]);
    }
    return areaMass_;
  }
  std::vector<double> areaMass_, ringR_; // rz: mu and R of every row

  SolverConfig cfg_;
  std::vector<bool> solid_;           // by material: has strength
  std::vector<bool> failedNoTension_; // by material: a failed particle carries no tension
  CrackedPairs<Dim> cracks_;          // the failed rows and their neighbors
  struct RowScratch {
    double hInv, gradNorm, vol;
    double q, s;    // the pressure term's per-row factors (see ratesLoop)
    double balsara; // Balsara (1995) factor, 1 when the switch is off
  };
  std::vector<RowScratch> rowScratch_; // scratch of the force loop
  // Symmetric, so stored as such (core/SymmetricTensor.hpp), and in single precision: 24 bytes a
  // row each in 3D, not 72. Each is a factor of pair terms that only a sum reads; i and j read the
  // same rounded values, so the pair force stays antisymmetric (momentum and energy conserved as
  // before), and rounding to ~1e-7 of a row's own stress (S/rho^2 is rounded twice: S's
  // symmetric part, then the quotient) is far below the sums' discretisation error (measured:
  // decks/README, where summary.json's memory_parts are described).
  using RowTensor = SymTensor<Dim, float>;
  std::vector<RowTensor> sOverRho_;         // scratch of the force loop (solids)
  std::vector<RowTensor> artificialStress_; // R of every row (solids, when enabled)
  std::vector<std::uint8_t> tensile_;       // R != 0: the row is in tension
  std::vector<RowTensor> strainRate_;       // sym L of every row (reconstructed viscosity)
  std::vector<double> isochoric_;           // pair::isochoricGate of every row
  // Marks the failed rows (ghosts included); whether any row failed at all.
  bool markCracks() {
    if (failedNoTension_.empty() || !f_.hasDamage()) return false;
    return cracks_.mark(s_[f_.damage], s_[f_.material], failedNoTension_);
  }
  // What the reconstruction needs of the row's own particle, once a row: its D in double
  // precision (exactly the stored value), its gate, and q_c = 1/n_h: the same bits as taking
  // them a pair at a time, and taylor_bar_3d's force loop 1.3% faster (200 steps, medians of 3).
  struct ReconstructionRow {
    SymTensor<Dim> D;
    double gate = 1.0, qc = 0.0;
  };
  ReconstructionRow reconstructionRow(std::size_t i) const {
    ReconstructionRow r;
    for (std::size_t k = 0; k < r.D.a.size(); ++k)
      r.D.a[k] = static_cast<double>(strainRate_[i].a[k]);
    r.gate = isochoric_[i];
    r.qc = 1.0 / cfg_.nodes_per_h;
    return r;
  }
  // Out of line: the pair loop is register-bound, and only approaching pairs call it.
  [[gnu::noinline]] double reconstructedApproach(double vr, const Vec<Dim>& xij,
                                                 const ReconstructionRow& own, std::size_t j,
                                                 double q) const {
    return pair::reconstructedApproach(vr, own.D.quadraticForm(xij),
                                       strainRate_[j].quadraticForm(xij), q, own.qc,
                                       0.5 * (own.gate + isochoric_[j]));
  }
  // SPH: the kernel values of the pairs of a row, before the force loop visits it. The square
  // root, the division and the kernel of a pair wait on each other; in a short loop of their own,
  // written to columns and without branches (df is 0 outside the support), the compiler runs a
  // vector register's worth of pairs at once (gathers of x_j, 1/h_j and j's normalisation).
  // It needs -fno-math-errno (CMakeLists.txt): else a square root may call the library.
  struct PairKernels {
    std::vector<double> gW;    // (dW_i + dW_j)/2 / r: grad W = gW x_ij, the pair's mean gradient
    std::vector<double> gWi;   // dW_i / r: i's own gradient (continuity)
    std::vector<double> qMean; // (q_i + q_j)/2
    std::vector<double> wH;    // W^H(q_i) = sigma |df(q_i)|, 0 outside i's support (Owen 2010)
  };
  void pairKernels(const Vec<Dim>& xi, double hiInv, double gradNormI,
                   std::span<const std::uint32_t> row, PairKernels& out) const {
    static_assert(sizeof(Vec<Dim>) == Dim * sizeof(double) &&
                  sizeof(RowScratch) % sizeof(double) == 0 &&
                  offsetof(RowScratch, gradNorm) == sizeof(double));
    constexpr std::size_t kStride = sizeof(RowScratch) / sizeof(double);
    const std::size_t n = row.size();
    for (auto* c : {&out.gW, &out.gWi, &out.qMean, &out.wH})
      if (c->size() < n) c->resize(n);
    const double* x = s_[f_.x].data()->data();
    const double* scratch = &rowScratch_.data()->hInv; // hInv, gradNorm, ... of every row
    const std::uint32_t* js = row.data();
    double *gW = out.gW.data(), *gWi = out.gWi.data(), *qMean = out.qMean.data(),
           *wH = out.wH.data();
    const double sigma = K::sigma();
    std::array<double, Dim> at;
    for (int d = 0; d < Dim; ++d) at[static_cast<std::size_t>(d)] = xi[d];
#pragma omp simd
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t j = js[k];
      double r2 = 0.0;
      for (std::size_t d = 0; d < Dim; ++d) {
        const double dx = at[d] - x[Dim * j + d];
        r2 += dx * dx;
      }
      // r = 0 gives inf here; the pair loop skips coincident pairs before reading it.
      const double r = std::sqrt(r2), rInv = 1.0 / r;
      const double qi = r * hiInv, qj = r * scratch[kStride * j];
      const double dfi = K::df(qi);
      const double dWi = gradNormI * dfi, dWj = scratch[kStride * j + 1] * K::df(qj);
      gW[k] = 0.5 * (dWi + dWj) * rInv;
      gWi[k] = dWi * rInv;
      qMean[k] = 0.5 * (qi + qj);
      wH[k] = sigma * std::abs(dfi);
    }
  }
  // ASPH: the same for the ellipsoidal kernels, whose pair needs two matrix-vector products,
  // two square roots and two divisions before anything else; columns and no branches, as
  // SPH's (taylor_bar_3d with ASPH: see decks/topics/asph.md).
  struct AnisoPairKernels {
    std::size_t stride = 0; // of the columns below
    // The pair's mean gradient (Dim columns), then i's own (Dim more): gW(a, k) and gWi(a, k).
    std::vector<double> g;
    std::vector<double> hbarOverR;  // the mean of 1/eta over both metrics: h along the pair over r
    std::vector<double> qMean;      // (eta_i + eta_j)/2
    std::vector<double> wH;         // sigma |W'(eta_i)| (Owen 2010, Eq. 1)
    std::vector<double> coincident; // 1 where coincident in eta (underflow): the pair is skipped
    double gW(int a, std::size_t k) const { return g[static_cast<std::size_t>(a) * stride + k]; }
    double gWi(int a, std::size_t k) const {
      return g[static_cast<std::size_t>(Dim + a) * stride + k];
    }
  };
  void anisoPairKernels(const Vec<Dim>& xi, std::size_t i, std::span<const std::uint32_t> row,
                        AnisoPairKernels& out) const {
    static_assert(sizeof(Vec<Dim>) == Dim * sizeof(double) &&
                  sizeof(AnisoRow) % sizeof(double) == 0 &&
                  offsetof(AnisoRow, normGrad) == Dim * Dim * sizeof(double));
    // G (column-major), then sigma det H (and in 2D the padding of G's alignment).
    constexpr std::size_t kStride = sizeof(AnisoRow) / sizeof(double);
    const std::size_t n = row.size();
    if (out.stride < n) {
      out.stride = n;
      out.g.resize(2 * Dim * n);
      for (auto* c : {&out.hbarOverR, &out.qMean, &out.wH, &out.coincident}) c->resize(n);
    }
    const std::size_t m = out.stride;
    const double* const x = s_[f_.x].data()->data();
    const double* const rows = anisoRow_.data()->G.data();
    const std::uint32_t* const js = row.data();
    double* const g = out.g.data();
    double* const hbarOverR = out.hbarOverR.data();
    double* const qMean = out.qMean.data();
    double* const wH = out.wH.data();
    double* const coincident = out.coincident.data();
    const double sigma = K::sigma();
    std::array<double, Dim> at;
    for (int d = 0; d < Dim; ++d) at[static_cast<std::size_t>(d)] = xi[d];
    std::array<double, Dim * Dim> GI;
    for (std::size_t e = 0; e < Dim * Dim; ++e) GI[e] = rows[kStride * i + e];
    const double normGradI = rows[kStride * i + Dim * Dim];
#pragma omp simd
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t j = js[k];
      // In the metric G = H^T H: eta^2 = x . G x and the gradient det(H) W'(eta) G x / eta,
      // so the pair needs two matrix-vector products, not four. (The divisions start from the
      // squares, in parallel with the square roots.)
      double etaI2 = 0.0, etaJ2 = 0.0;
#pragma GCC unroll 3
      for (std::size_t a = 0; a < Dim; ++a) {
        double gi = 0.0, gj = 0.0;
#pragma GCC unroll 3
        for (std::size_t b = 0; b < Dim; ++b) {
          const double xb = at[b] - x[Dim * j + b];
          gi += GI[b * Dim + a] * xb;
          gj += rows[kStride * j + b * Dim + a] * xb;
        }
        const double xa = at[a] - x[Dim * j + a];
        etaI2 += xa * gi;
        etaJ2 += xa * gj;
        g[(Dim + a) * m + k] = gi; // G_i x_ij and G_j x_ij until scaled below
        g[a * m + k] = gj;
      }
      coincident[k] = etaI2 > 0.0 && etaJ2 > 0.0 ? 0.0 : 1.0;
      const double etaI2Inv = 1.0 / etaI2, etaJ2Inv = 1.0 / etaJ2;
      const double etaI = std::sqrt(etaI2), etaJ = std::sqrt(etaJ2);
      const double etaIInv = etaI * etaI2Inv, etaJInv = etaJ * etaJ2Inv;
      // (df is 0 outside the support.)
      const double dfI = K::df(etaI), dfJ = K::df(etaJ);
      const double cI = normGradI * dfI * etaIInv,
                   cJ = rows[kStride * j + Dim * Dim] * dfJ * etaJInv;
#pragma GCC unroll 3
      for (std::size_t a = 0; a < Dim; ++a) {
        const double gWi = cI * g[(Dim + a) * m + k];
        g[a * m + k] = 0.5 * (gWi + cJ * g[a * m + k]);
        g[(Dim + a) * m + k] = gWi;
      }
      hbarOverR[k] = 0.5 * (etaIInv + etaJInv);
      qMean[k] = 0.5 * (etaI + etaJ);
      // W^H = 0 outside i's support, so a neighbor only j's support reaches adds nothing.
      wH[k] = sigma * std::abs(dfI);
    }
  }
  ParticleStore& s_;
  ParticleFields<Dim> f_;
  kernels::PsiTable psi_;
  std::vector<double> rhoPrev_;
  std::vector<double> divNew_, curlNew_; // this loop's div v, |curl v| (Balsara), owned rows
  std::vector<AnisoRow> anisoRow_;       // scratch of the ASPH loops
};

} // namespace spall::solvers::sph
