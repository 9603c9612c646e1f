#pragma once
// Boundary conditions: mirror ghosts across rigid walls (Lam et al. 2001, Sec. 4.1: "converts
// the impact on a rigid wall into a symmetric impact"), appended after the owned particles and
// the remote/periodic ghosts of the halo exchange, and the wrapping of periodic axes (whose
// images the halo exchange makes, on one rank as on many). Each wall also images the ghosts
// before it (remote particles near the wall, periodic images, earlier walls' images), so
// corners are covered and a wall that crosses rank domains is mirrored on every rank.
// An image copies every field of its source; the fields flagged kReflectVector/kReflectTensor
// are reflected (P v, P T P with P = I - 2 n n^T), the position across the wall plane.
#include "spall/core/ParticleFields.hpp"
#include "spall/parallel/HaloExchange.hpp"
#include "spall/solvers/Config.hpp"

#include <span>
#include <vector>

namespace spall::solvers {

template <int Dim> class Boundaries {
public:
  Boundaries(const std::vector<BoundaryConfig>& config, const ParticleStore& s,
             const ParticleFields<Dim>& f);

  // Maps owned particles that left a periodic box back into it, and folds those behind a
  // folding wall back across it (position and velocity mirrored); how many it moved.
  std::size_t wrapPeriodic(ParticleStore& s) const;
  // Whether a particle is on another side of a wall at `to` than at `from` (its image, made or
  // not by buildGhosts, would be another).
  bool crossedWall(std::span<const Vec<Dim>> from, std::span<const Vec<Dim>> to) const;
  // Appends the mirror image of every particle (owned or ghost) within `reach` of a wall.
  void buildGhosts(ParticleStore& s, double reach);
  // The images of rigid walls are the rows from this one on (the rz axis, the only folding
  // wall, comes first: its images are the material's own mirror, those of a rigid wall only
  // carry the stress across it; see holdAcceleration).
  std::size_t firstWallImage() const { return firstWallImage_; }
  // A rigid wall's normal constraint on the owned particles (issue 21, decks/README.md "Taylor
  // bars"): a particle within kHold h of the plane is not accelerated into it (the constraint
  // force, which does no work on a particle sliding along the wall), and its velocity into the
  // plane is stopped, the kinetic energy of that component becoming heat (a rigid wall does no
  // work, so total energy is kept). The images alone hold a particle ever more weakly as it
  // nears the plane (the kernel's gradient vanishes at zero distance); their artificial
  // viscosity, the hold before this, pushed the face of a Taylor bar off the wall and kept its
  // mushroom narrow. kHold: a step at the CFL number 0.25 carries a particle approaching at a
  // quarter of its sound speed less than 0.05 h, so it is held before it reaches the plane; a
  // faster one that stepped across (at most h behind) is put back onto it.
  static constexpr double kHold = 0.05;
  void holdAcceleration(std::span<const Vec<Dim>> x, std::span<const double> h,
                        std::span<Vec<Dim>> a) const;
  void holdVelocity(std::span<Vec<Dim>> x, std::span<const double> h, std::span<Vec<Dim>> v,
                    std::span<double> e) const;
  std::vector<parallel::PeriodicAxis> periodicAxes() const;
  // Which ghost images which row, across which wall.
  std::size_t bytes() const { return allocatedBytes(source_, wallOf_); }
  // Copies the listed columns of each image from its source again (reflected where flagged; the
  // position mirrored across the plane), after they changed on the source (a step's positions,
  // the density pass, the kernel correction).
  void refreshGhosts(ParticleStore& s, std::span<const std::size_t> columns) const;

private:
  struct Wall {
    Vec<Dim> point, normal; // normal points into the material
    bool fold;
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
  // Whether a particle at distance d from a rigid wall's plane is held by it.
  static bool held(double d, double h) { return d <= kHold * h && d >= -h; }
  // Reflects image k's value of a field in place.
  void reflectVector(ParticleStore& s, Field<Vec<Dim>> field, std::size_t k) const;
  template <int N>
  void reflectTensor(ParticleStore& s, Field<Tensor<N>> field, std::size_t k) const;
  std::vector<Wall> walls_;
  std::vector<Periodic> periodic_;
  std::size_t first_ = 0;             // first wall ghost
  std::size_t firstWallImage_ = 0;    // first image of a rigid (not folding) wall
  std::vector<std::uint32_t> source_; // ghost first_ + k images source_[k]
  std::vector<std::uint32_t> wallOf_; // ... across walls_[wallOf_[k]]
  Field<Vec<Dim>> x_, v_;
  // The reflected fields by type (the position is reflected across the plane, not listed here).
  std::vector<Field<Vec<Dim>>> vectors_;
  std::vector<Field<Tensor<Dim>>> tensors_;
  std::vector<Field<Tensor<3>>> tensors3_;
};

} // namespace spall::solvers
