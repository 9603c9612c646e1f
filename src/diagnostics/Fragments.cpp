#include "spall/diagnostics/Fragments.hpp"

#include "spall/core/Random.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numeric>
#include <unordered_map>

namespace spall::diagnostics {

namespace {

struct UnionFind {
  std::vector<std::uint32_t> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  std::uint32_t find(std::uint32_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  }
  void join(std::uint32_t a, std::uint32_t b) {
    a = find(a), b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

// A fragment's share on one rank, sent to the label's home rank: its members there, their exact
// mass, momentum and first moment along axes that are not periodic (fixed point), and along a
// periodic one the sums for the centre about the share's first member.
struct Partial {
  Int128 q = 0;                    // sum of the members' fixed-point masses
  Int128 qmx[3] = {0, 0, 0};       // ... of m x (axes that are not periodic)
  Int128 qmv[3] = {0, 0, 0};       // ... of m v
  ParticleId label = 0, first = 0; // first: the share's smallest id
  std::uint64_t count = 0;
  double m = 0.0, ref[3] = {0, 0, 0}, mx[3] = {0, 0, 0};
};

int homeOf(ParticleId label, int ranks) {
  return static_cast<int>(splitmix64(label) % static_cast<std::uint64_t>(ranks));
}

// Exchanges variable-length blocks of trivially copyable records: out[r] goes to rank r.
template <class T> std::vector<T> allToAll(const std::vector<std::vector<T>>& out, MPI_Comm comm) {
  const int P = static_cast<int>(out.size());
  std::vector<int> sendCounts(P), recvCounts(P), sendOff(P + 1, 0), recvOff(P + 1, 0);
  for (int r = 0; r < P; ++r) sendCounts[r] = static_cast<int>(out[r].size() * sizeof(T));
  MPI_Alltoall(sendCounts.data(), 1, MPI_INT, recvCounts.data(), 1, MPI_INT, comm);
  for (int r = 0; r < P; ++r) {
    sendOff[r + 1] = sendOff[r] + sendCounts[r];
    recvOff[r + 1] = recvOff[r] + recvCounts[r];
  }
  std::vector<std::byte> send(static_cast<std::size_t>(sendOff[P]));
  for (int r = 0; r < P; ++r)
    if (!out[r].empty())
      std::memcpy(send.data() + sendOff[r], out[r].data(), out[r].size() * sizeof(T));
  std::vector<T> in(static_cast<std::size_t>(recvOff[P]) / sizeof(T));
  MPI_Alltoallv(send.data(), sendCounts.data(), sendOff.data(), MPI_BYTE, in.data(),
                recvCounts.data(), recvOff.data(), MPI_BYTE, comm);
  return in;
}

} // namespace

template <int Dim>
FragmentCatalogue findFragments(const FragmentInput<Dim>& in, const GhostRefresh& refresh,
                                MPI_Comm comm) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &ranks);
  const std::size_t rows = in.id.size(), n = in.owned;

  // Friends among this rank's rows.
  UnionFind uf(rows);
  std::vector<std::uint32_t> row;
  for (std::size_t i = 0; i < n; ++i) {
    if (!in.linkable[i]) continue;
    for (const std::uint32_t j : in.pairs->of(i, row)) {
      if (j >= rows || !in.linkable[j]) continue;
      const double reach = 0.5 * (in.linkRadius[i] + in.linkRadius[j]);
      if ((in.x[i] - in.x[j]).squaredNorm() <= reach * reach)
        uf.join(static_cast<std::uint32_t>(i), j);
    }
  }
  std::vector<std::uint32_t> root(rows);
  for (std::size_t r = 0; r < rows; ++r) root[r] = uf.find(static_cast<std::uint32_t>(r));

  // The smallest id each component reaches, across ranks.
  std::vector<ParticleId> label(in.id.begin(), in.id.end());
  std::vector<ParticleId> best(rows, ~ParticleId{0});
  for (int round = 0;; ++round) {
    std::fill(best.begin(), best.end(), ~ParticleId{0});
    for (std::size_t r = 0; r < rows; ++r) best[root[r]] = std::min(best[root[r]], label[r]);
    int changed = 0;
    for (std::size_t r = 0; r < n; ++r)
      if (best[root[r]] != label[r]) label[r] = best[root[r]], changed = 1;
    MPI_Allreduce(MPI_IN_PLACE, &changed, 1, MPI_INT, MPI_MAX, comm);
    if (!changed && round > 0) break;
    refresh(label); // ghosts take their owners' labels
  }

  // Each rank's share of each fragment (members in id order), summed at the label's home rank:
  // one record per fragment and rank, however large the fragment.
  // The largest |m|, |m x_d| and |m v_d| over all ranks set each quantity's fixed point.
  std::array<double, 7> largest{};
  for (std::size_t i = 0; i < n; ++i) {
    largest[0] = std::max(largest[0], in.m[i]);
    for (int d = 0; d < Dim; ++d) {
      largest[1 + d] = std::max(largest[1 + d], std::abs(in.m[i] * in.x[i][d]));
      largest[4 + d] = std::max(largest[4 + d], std::abs(in.m[i] * in.v[i][d]));
    }
  }
  MPI_Allreduce(MPI_IN_PLACE, largest.data(), 7, MPI_DOUBLE, MPI_MAX, comm);
  const FixedPoint fixed(largest[0]);
  std::array<FixedPoint, 3> fixedMx, fixedMv;
  for (int d = 0; d < Dim; ++d) fixedMx[d] = FixedPoint(largest[1 + d]);
  for (int d = 0; d < Dim; ++d) fixedMv[d] = FixedPoint(largest[4 + d]);
  std::vector<std::uint32_t> byLabel(n);
  std::iota(byLabel.begin(), byLabel.end(), 0u);
  std::sort(byLabel.begin(), byLabel.end(), [&](std::uint32_t a, std::uint32_t b) {
    return label[a] != label[b] ? label[a] < label[b] : in.id[a] < in.id[b];
  });
  const auto unwrap = [&](double x, double ref, int d) {
    // Periodic axes: the image nearest the reference.
    return in.period[d] > 0.0 ? x - in.period[d] * std::round((x - ref) / in.period[d]) : x;
  };
  std::vector<std::vector<Partial>> out(static_cast<std::size_t>(ranks));
  for (std::size_t k = 0; k < n;) {
    const std::uint32_t i0 = byLabel[k];
    Partial pt;
    pt.label = label[i0];
    pt.first = in.id[i0];
    for (int d = 0; d < Dim; ++d) pt.ref[d] = in.x[i0][d];
    for (; k < n && label[byLabel[k]] == pt.label; ++k) {
      const std::uint32_t i = byLabel[k];
      ++pt.count;
      pt.q += fixed.of(in.m[i]);
      pt.m += in.m[i];
      for (int d = 0; d < Dim; ++d) {
        if (in.period[d] > 0.0)
          pt.mx[d] += in.m[i] * unwrap(in.x[i][d], pt.ref[d], d);
        else
          pt.qmx[d] += fixedMx[d].of(in.m[i] * in.x[i][d]);
        pt.qmv[d] += fixedMv[d].of(in.m[i] * in.v[i][d]);
      }
    }
    out[static_cast<std::size_t>(homeOf(pt.label, ranks))].push_back(pt);
  }
  std::vector<Partial> mine = allToAll(out, comm);
  // The share holding the label (the fragment's smallest id) first: its first member is the
  // reference of the periodic images, the same on any rank count.
  std::sort(mine.begin(), mine.end(), [](const Partial& a, const Partial& b) {
    return a.label != b.label ? a.label < b.label : a.first < b.first;
  });
  std::vector<Fragment> local;
  for (std::size_t k = 0; k < mine.size();) {
    const Partial& head = mine[k];
    Fragment f;
    f.label = head.label;
    Int128 q = 0, qmx[3] = {0, 0, 0}, qmv[3] = {0, 0, 0};
    double m = 0.0, mx[3] = {0, 0, 0};
    for (; k < mine.size() && mine[k].label == head.label; ++k) {
      const Partial& pt = mine[k];
      f.particles += pt.count;
      q += pt.q;
      m += pt.m;
      for (int d = 0; d < Dim; ++d) {
        const double shift = unwrap(pt.ref[d], head.ref[d], d) - pt.ref[d];
        mx[d] += pt.mx[d] + pt.m * shift;
        qmx[d] += pt.qmx[d];
        qmv[d] += pt.qmv[d];
      }
    }
    f.mass = fixed.value(q);
    for (int d = 0; d < Dim; ++d) {
      f.x[d] = in.period[d] > 0.0 ? mx[d] / m : fixedMx[d].value(qmx[d]) / f.mass;
      f.v[d] = fixedMv[d].value(qmv[d]) / f.mass;
    }
    local.push_back(f);
  }

  // The catalogue on rank 0, in order; every rank learns each fragment's place.
  FragmentCatalogue cat;
  const int mineBytes = static_cast<int>(local.size() * sizeof(Fragment));
  std::vector<int> counts(static_cast<std::size_t>(ranks)),
      offsets(static_cast<std::size_t>(ranks) + 1, 0);
  MPI_Gather(&mineBytes, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm);
  for (int r = 0; r < ranks; ++r) offsets[r + 1] = offsets[r] + counts[r];
  std::vector<Fragment> all(rank == 0 ? static_cast<std::size_t>(offsets[ranks]) / sizeof(Fragment)
                                      : 0);
  MPI_Gatherv(local.data(), mineBytes, MPI_BYTE, all.data(), counts.data(), offsets.data(),
              MPI_BYTE, 0, comm);
  std::uint64_t count = all.size();
  MPI_Bcast(&count, 1, MPI_UINT64_T, 0, comm);
  std::sort(all.begin(), all.end(), [](const Fragment& a, const Fragment& b) {
    return a.mass != b.mass ? a.mass > b.mass : a.label < b.label;
  });
  std::vector<ParticleId> order(count);
  for (std::size_t k = 0; k < all.size(); ++k) order[k] = all[k].label;
  MPI_Bcast(order.data(), static_cast<int>(count), MPI_UINT64_T, 0, comm);
  std::unordered_map<ParticleId, std::int64_t> place;
  place.reserve(count);
  for (std::size_t k = 0; k < order.size(); ++k)
    place.emplace(order[k], static_cast<std::int64_t>(k));
  cat.index.resize(n);
  for (std::size_t i = 0; i < n; ++i) cat.index[i] = place.at(label[i]);
  cat.count = count;
  cat.fragments = std::move(all);
  return cat;
}

template FragmentCatalogue findFragments<1>(const FragmentInput<1>&, const GhostRefresh&, MPI_Comm);
template FragmentCatalogue findFragments<2>(const FragmentInput<2>&, const GhostRefresh&, MPI_Comm);
template FragmentCatalogue findFragments<3>(const FragmentInput<3>&, const GhostRefresh&, MPI_Comm);

} // namespace spall::diagnostics
