#include "spall/parallel/Partition.hpp"

#include "spall/core/Error.hpp"
#include "spall/parallel/SfcKeys.hpp"

#include <algorithm>
#include <map>
#include <metis.h>
#include <numeric>
#include <string>

namespace spall::parallel {

KeyOwnership KeyOwnership::contiguous(std::vector<std::uint64_t> splitters) {
  std::vector<int> ranks(splitters.size());
  std::iota(ranks.begin(), ranks.end(), 0);
  return KeyOwnership(std::move(splitters), std::move(ranks));
}

KeyOwnership::KeyOwnership(std::vector<std::uint64_t> begins, std::vector<int> ranks)
    : begins_(std::move(begins)), ranks_(std::move(ranks)) {}

int KeyOwnership::owner(std::uint64_t key) const {
  // The last interval that begins at or before the key; empty intervals (equal begins) are
  // skipped because upper_bound lands after all of them.
  const auto it = std::upper_bound(begins_.begin(), begins_.end(), key);
  return ranks_[static_cast<std::size_t>(it - begins_.begin()) - 1];
}

std::vector<std::uint64_t> weightedSplitters(MPI_Comm comm, std::span<const std::uint64_t> keys,
                                             std::span<const std::uint64_t> cost) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  std::vector<std::uint64_t> prefix(keys.size() + 1, 0);
  for (std::size_t i = 0; i < keys.size(); ++i) prefix[i + 1] = prefix[i] + cost[i];
  std::uint64_t total = prefix.back();
  MPI_Allreduce(MPI_IN_PLACE, &total, 1, MPI_UINT64_T, MPI_SUM, comm);

  const std::size_t cuts = static_cast<std::size_t>(size - 1);
  std::vector<std::uint64_t> target(cuts), lo(cuts, 0), hi(cuts, kKeyEnd);
  for (std::size_t k = 0; k < cuts; ++k) {
    // ceil((k+1) W / R) = (k+1) q + ceil((k+1) rem / R) with W = q R + rem: no overflow.
    const std::uint64_t R = static_cast<std::uint64_t>(size), q = total / R, rem = total % R;
    target[k] = (k + 1) * q + ((k + 1) * rem + R - 1) / R;
  }
  // Invariant: cost(keys < lo) < target <= cost(keys < hi); stop when hi = lo + 1, then hi is the
  // smallest such key. A target of 0 is met by key 0.
  std::vector<std::uint64_t> below(cuts);
  for (int iter = 0; iter < 64; ++iter) {
    bool open = false;
    std::vector<std::uint64_t> mid(cuts);
    for (std::size_t k = 0; k < cuts; ++k) {
      mid[k] = lo[k] + (hi[k] - lo[k]) / 2;
      open = open || hi[k] - lo[k] > 1;
      const auto pos = std::lower_bound(keys.begin(), keys.end(), mid[k]) - keys.begin();
      below[k] = prefix[static_cast<std::size_t>(pos)];
    }
    if (!open) break;
    MPI_Allreduce(MPI_IN_PLACE, below.data(), static_cast<int>(cuts), MPI_UINT64_T, MPI_SUM, comm);
    for (std::size_t k = 0; k < cuts; ++k) {
      if (hi[k] - lo[k] <= 1) continue;
      (below[k] >= target[k] ? hi[k] : lo[k]) = mid[k];
    }
  }
  std::vector<std::uint64_t> splitters(static_cast<std::size_t>(size), 0);
  for (std::size_t k = 0; k < cuts; ++k) splitters[k + 1] = target[k] == 0 ? 0 : hi[k];
  return splitters;
}

std::vector<std::uint64_t> splittersOf(std::span<const std::uint64_t> keys,
                                       std::span<const std::uint64_t> cost, int ranks) {
  std::uint64_t total = 0;
  for (auto c : cost) total += c;
  const std::uint64_t R = static_cast<std::uint64_t>(ranks), q = total / R, rem = total % R;
  std::vector<std::uint64_t> splitters(static_cast<std::size_t>(ranks), 0);
  std::size_t i = 0;
  std::uint64_t running = 0; // cost of keys[0, i)
  for (std::uint64_t k = 1; k < R; ++k) {
    const std::uint64_t target = k * q + (k * rem + R - 1) / R; // as weightedSplitters
    if (target == 0) continue;
    while (running < target) running += cost[i++];
    // keys[i - 1] brought the running cost to the target; equal keys fall on the same side.
    const std::uint64_t key = keys[i - 1];
    while (i < keys.size() && keys[i] == key) running += cost[i++];
    splitters[static_cast<std::size_t>(k)] = key + 1;
  }
  return splitters;
}

namespace {

template <class T>
std::vector<T> gatherToRoot(MPI_Comm comm, const std::vector<T>& local, MPI_Datatype type) {
  int size = 1, rank = 0;
  MPI_Comm_size(comm, &size);
  MPI_Comm_rank(comm, &rank);
  int n = static_cast<int>(local.size());
  std::vector<int> counts(static_cast<std::size_t>(size)), displs(static_cast<std::size_t>(size));
  MPI_Gather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm);
  std::vector<T> all;
  if (rank == 0) {
    int total = 0;
    for (int r = 0; r < size; ++r)
      displs[static_cast<std::size_t>(r)] = total, total += counts[static_cast<std::size_t>(r)];
    all.resize(static_cast<std::size_t>(total));
  }
  MPI_Gatherv(local.data(), n, type, all.data(), counts.data(), displs.data(), type, 0, comm);
  return all;
}

} // namespace

MetisResult metisPartition(MPI_Comm comm, const CellGraph& local) {
  int size = 1, rank = 0;
  MPI_Comm_size(comm, &size);
  MPI_Comm_rank(comm, &rank);
  const auto cells = gatherToRoot(comm, local.cells, MPI_UINT64_T);
  const auto weights = gatherToRoot(comm, local.weight, MPI_UINT64_T);
  const auto from = gatherToRoot(comm, local.edgeFrom, MPI_UINT64_T);
  const auto to = gatherToRoot(comm, local.edgeTo, MPI_UINT64_T);
  const auto ew = gatherToRoot(comm, local.edgeWeight, MPI_UINT64_T);

  // Root: merge, build the CSR graph, partition. Result broadcast as (begins, ranks, cut).
  std::vector<std::uint64_t> begins;
  std::vector<int> owners;
  std::int64_t cut = 0;
  int used = 0;
  if (rank == 0) {
    std::map<std::uint64_t, std::uint64_t> vw;
    for (std::size_t i = 0; i < cells.size(); ++i) vw[cells[i]] += weights[i];
    std::vector<std::uint64_t> ids;
    for (const auto& [c, w] : vw) ids.push_back(c);
    const auto index = [&](std::uint64_t c) {
      return static_cast<std::size_t>(std::lower_bound(ids.begin(), ids.end(), c) - ids.begin());
    };
    std::map<std::pair<std::size_t, std::size_t>, std::uint64_t> edges;
    for (std::size_t e = 0; e < from.size(); ++e) {
      if (!vw.count(from[e]) || !vw.count(to[e]) || from[e] == to[e]) continue;
      std::size_t a = index(from[e]), b = index(to[e]);
      if (a > b) std::swap(a, b);
      edges[{a, b}] += ew[e];
    }
    idx_t n = static_cast<idx_t>(ids.size());
    if (n >= static_cast<idx_t>(size) && size > 1) {
      std::vector<std::vector<std::pair<idx_t, idx_t>>> adj(ids.size());
      for (const auto& [ab, w] : edges) {
        const idx_t wt = static_cast<idx_t>(std::min<std::uint64_t>(w, 1u << 30));
        adj[ab.first].push_back({static_cast<idx_t>(ab.second), wt});
        adj[ab.second].push_back({static_cast<idx_t>(ab.first), wt});
      }
      std::vector<idx_t> xadj{0}, adjncy, adjwgt, vwgt, part(ids.size(), 0);
      for (std::size_t v = 0; v < ids.size(); ++v) {
        for (const auto& [u, w] : adj[v]) adjncy.push_back(u), adjwgt.push_back(w);
        xadj.push_back(static_cast<idx_t>(adjncy.size()));
        vwgt.push_back(static_cast<idx_t>(std::min<std::uint64_t>(vw[ids[v]], 1u << 30)));
      }
      idx_t ncon = 1, nparts = size, objval = 0;
      idx_t options[METIS_NOPTIONS];
      METIS_SetDefaultOptions(options);
      options[METIS_OPTION_SEED] = 1; // the same partition on every run of the same deck
      const int status = METIS_PartGraphKway(&n, &ncon, xadj.data(), adjncy.data(), vwgt.data(),
                                             nullptr, adjwgt.data(), &nparts, nullptr, nullptr,
                                             options, &objval, part.data());
      if (status == METIS_OK) {
        used = 1;
        cut = objval / 2; // every pair is listed from both of its particles' rows
        for (std::size_t v = 0; v < ids.size(); ++v) {
          const int r = static_cast<int>(part[v]);
          if (!owners.empty() && owners.back() == r) continue; // merge runs of one rank
          begins.push_back(v == 0 ? 0 : ids[v] << local.shift);
          owners.push_back(r);
        }
      }
    }
  }
  MPI_Bcast(&used, 1, MPI_INT, 0, comm);
  MetisResult result;
  if (!used) return result;
  std::uint64_t count = begins.size();
  MPI_Bcast(&count, 1, MPI_UINT64_T, 0, comm);
  begins.resize(count);
  owners.resize(count);
  MPI_Bcast(begins.data(), static_cast<int>(count), MPI_UINT64_T, 0, comm);
  MPI_Bcast(owners.data(), static_cast<int>(count), MPI_INT, 0, comm);
  MPI_Bcast(&cut, 1, MPI_INT64_T, 0, comm);
  result.ownership = KeyOwnership(std::move(begins), std::move(owners));
  result.edgeCut = cut;
  result.used = true;
  return result;
}

} // namespace spall::parallel
