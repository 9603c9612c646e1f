#pragma once
// The walls on the grid (MpmGrid.hpp): their constraint and their Coulomb friction, and the work
// of a friction correction, which contact (MpmGridContact.hpp) and the walls book as heat.
#include "MpmGridImpl.hpp"

namespace spall::solvers::grid {

// A node on or behind a wall's plane: the wall holds its velocity along the normal.
template <int Dim, MpmShape Shape>
bool Grid<Dim, Shape>::onWall(const Vec<Dim>& X, const GridWall<Dim>& w) const {
  return (X - w.point).dot(w.normal) <= 1e-9 * c_.cell_size;
}

template <int Dim, MpmShape Shape>
void Grid<Dim, Shape>::constrainAt(const Key& k, Vec<Dim>& v) const {
  if (walls_.empty()) return;
  const Vec<Dim> X = place(k);
  for (const auto& w : walls_)
    if (onWall(X, w)) v -= v.dot(w.normal) * w.normal;
}

// The work of a friction impulse J = m (1 - kept) u_t that leaves the slide u_t at kept u_t:
// J times the mean of the slide at the step's start, u0, and the slide after it, at least 0
// (none where the force turned the slide around) and at most the kinetic energy it takes,
// J . (u_t + kept u_t) / 2. (With the kinetic energy alone, the force's own tangential push at
// an interface node, the body's shear that the friction takes back in the same step, counted
// as a slide: a block sliding to rest booked 1.19 times the energy it lost; decks/topics/mpm.md.)
template <int Dim>
double frictionWork(const Vec<Dim>& J, const Vec<Dim>& u0, const Vec<Dim>& ut, double kept) {
  return std::clamp(0.5 * J.dot(u0 + kept * ut), 0.0, 0.5 * J.dot((1.0 + kept) * ut));
}

// Coulomb friction of the walls a node lies on (GridWall::friction), before the walls take the
// normal parts: the force pressing the node on a wall this step is -(v^L - v) . n (the change
// the wall cancels, as the FLIP increment keeps out its correction of v), and the tangential
// v^L loses up to mu times it, or all of it (it sticks); the work into heat.
template <int Dim, MpmShape Shape>
void Grid<Dim, Shape>::rub(std::size_t I, const Vec<Dim>& v, Vec<Dim>& vL,
                           std::vector<double>* heat) const {
  if (!rigid_.empty() && rigid_[I]) return;
  const Vec<Dim> X = place(key_[lattice(I)]);
  for (const auto& w : walls_) {
    if (!(w.friction > 0.0) || !onWall(X, w)) continue;
    const double pressed = -(vL - v).dot(w.normal);
    const Vec<Dim> slide = vL - vL.dot(w.normal) * w.normal;
    const double s = slide.norm();
    if (!(pressed > 0.0) || !(s > 0.0)) continue;
    const double kept = std::max(0.0, 1.0 - w.friction * pressed / s); // 0: it sticks
    vL -= (1.0 - kept) * slide;
    if (heat)
      (*heat)[I] += frictionWork<Dim>(mass_[I] * (1.0 - kept) * slide,
                                      v - v.dot(w.normal) * w.normal, slide, kept);
  }
}

} // namespace spall::solvers::grid
