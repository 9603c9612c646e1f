#include "spall/parallel/VirtualRanks.hpp"

#include "spall/parallel/Partition.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace spall::parallel {

template <int Dim>
VirtualRanks<Dim>::VirtualRanks(VirtualParticles<Dim> particles) : p_(std::move(particles)) {
  const std::size_t n = p_.x.size();
  // The key box as Decomposition::newKeyBox makes it: the particles' extent, 5% wider.
  Vec<Dim> lo = Vec<Dim>::Constant(std::numeric_limits<double>::infinity());
  Vec<Dim> hi = -lo;
  for (const auto& x : p_.x)
    if (x.allFinite()) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  for (int d = 0; d < Dim; ++d) {
    if (!(lo[d] <= hi[d])) lo[d] = hi[d] = 0.0;
    const double pad = 0.05 * (hi[d] - lo[d]);
    lo[d] -= pad;
    hi[d] += pad;
  }
  const KeyMap<Dim> keys(lo, hi, p_.curve);
  std::vector<std::pair<std::uint64_t, ParticleId>> key(n);
  for (std::size_t i = 0; i < n; ++i) key[i] = {keys(p_.x[i]), p_.id[i]};
  order_.resize(n);
  std::iota(order_.begin(), order_.end(), 0u);
  std::sort(order_.begin(), order_.end(),
            [&](std::uint32_t a, std::uint32_t b) { return key[a] < key[b]; });
  keys_.resize(n);
  for (std::size_t k = 0; k < n; ++k) keys_[k] = key[order_[k]].first;
}

namespace {

// Ranks whose domain may be near a position: a grid over the particles, each cell listing the
// ranks whose domain (its union box, widened by the largest radius) overlaps it.
template <int Dim> class RankIndex {
public:
  RankIndex(const HaloTargets<Dim>& t, Vec<Dim> lo, Vec<Dim> hi) {
    const int ranks = t.ranks();
    const double widen = t.radiusMax() * kHaloSlack * (1.0 + 1e-12);
    // About eight cells per rank, cubic, at most 4096 along an axis.
    double extent = 0.0;
    for (int d = 0; d < Dim; ++d) extent = std::max(extent, hi[d] - lo[d]);
    const double per = std::ceil(std::pow(8.0 * ranks, 1.0 / Dim));
    const double cell = extent > 0.0 ? extent / per : 1.0;
    std::size_t cells = 1;
    for (int d = 0; d < Dim; ++d) {
      n_[d] = static_cast<int>(std::clamp(std::ceil((hi[d] - lo[d]) / cell), 1.0, 4096.0));
      stride_[d] = cells;
      cells *= static_cast<std::size_t>(n_[d]);
    }
    lo_ = lo;
    inv_ = Vec<Dim>::Constant(1.0 / cell);
    std::vector<std::vector<int>> lists(cells);
    for (int r = 0; r < ranks; ++r) {
      const HaloBox<Dim>& u = t.rankBox(r);
      if (u.empty()) continue;
      std::array<int, Dim> a{}, b{};
      for (int d = 0; d < Dim; ++d) {
        a[static_cast<std::size_t>(d)] = index(u.lo[d] - widen, d);
        b[static_cast<std::size_t>(d)] = index(u.hi[d] + widen, d);
      }
      std::array<int, Dim> c = a;
      while (true) {
        std::size_t k = 0;
        for (int d = 0; d < Dim; ++d)
          k += static_cast<std::size_t>(c[static_cast<std::size_t>(d)]) * stride_[d];
        lists[k].push_back(r);
        int d = 0;
        for (; d < Dim; ++d) {
          auto& cd = c[static_cast<std::size_t>(d)];
          if (++cd <= b[static_cast<std::size_t>(d)]) break;
          cd = a[static_cast<std::size_t>(d)];
        }
        if (d == Dim) break;
      }
    }
    begin_.assign(cells + 1, 0);
    for (std::size_t k = 0; k < cells; ++k) begin_[k + 1] = begin_[k] + lists[k].size();
    ranks_.reserve(begin_.back());
    for (const auto& l : lists) ranks_.insert(ranks_.end(), l.begin(), l.end());
  }

  template <class Visit> void visit(const Vec<Dim>& x, Visit&& v) const {
    std::size_t k = 0;
    for (int d = 0; d < Dim; ++d) k += static_cast<std::size_t>(index(x[d], d)) * stride_[d];
    for (std::size_t i = begin_[k]; i < begin_[k + 1]; ++i) v(ranks_[i]);
  }

private:
  // Clamped to the grid: a position beyond it (a periodic image) lands in the edge cell, where
  // every domain that reaches beyond the edge is listed too.
  int index(double x, int d) const {
    const double t = std::floor((x - lo_[d]) * inv_[d]);
    if (!(t > 0.0)) return 0;
    return static_cast<int>(std::min(t, static_cast<double>(n_[d] - 1)));
  }

  Vec<Dim> lo_, inv_;
  std::array<int, Dim> n_{};
  std::array<std::size_t, Dim> stride_{};
  std::vector<std::size_t> begin_;
  std::vector<int> ranks_;
};

} // namespace

template <int Dim> std::vector<VirtualRank> VirtualRanks<Dim>::cut(int ranks) const {
  const std::size_t n = order_.size();
  std::vector<VirtualRank> out(static_cast<std::size_t>(ranks));
  // Unit costs: a new run's first partition (Decomposition::distributeInitial).
  const std::vector<std::uint64_t> unit(n, 1);
  const KeyOwnership owner = KeyOwnership::contiguous(splittersOf(keys_, unit, ranks));
  std::vector<std::size_t> first(static_cast<std::size_t>(ranks) + 1, n);
  for (int r = 0; r < ranks; ++r)
    first[static_cast<std::size_t>(r)] = static_cast<std::size_t>(
        std::lower_bound(keys_.begin(), keys_.end(), owner.begins()[static_cast<std::size_t>(r)]) -
        keys_.begin());
  // Each rank's boxes over its owned rows in (key, id) order, as HaloExchange describes them.
  std::vector<HaloBox<Dim>> boxes;
  boxes.reserve(static_cast<std::size_t>(ranks) * kHaloBoxes);
  std::vector<Vec<Dim>> x, reach;
  std::vector<double> radius;
  for (int r = 0; r < ranks; ++r) {
    const std::size_t a = first[static_cast<std::size_t>(r)],
                      b = first[static_cast<std::size_t>(r) + 1];
    x.clear(), reach.clear(), radius.clear();
    for (std::size_t k = a; k < b; ++k) {
      const std::uint32_t i = order_[k];
      x.push_back(p_.x[i]), reach.push_back(p_.reach[i]), radius.push_back(p_.radius[i]);
    }
    const auto own = describeBoxes<Dim>(x, reach, radius);
    boxes.insert(boxes.end(), own.begin(), own.end());
    out[static_cast<std::size_t>(r)].owned = b - a;
  }
  HaloTargets<Dim> targets(p_.periodic);
  targets.setBoxes(std::move(boxes), p_.round);

  Vec<Dim> lo = Vec<Dim>::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (int r = 0; r < ranks; ++r)
    if (!targets.rankBox(r).empty())
      lo = lo.cwiseMin(targets.rankBox(r).lo), hi = hi.cwiseMax(targets.rankBox(r).hi);
  if (!(lo[0] <= hi[0])) return out; // no finite particle
  const RankIndex<Dim> index(targets, lo, hi);
  const auto candidates = [&](const Vec<Dim>& xs, auto&& visit) { index.visit(xs, visit); };

  std::vector<std::uint64_t> links, mine; // (from << 32) | to, distinct
  for (int o = 0; o < ranks; ++o) {
    auto& from = out[static_cast<std::size_t>(o)];
    mine.clear();
    for (std::size_t k = first[static_cast<std::size_t>(o)];
         k < first[static_cast<std::size_t>(o) + 1]; ++k) {
      const std::uint32_t i = order_[k];
      targets.targets(p_.x[i], p_.reach[i], p_.radius[i], o, candidates, [&](int r, std::uint8_t) {
        ++out[static_cast<std::size_t>(r)].ghosts;
        if (r == o) return;
        ++from.sent;
        if (mine.empty() || mine.back() != static_cast<std::uint64_t>(r))
          mine.push_back(static_cast<std::uint64_t>(r));
      });
    }
    std::sort(mine.begin(), mine.end());
    mine.erase(std::unique(mine.begin(), mine.end()), mine.end());
    for (const std::uint64_t r : mine) links.push_back((static_cast<std::uint64_t>(o) << 32) | r);
  }
  std::vector<std::uint64_t> either;
  either.reserve(2 * links.size());
  for (const std::uint64_t l : links) {
    const std::uint64_t a = l >> 32, b = l & 0xffffffffu;
    ++out[a].sendsTo;
    ++out[b].receivesFrom;
    either.push_back(l);
    either.push_back((b << 32) | a);
  }
  std::sort(either.begin(), either.end());
  either.erase(std::unique(either.begin(), either.end()), either.end());
  for (const std::uint64_t l : either) ++out[l >> 32].neighbors;
  return out;
}

template class VirtualRanks<1>;
template class VirtualRanks<2>;
template class VirtualRanks<3>;

} // namespace spall::parallel
