#pragma once
// Boundary conditions: mirror ghosts across rigid walls (Lam et al. 2001, Sec. 4.1: "converts
// the impact on a rigid wall into a symmetric impact"), appended after the owned particles and
// the remote/periodic ghosts of the halo exchange, and the wrapping of periodic axes (whose
// images the halo exchange makes, on one rank as on many). Each wall also images the ghosts
// before it (remote particles near the wall, periodic images, earlier walls' images), so
// corners are covered and a wall that crosses rank domains is mirrored on every rank.
#include "spall/io/Deck.hpp"
#include "spall/parallel/HaloExchange.hpp"
#include "spall/solvers/SphFields.hpp"

#include <initializer_list>
#include <vector>

namespace spall::solvers {

template <int Dim> class Boundaries {
public:
  Boundaries(const std::vector<BoundaryConfig>& config, const SphFields<Dim>& f);

  bool empty() const { return walls_.empty() && periodic_.empty(); }
  // Maps owned particles that left a periodic box back into it.
  void wrapPeriodic(ParticleStore& s) const;
  // Appends the mirror image of every particle (owned or ghost) within `reach` of a wall.
  void buildGhosts(ParticleStore& s, double reach);
  std::vector<parallel::PeriodicAxis> periodicAxes() const;
  // Copies the fields that change between ghost creation and the force loop (summation density
  // and the EOS) from each ghost's source, and the mirror image P T P of the given tensor fields
  // (those that are registered).
  void refreshGhosts(ParticleStore& s, std::initializer_list<Field<Tensor<3>>> tensors = {}) const;

private:
  struct Wall {
    Vec<Dim> point, normal; // normal points into the material
  };
  struct Periodic {
    int axis;
    double min, max;
  };
  // The mirror image P T P of a tensor (Dim x Dim, or embedded in 3x3), P = I - 2 n n^T.
  template <int N> static Tensor<N> mirrored(const Tensor<N>& T, const Wall& w) {
    Tensor<N> P = Tensor<N>::Identity();
    P.template topLeftCorner<Dim, Dim>() -= 2.0 * w.normal * w.normal.transpose();
    return P * T * P;
  }
  std::vector<Wall> walls_;
  std::vector<Periodic> periodic_;
  std::size_t first_ = 0;             // first wall ghost
  std::vector<std::uint32_t> source_; // ghost first_ + k images source_[k]
  std::vector<std::uint32_t> wallOf_; // ... across walls_[wallOf_[k]]
  SphFields<Dim> f_;
};

} // namespace spall::solvers
