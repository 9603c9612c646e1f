#pragma once
// A body of particles read from a file (shape "particles"): the particles as sites, and the
// region they stand for (for the overlap check against later bodies).
#include "BodyShape.hpp"

#include "spall/io/Deck.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace spall::app::sites {

// The region a file's particles stand for: each one's cube of its own volume about it (the cells
// a mesher's particles fill), looked up in a grid of the coarsest cell.
template <int Dim> class CloudRegion {
public:
  explicit CloudRegion(const ParticleCloud& c) : c_(c), cell_(c.coarsest) {
    for (std::size_t i = 0; i < c.size(); ++i) cells_.emplace_back(keyOf(at(i)), i);
    std::sort(cells_.begin(), cells_.end());
  }
  bool contains(const Vec<Dim>& x) const {
    const Key k = keyOf(x);
    const std::int64_t r2 = Dim >= 2 ? 1 : 0, r3 = Dim == 3 ? 1 : 0;
    for (std::int64_t dz = -r3; dz <= r3; ++dz)
      for (std::int64_t dy = -r2; dy <= r2; ++dy)
        for (std::int64_t dx = -1; dx <= 1; ++dx) {
          const Key q{k[0] + dx, k[1] + dy, k[2] + dz};
          for (auto it = std::lower_bound(cells_.begin(), cells_.end(), std::make_pair(q, 0UL));
               it != cells_.end() && it->first == q; ++it) {
            const double half = 0.5 * std::pow(c_.volume[it->second], 1.0 / Dim);
            if ((x - at(it->second)).cwiseAbs().maxCoeff() < half) return true;
          }
        }
    return false;
  }

private:
  using Key = std::array<std::int64_t, 3>;
  Vec<Dim> at(std::size_t i) const {
    Vec<Dim> x;
    for (int d = 0; d < Dim; ++d) x[d] = c_.position[i * Dim + static_cast<std::size_t>(d)];
    return x;
  }
  Key keyOf(const Vec<Dim>& x) const {
    Key k{0, 0, 0};
    for (int d = 0; d < Dim; ++d)
      k[static_cast<std::size_t>(d)] = static_cast<std::int64_t>(std::floor(x[d] / cell_));
    return k;
  }
  const ParticleCloud& c_;
  double cell_;
  std::vector<std::pair<Key, std::size_t>> cells_;
};

// A file's particles as sites (run.resolution does not apply: they are what the mesher made).
template <int Dim> std::vector<Site<Dim>> cloudSites(const ParticleCloud& cloud) {
  std::vector<Site<Dim>> out(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    for (int d = 0; d < Dim; ++d)
      out[i].x[d] = cloud.position[i * static_cast<std::size_t>(Dim) + static_cast<std::size_t>(d)];
    out[i].volume = cloud.volume[i];
  }
  return out;
}

} // namespace spall::app::sites
