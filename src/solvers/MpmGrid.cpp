#include "spall/solvers/MpmGrid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace spall::solvers {

namespace {

template <int Dim, MpmShape Shape> class Grid final : public MpmGrid<Dim> {
  static constexpr int K = mpm::kNodesPerParticle<Shape, Dim>;
  using Key = std::array<std::int64_t, Dim>;

public:
  Grid(const MpmConfig& c, const Vec<Dim>& origin, std::vector<GridWall<Dim>> walls, bool rz)
      : c_(c), origin_(origin), walls_(std::move(walls)), rz_(rz) {}

  double haloReach(double lpMax) const override {
    return Shape == MpmShape::Linear ? 2.0 * c_.cell_size : 2.0 * (c_.cell_size + lpMax);
  }
  std::size_t nodes() const override { return key_.size(); }

  void project(const MpmParticles<Dim>& P, std::span<const std::uint32_t> order,
               double dt) override {
    connect(P, order.size());
    // P2G in id order: mass, momentum, internal force.
    const std::size_t N = key_.size();
    mass_.assign(N, 0.0);
    momentum_.assign(N, Vec<Dim>::Zero());
    force_.assign(N, Vec<Dim>::Zero());
    const bool solid = !P.S.empty();
    for (const std::uint32_t r : order) {
      Tensor<Dim> sigma = -P.p[r] * Tensor<Dim>::Identity();
      if (solid) sigma += P.S[r].template topLeftCorner<Dim, Dim>();
      const double V = P.m[r] / P.rho[r];
      const Vec<Dim> mv = P.m[r] * P.v[r];
      // rz: the hoop stress's share of the radial force, sigma_tt S / r (the weak form's
      // 2 pi r dA is in the ring's mass and volume).
      Vec<Dim> hoop = Vec<Dim>::Zero();
      if (rz_) hoop[0] = ((solid ? P.S[r](2, 2) : 0.0) - P.p[r]) / radius(P, r);
      for (int q = 0; q < K; ++q) {
        const std::size_t e = r * K + static_cast<std::size_t>(q);
        const std::uint32_t I = node_[e];
        mass_[I] += S_[e] * P.m[r];
        momentum_[I] += S_[e] * mv;
        force_[I] -= V * (sigma * grad_[e] + S_[e] * hoop);
      }
    }
    // The grid's velocities before and after the step's forces; walls take the normal part of
    // both, so the FLIP increment carries the constraint too.
    velocity_.assign(N, Vec<Dim>::Zero());
    increment_.assign(N, Vec<Dim>::Zero());
    for (std::size_t I = 0; I < N; ++I) {
      if (!(mass_[I] > 0.0)) continue;
      Vec<Dim> v = momentum_[I] / mass_[I];
      Vec<Dim> vL = v + (dt / mass_[I]) * force_[I];
      constrain(I, v);
      constrain(I, vL);
      velocity_[I] = vL;
      increment_[I] = vL - v;
    }
    // G2P on the owned rows (rz: their radii at the step's start kept for the hoop rate).
    if (rz_) {
      radius_.resize(P.owned);
      for (std::size_t r = 0; r < P.owned; ++r) radius_[r] = radius(P, r);
    }
    const double flip = c_.flip;
    for (std::size_t r = 0; r < P.owned; ++r) {
      Vec<Dim> vPic = Vec<Dim>::Zero(), dv = Vec<Dim>::Zero();
      for (int q = 0; q < K; ++q) {
        const std::size_t e = r * K + static_cast<std::size_t>(q);
        vPic += S_[e] * velocity_[node_[e]];
        dv += S_[e] * increment_[node_[e]];
      }
      P.x[r] += dt * vPic;
      P.a[r] = dv / dt;
      P.v[r] = flip * (P.v[r] + dv) + (1.0 - flip) * vPic;
      // rz: the axis nodes keep v_r = 0, but a point's box reaches past them; one that would
      // cross the axis is folded back, as SPH's rings are.
      if (rz_ && P.x[r][0] < 0.0) {
        P.x[r][0] = -P.x[r][0];
        P.v[r][0] = -P.v[r][0];
      }
    }
  }

  void velocityGradient(const MpmParticles<Dim>& P, std::span<const std::uint32_t> order,
                        std::span<Tensor<3>> L) override {
    const std::size_t N = key_.size();
    momentum_.assign(N, Vec<Dim>::Zero());
    for (const std::uint32_t r : order) {
      const Vec<Dim> mv = P.m[r] * P.v[r];
      for (int q = 0; q < K; ++q) {
        const std::size_t e = r * K + static_cast<std::size_t>(q);
        momentum_[node_[e]] += S_[e] * mv;
      }
    }
    for (std::size_t I = 0; I < N; ++I) {
      velocity_[I] = mass_[I] > 0.0 ? Vec<Dim>(momentum_[I] / mass_[I]) : Vec<Dim>::Zero();
      constrain(I, velocity_[I]);
    }
    for (std::size_t r = 0; r < P.owned; ++r) {
      Tensor<Dim> l = Tensor<Dim>::Zero();
      double vr = 0.0; // rz: the point's radial velocity, for the hoop rate v_r / r
      for (int q = 0; q < K; ++q) {
        const std::size_t e = r * K + static_cast<std::size_t>(q);
        l += velocity_[node_[e]] * grad_[e].transpose();
        vr += S_[e] * velocity_[node_[e]][0];
      }
      L[r].setZero();
      L[r].template topLeftCorner<Dim, Dim>() = l;
      if (rz_) L[r](2, 2) = vr / radius_[r];
    }
  }

private:
  // rz: a ring's radius at the step's start, and at least its box's half-width (a ring closer
  // to the axis than that lies on it; its mass, made at its first radius, would otherwise turn
  // sigma_tt / r and v_r / r infinite).
  static double radius(const MpmParticles<Dim>& P, std::size_t r) {
    return std::max(P.x[r][0], P.halfWidth[r]);
  }

  // Each row's block of nodes and weights, and the nodes numbered: densely over the rows'
  // bounding box of nodes when it is small against the entries, else by sorting the keys.
  void connect(const MpmParticles<Dim>& P, std::size_t rows) {
    node_.resize(rows * K);
    S_.resize(rows * K);
    grad_.resize(rows * K);
    first_.resize(rows);
    Key lo, hi;
    lo.fill(std::numeric_limits<std::int64_t>::max());
    hi.fill(std::numeric_limits<std::int64_t>::min());
    for (std::size_t r = 0; r < rows; ++r) {
      const auto b = mpm::block<Shape, Dim>(P.x[r], origin_, c_.cell_size, P.halfWidth[r]);
      first_[r] = b.first;
      for (int q = 0; q < K; ++q) {
        S_[r * K + static_cast<std::size_t>(q)] = b.S[static_cast<std::size_t>(q)];
        grad_[r * K + static_cast<std::size_t>(q)] = b.grad[static_cast<std::size_t>(q)];
      }
      for (int a = 0; a < Dim; ++a) {
        const auto sa = static_cast<std::size_t>(a);
        lo[sa] = std::min(lo[sa], b.first[sa]);
        hi[sa] = std::max(hi[sa], b.first[sa] + mpm::kNodesPerAxis<Shape> - 1);
      }
    }
    key_.clear();
    if (rows == 0) return;
    double boxSize = 1.0;
    for (int a = 0; a < Dim; ++a)
      boxSize *= static_cast<double>(hi[static_cast<std::size_t>(a)] -
                                     lo[static_cast<std::size_t>(a)] + 1);
    const double entries = static_cast<double>(rows * K);
    if (boxSize <= std::max(4.0 * entries, 65536.0))
      numberDense(rows, lo, hi, static_cast<std::size_t>(boxSize));
    else
      numberSorted(rows);
  }

  Key keyOf(std::size_t r, int q) const {
    const auto off = mpm::blockOffset<Shape, Dim>(q);
    Key k = first_[r];
    for (int a = 0; a < Dim; ++a)
      k[static_cast<std::size_t>(a)] += off[static_cast<std::size_t>(a)];
    return k;
  }

  void numberDense(std::size_t rows, const Key& lo, const Key& hi, std::size_t size) {
    box_.assign(size, std::numeric_limits<std::uint32_t>::max());
    for (std::size_t r = 0; r < rows; ++r)
      for (int q = 0; q < K; ++q) {
        const Key k = keyOf(r, q);
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
        node_[r * K + static_cast<std::size_t>(q)] = slot;
      }
  }

  void numberSorted(std::size_t rows) {
    std::vector<std::pair<Key, std::uint32_t>> all(rows * K);
    for (std::size_t r = 0; r < rows; ++r)
      for (int q = 0; q < K; ++q) {
        const std::size_t e = r * K + static_cast<std::size_t>(q);
        all[e] = {keyOf(r, q), static_cast<std::uint32_t>(e)};
      }
    std::sort(all.begin(), all.end());
    for (std::size_t i = 0; i < all.size(); ++i) {
      if (i == 0 || all[i].first != all[i - 1].first) key_.push_back(all[i].first);
      node_[all[i].second] = static_cast<std::uint32_t>(key_.size() - 1);
    }
  }

  void constrain(std::size_t I, Vec<Dim>& v) const {
    if (walls_.empty()) return;
    Vec<Dim> X;
    for (int a = 0; a < Dim; ++a)
      X[a] = origin_[a] + static_cast<double>(key_[I][static_cast<std::size_t>(a)]) * c_.cell_size;
    for (const auto& w : walls_)
      if ((X - w.point).dot(w.normal) <= 1e-9 * c_.cell_size) v -= v.dot(w.normal) * w.normal;
  }

  MpmConfig c_;
  Vec<Dim> origin_;
  std::vector<GridWall<Dim>> walls_;
  bool rz_;                    // axisymmetric: x = r, y = z, the points rings
  std::vector<double> radius_; // rz: the owned rings' radii for the hoop rate
  // Per row and block entry (row r, entry q at r K + q): the node's number, S and grad S.
  std::vector<std::uint32_t> node_;
  std::vector<double> S_;
  std::vector<Vec<Dim>> grad_;
  std::vector<Key> first_;         // each row's first node
  std::vector<Key> key_;           // each numbered node's lattice index
  std::vector<std::uint32_t> box_; // dense numbering scratch
  std::vector<double> mass_;
  std::vector<Vec<Dim>> momentum_, force_, velocity_, increment_;
};

} // namespace

template <int Dim>
std::unique_ptr<MpmGrid<Dim>> makeMpmGrid(const MpmConfig& config, const Vec<Dim>& origin,
                                          std::vector<GridWall<Dim>> walls, bool axisymmetric) {
  if (axisymmetric && Dim != 2) throw std::logic_error("axisymmetric MPM needs dimension 2");
  if (config.shape == MpmShape::Linear)
    return std::make_unique<Grid<Dim, MpmShape::Linear>>(config, origin, std::move(walls),
                                                         axisymmetric);
  return std::make_unique<Grid<Dim, MpmShape::Gimp>>(config, origin, std::move(walls),
                                                     axisymmetric);
}

template std::unique_ptr<MpmGrid<1>> makeMpmGrid<1>(const MpmConfig&, const Vec<1>&,
                                                    std::vector<GridWall<1>>, bool);
template std::unique_ptr<MpmGrid<2>> makeMpmGrid<2>(const MpmConfig&, const Vec<2>&,
                                                    std::vector<GridWall<2>>, bool);
template std::unique_ptr<MpmGrid<3>> makeMpmGrid<3>(const MpmConfig&, const Vec<3>&,
                                                    std::vector<GridWall<3>>, bool);

} // namespace spall::solvers
