#pragma once
// Boundary conditions as ghost particles appended after the owned ones: mirror images across
// rigid walls (Lam et al. 2001, Sec. 4.1: "converts the impact on a rigid wall into a symmetric
// impact") and periodic images. Boundaries are applied in deck order and each one also images
// the ghosts of the ones before it, so corners of walls and periodic axes are covered.
#include "spall/io/Deck.hpp"
#include "spall/solvers/SphFields.hpp"

#include <vector>

namespace spall::solvers {

template <int Dim> class Boundaries {
public:
  Boundaries(const std::vector<BoundaryConfig>& config, const SphFields<Dim>& f);

  bool empty() const { return walls_.empty() && periodic_.empty(); }
  // Maps owned particles that left a periodic box back into it.
  void wrapPeriodic(ParticleStore& s) const;
  // Drops old ghosts and images every particle within `reach` of a boundary.
  void buildGhosts(ParticleStore& s, double reach);
  // Copies the fields that change between ghost creation and the force loop (summation density
  // and the EOS) from each ghost's source.
  void refreshGhosts(ParticleStore& s) const;

private:
  struct Wall {
    Vec<Dim> point, normal; // normal points into the material
  };
  struct Periodic {
    int axis;
    double min, max;
  };
  struct Kind {
    bool wall;
    std::size_t index;
  };
  std::vector<Wall> walls_;
  std::vector<Periodic> periodic_;
  std::vector<Kind> order_;           // deck order
  std::vector<std::uint32_t> source_; // ghost k = localCount + k images source_[k]
  SphFields<Dim> f_;
};

} // namespace spall::solvers
