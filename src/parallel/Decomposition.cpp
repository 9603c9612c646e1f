#include "spall/parallel/Decomposition.hpp"

#include "spall/neighbors/NeighborList.hpp"
#include "spall/parallel/RowExchange.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <unordered_map>

namespace spall::parallel {

template <int Dim>
Decomposition<Dim>::Decomposition(MPI_Comm comm, DecompositionConfig config, Field<ParticleId> id,
                                  Field<Vec<Dim>> x, Field<std::int32_t> cost)
    : comm_(comm), cfg_(config), id_(id), x_(x), cost_(cost) {
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &size_);
}

template <int Dim> void Decomposition<Dim>::distributeInitial(ParticleStore& s) {
  const std::size_t n = s.localCount();
  const std::size_t begin = n * static_cast<std::size_t>(rank_) / static_cast<std::size_t>(size_);
  const std::size_t end = n * static_cast<std::size_t>(rank_ + 1) / static_cast<std::size_t>(size_);
  std::vector<std::uint32_t> rows(end - begin);
  std::iota(rows.begin(), rows.end(), static_cast<std::uint32_t>(begin));
  s.keepLocal(rows);
  for (auto& c : s[cost_]) c = 1;
  distributeLoaded(s);
}

template <int Dim> void Decomposition<Dim>::distributeLoaded(ParticleStore& s) {
  rebalance(s);
  // Room for the halo's ghosts (~10% on a few ranks) without a reallocation; one rank has none.
  s.shrinkToFit(size_ > 1 ? 0.15 : 0.0);
}

template <int Dim> DecompositionState Decomposition<Dim>::state() const {
  DecompositionState st;
  for (int d = 0; d < Dim; ++d) st.box.push_back(keys_.lo()[d]);
  for (int d = 0; d < Dim; ++d) st.box.push_back(keys_.hi()[d]);
  st.begins = owner_.begins();
  for (int r : owner_.ranks()) st.owners.push_back(r);
  return st;
}

template <int Dim> void Decomposition<Dim>::restore(const DecompositionState& st) {
  if (st.box.size() != 2 * Dim || st.begins.empty() || st.begins.size() != st.owners.size() ||
      st.begins.front() != 0 || !std::is_sorted(st.begins.begin(), st.begins.end()))
    throw std::invalid_argument("decomposition state has the wrong shape");
  Vec<Dim> lo, hi;
  for (int d = 0; d < Dim; ++d) {
    lo[d] = st.box[static_cast<std::size_t>(d)];
    hi[d] = st.box[static_cast<std::size_t>(Dim + d)];
  }
  keys_ = KeyMap<Dim>(lo, hi, cfg_.curve);
  std::vector<int> owners;
  for (auto r : st.owners) {
    if (r < 0 || r >= size_) throw std::invalid_argument("decomposition state names a bad rank");
    owners.push_back(static_cast<int>(r));
  }
  owner_ = KeyOwnership(st.begins, owners);
}

template <int Dim> void Decomposition<Dim>::newKeyBox(const ParticleStore& s) {
  // lo and -hi in one MIN reduction.
  std::vector<double> ext(2 * Dim, std::numeric_limits<double>::infinity());
  const auto x = s[x_];
  for (std::size_t i = 0; i < s.localCount(); ++i) {
    if (!x[i].allFinite()) continue;
    for (int d = 0; d < Dim; ++d) {
      ext[static_cast<std::size_t>(d)] = std::min(ext[static_cast<std::size_t>(d)], x[i][d]);
      ext[static_cast<std::size_t>(Dim + d)] =
          std::min(ext[static_cast<std::size_t>(Dim + d)], -x[i][d]);
    }
  }
  MPI_Allreduce(MPI_IN_PLACE, ext.data(), 2 * Dim, MPI_DOUBLE, MPI_MIN, comm_);
  Vec<Dim> lo, hi;
  for (int d = 0; d < Dim; ++d) {
    lo[d] = ext[static_cast<std::size_t>(d)];
    hi[d] = -ext[static_cast<std::size_t>(Dim + d)];
    if (!(lo[d] <= hi[d])) lo[d] = hi[d] = 0.0; // no particle anywhere
    // Room for the motion until the next rebalance; particles beyond it are clamped to the faces
    // (still owned by someone, only less evenly).
    const double pad = 0.05 * (hi[d] - lo[d]);
    lo[d] -= pad;
    hi[d] += pad;
  }
  keys_ = KeyMap<Dim>(lo, hi, cfg_.curve);
}

template <int Dim> MigrationStats Decomposition<Dim>::moveToOwners(ParticleStore& s) {
  s.dropGhosts();
  if (size_ == 1) return {}; // one owner for all: no keys to take (a fifth of a small 2D step)
  const std::size_t n = s.localCount();
  const auto x = s[x_];
  std::vector<std::vector<std::uint32_t>> to(static_cast<std::size_t>(size_));
  std::vector<std::uint32_t> stay;
  stay.reserve(n);
  int farthest = 0;
  for (std::size_t i = 0; i < n; ++i) {
    // A non-finite particle stays where it is, to be reported by id by the run.
    const int r = x[i].allFinite() ? owner_.owner(keys_(x[i])) : rank_;
    if (r == rank_) {
      stay.push_back(static_cast<std::uint32_t>(i));
    } else {
      to[static_cast<std::size_t>(r)].push_back(static_cast<std::uint32_t>(i));
      farthest = std::max(farthest, std::abs(r - rank_));
    }
  }
  const auto columns = allColumns(s);
  const ExchangeResult in = sendRows(comm_, s, columns, to);
  std::uint64_t moved = n - stay.size();
  s.keepLocal(stay);
  const std::size_t first =
      s.appendLocal(in.data.size() / std::max<std::size_t>(s.bytesPerParticle(), 1));
  receiveRows(s, columns, in, first);
  MPI_Allreduce(MPI_IN_PLACE, &moved, 1, MPI_UINT64_T, MPI_SUM, comm_);
  MPI_Allreduce(MPI_IN_PLACE, &farthest, 1, MPI_INT, MPI_MAX, comm_);
  return {moved, farthest};
}

template <int Dim> void Decomposition<Dim>::sortByKey(ParticleStore& s) {
  const std::size_t n = s.localCount();
  const auto x = s[x_];
  const auto id = s[id_];
  std::vector<std::pair<std::uint64_t, ParticleId>> key(n);
  for (std::size_t i = 0; i < n; ++i) key[i] = {keys_(x[i]), id[i]};
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(),
            [&](std::uint32_t a, std::uint32_t b) { return key[a] < key[b]; });
  s.permuteLocal(order);
}

template <int Dim> MigrationStats Decomposition<Dim>::migrate(ParticleStore& s, std::int64_t step) {
  const MigrationStats m = moveToOwners(s);
  if (cfg_.reorderEvery > 0 && step % cfg_.reorderEvery == 0) sortByKey(s);
  return m;
}

template <int Dim> double Decomposition<Dim>::imbalance(const ParticleStore& s) const {
  std::uint64_t mine = 0;
  for (std::int32_t c : s[cost_].first(s.localCount())) mine += static_cast<std::uint64_t>(c);
  std::vector<std::uint64_t> all(static_cast<std::size_t>(size_));
  MPI_Allgather(&mine, 1, MPI_UINT64_T, all.data(), 1, MPI_UINT64_T, comm_);
  std::uint64_t sum = 0, most = 0;
  for (auto c : all) sum += c, most = std::max(most, c);
  return sum > 0 ? static_cast<double>(most) * size_ / static_cast<double>(sum) : 1.0;
}

template <int Dim>
bool Decomposition<Dim>::rebalanceDue(std::int64_t step, double imbalance) const {
  if (size_ == 1) return false;
  if (cfg_.rebalanceEvery > 0 && step % cfg_.rebalanceEvery == 0) return true;
  return imbalance > cfg_.imbalanceThreshold;
}

template <int Dim>
RebalanceReport Decomposition<Dim>::rebalance(ParticleStore& s,
                                              const neighbors::NeighborList* pairs) {
  RebalanceReport report;
  report.imbalanceBefore = imbalance(s);
  std::vector<std::uint64_t> cellOfRow;
  int shift = 0;
  const bool metis = cfg_.metis && size_ > 1 && pairs && pairs->rows() > 0;
  newKeyBox(s);
  const std::size_t n = s.localCount();
  const auto x = s[x_];
  const auto cost = s[cost_];
  std::vector<std::pair<std::uint64_t, std::uint64_t>> kc(n);
  for (std::size_t i = 0; i < n; ++i)
    kc[i] = {keys_(x[i]), static_cast<std::uint64_t>(std::max<std::int32_t>(cost[i], 1))};
  std::sort(kc.begin(), kc.end());
  std::vector<std::uint64_t> keys(n), costs(n);
  for (std::size_t i = 0; i < n; ++i) keys[i] = kc[i].first, costs[i] = kc[i].second;
  owner_ = KeyOwnership::contiguous(weightedSplitters(comm_, keys, costs));

  if (metis) {
    // About 16 particles per cell and at least 64 cells per rank, on whole levels of the curve.
    std::uint64_t global = n;
    MPI_Allreduce(MPI_IN_PLACE, &global, 1, MPI_UINT64_T, MPI_SUM, comm_);
    const double wanted = std::max(static_cast<double>(global) / 16.0, 64.0 * size_);
    const int bits = keyBits<Dim>() * Dim;
    // Cell ids stay below 2^32 (edges are keyed by a pair of them in 64 bits).
    const int levels =
        std::min({keyBits<Dim>(), 32 / Dim, static_cast<int>(std::ceil(std::log2(wanted) / Dim))});
    shift = bits - Dim * levels;
    CellGraph g;
    g.shift = shift;
    std::unordered_map<std::uint64_t, std::uint64_t> weight;
    for (std::size_t i = 0; i < n; ++i) weight[kc[i].first >> shift] += kc[i].second;
    for (const auto& [c, w] : weight) g.cells.push_back(c), g.weight.push_back(w);
    cellOfRow.resize(s.size());
    for (std::size_t j = 0; j < s.size(); ++j) cellOfRow[j] = keys_(x[j]) >> shift;
    std::unordered_map<std::uint64_t, std::uint64_t> edges;
    std::vector<std::uint32_t> row;
    for (std::size_t i = 0; i < pairs->rows() && i < n; ++i) {
      const std::uint64_t ci = cellOfRow[i];
      for (const std::uint32_t j : pairs->of(i, row)) {
        const std::uint64_t cj = cellOfRow[j];
        if (cj != ci) ++edges[(std::min(ci, cj) << 32) | std::max(ci, cj)];
      }
    }
    for (const auto& [e, w] : edges) {
      g.edgeFrom.push_back(e >> 32);
      g.edgeTo.push_back(e & 0xffffffffu);
      g.edgeWeight.push_back(w);
    }
    const MetisResult m = metisPartition(comm_, g);
    if (m.used) {
      owner_ = m.ownership;
      report.metisEdgeCut = m.edgeCut;
    }
  }
  report.moved = moveToOwners(s).moved;
  sortByKey(s);
  report.imbalanceAfter = imbalance(s);
  return report;
}

template class Decomposition<1>;
template class Decomposition<2>;
template class Decomposition<3>;

} // namespace spall::parallel
