#pragma once
// Neighbor search over owned + ghost particles with a uniform cell grid (linked cells via a
// counting sort). A pair (i, j) is kept when r_ij < support * max(h_i, h_j): the symmetrised
// (gather-scatter) interaction of the SPH equations needs both sides' supports. Lists are built
// for owned particles only, in compressed rows of 32-bit indices (memory: ~4 bytes per pair).
#include "spall/core/Types.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace spall::neighbors {

struct NeighborList {
  std::vector<std::uint64_t> offsets; // owned count + 1
  std::vector<std::uint32_t> indices; // neighbors of i: indices[offsets[i] .. offsets[i+1])
  std::size_t pairs() const { return indices.size(); }
  std::span<const std::uint32_t> of(std::size_t i) const {
    return {indices.data() + offsets[i], indices.data() + offsets[i + 1]};
  }
  std::size_t bytes() const {
    return offsets.capacity() * sizeof(std::uint64_t) + indices.capacity() * sizeof(std::uint32_t);
  }
};

template <int Dim> class CellGrid {
public:
  // Bins all `x` (owned and ghosts) into cells no smaller than `cellSize`; the grid is coarsened
  // when the particles' extent would need more than ~2 cells per particle (a far-flung particle
  // must not cost memory).
  void build(std::span<const Vec<Dim>> x, double cellSize) {
    lo_ = Vec<Dim>::Constant(std::numeric_limits<double>::max());
    Vec<Dim> hi = Vec<Dim>::Constant(std::numeric_limits<double>::lowest());
    for (const auto& p : x) {
      lo_ = lo_.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    if (x.empty()) lo_.setZero(), hi.setZero();
    double size = cellSize;
    const double maxCells = 2.0 * static_cast<double>(x.size()) + 64.0;
    for (;;) {
      double total = 1.0;
      for (int d = 0; d < Dim; ++d) {
        n_[d] = std::max<std::int64_t>(1, static_cast<std::int64_t>((hi[d] - lo_[d]) / size) + 1);
        total *= static_cast<double>(n_[d]);
      }
      if (total <= maxCells) break;
      size *= std::pow(total / maxCells, 1.0 / Dim) * 1.01;
    }
    inv_ = 1.0 / size;
    std::int64_t cells = 1;
    for (int d = 0; d < Dim; ++d) cells *= n_[d];
    start_.assign(static_cast<std::size_t>(cells) + 1, 0);
    cellOf_.resize(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
      cellOf_[i] = cellIndex(x[i]);
      ++start_[cellOf_[i] + 1];
    }
    for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    members_.resize(x.size());
    std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
    for (std::size_t i = 0; i < x.size(); ++i) members_[fill[cellOf_[i]]++] = static_cast<std::uint32_t>(i);
  }

  std::uint32_t cellIndex(const Vec<Dim>& p) const {
    std::int64_t c = 0;
    for (int d = Dim - 1; d >= 0; --d) {
      std::int64_t k = static_cast<std::int64_t>((p[d] - lo_[d]) * inv_);
      k = std::clamp<std::int64_t>(k, 0, n_[d] - 1);
      c = c * n_[d] + k;
    }
    return static_cast<std::uint32_t>(c);
  }
  std::span<const std::uint32_t> cellOf() const { return cellOf_; }

  // Calls visit(j) for every particle in the 3^Dim cells around cell `c`.
  template <class F> void forEachNear(std::uint32_t c, F&& visit) const {
    std::int64_t k[3] = {0, 0, 0};
    std::int64_t rem = c;
    for (int d = 0; d < Dim; ++d) {
      k[d] = rem % n_[d];
      rem /= n_[d];
    }
    const int r1 = Dim >= 2 ? 1 : 0, r2 = Dim >= 3 ? 1 : 0;
    for (int dz = -r2; dz <= r2; ++dz) {
      if (Dim >= 3 && (k[2] + dz < 0 || k[2] + dz >= n_[2])) continue;
      for (int dy = -r1; dy <= r1; ++dy) {
        if (Dim >= 2 && (k[1] + dy < 0 || k[1] + dy >= n_[1])) continue;
        const std::int64_t x0 = std::max<std::int64_t>(k[0] - 1, 0);
        const std::int64_t x1 = std::min<std::int64_t>(k[0] + 1, n_[0] - 1);
        std::int64_t base = 0;
        if constexpr (Dim == 3) base = ((k[2] + dz) * n_[1] + (k[1] + dy)) * n_[0];
        else if constexpr (Dim == 2) base = (k[1] + dy) * n_[0];
        // The cells x0..x1 of one row are contiguous in `members_`.
        const std::uint32_t b = start_[base + x0], e = start_[base + x1 + 1];
        for (std::uint32_t m = b; m < e; ++m) visit(members_[m]);
      }
    }
  }

private:
  Vec<Dim> lo_;
  double inv_ = 1.0;
  std::int64_t n_[3] = {1, 1, 1};
  std::vector<std::uint32_t> start_;
  std::vector<std::uint32_t> cellOf_;
  std::vector<std::uint32_t> members_;
};

// Builds the neighbor lists of the first `owned` particles of x (the rest are ghosts).
template <int Dim>
void buildNeighborList(std::span<const Vec<Dim>> x, std::span<const double> h, std::size_t owned,
                       double support, CellGrid<Dim>& grid, NeighborList& out) {
  double hmax = 0.0;
  for (double hi : h) hmax = std::max(hmax, hi);
  grid.build(x, support * hmax);
  out.offsets.resize(owned + 1);
  out.indices.clear();
  out.offsets[0] = 0;
  const auto cellOf = grid.cellOf();
  for (std::size_t i = 0; i < owned; ++i) {
    const Vec<Dim> xi = x[i];
    const double hi = h[i];
    grid.forEachNear(cellOf[i], [&](std::uint32_t j) {
      if (j == i) return;
      const double reach = support * std::max(hi, h[j]);
      if ((xi - x[j]).squaredNorm() < reach * reach) out.indices.push_back(j);
    });
    // Ascending index order fixes the summation order of every neighbor loop.
    std::sort(out.indices.begin() + static_cast<std::ptrdiff_t>(out.offsets[i]), out.indices.end());
    out.offsets[i + 1] = out.indices.size();
  }
}

} // namespace spall::neighbors
