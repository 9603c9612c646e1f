#pragma once
// ASPH's Voronoi pass (Sph::cutVoronoiCells): after the force loop, the cells that give each
// particle's next H its shape (solvers/IdealH.hpp, solvers/VoronoiCell.hpp).
#include "Sph.hpp"

namespace spall::solvers::sph {

// The shape of the next H (solvers/IdealH.hpp): each owned row's Voronoi cell among its row, in
// a box as wide as its longest reach, cut in the row's (rank-count-independent) order at the
// force loop's positions; every shape_interval evaluations, staggered by id so that each step
// cuts the same share. Half the cost of an ASPH step is the cell, and H moves only half way
// towards it a step: a cell a few steps old is as good a target (decks/topics/asph.md).
template <int Dim, class K, bool Aniso>
void Sph<Dim, K, Aniso>::cutVoronoiCells(const neighbors::NeighborList& nl) {
  const EvaluatedRows rows = this->passRows(s_.localCount());
#pragma omp parallel for schedule(dynamic, 64) if (threaded(rows.size()))
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const std::size_t i = rows[k];
    thread_local std::vector<std::uint32_t> rowBuf; // each thread's own
    cutVoronoiCell(i, nl.of(i, rowBuf));
  }
}

template <int Dim, class K, bool Aniso>
void Sph<Dim, K, Aniso>::cutVoronoiCell(std::size_t i, std::span<const std::uint32_t> row) {
  const auto x = s_[f_.x];
  std::int32_t& age = s_[f_.cellAge][i]; // evaluations since the last cut, plus 1; 0: never cut
  const std::int32_t shapeInterval = cfg_.shape_interval;
  if (age > 0 && age < shapeInterval) {
    ++age;
    return;
  }
  thread_local std::vector<Vec<Dim>> offsets;
  thread_local VoronoiCell<Dim> cell;
  offsets.clear();
  for (std::uint32_t j : row) offsets.push_back(x[j] - x[i]);
  s_[f_.cellMoment][i] = voronoiCell<Dim>(cell, offsets, K::support * s_[f_.h][i])
                             ? cell.moments().second
                             : Tensor<Dim>::Zero();
  age = age == 0
            ? 1 + static_cast<std::int32_t>(s_[f_.id][i] % static_cast<ParticleId>(shapeInterval))
            : 1;
}

} // namespace spall::solvers::sph
