#pragma once
// Which pairs of the force loop are cracked: a pair with a failed particle (damage 1, in a
// material whose failed particles carry no tension), or a pair of intact particles with a failed
// one between them. A cracked pair carries compression only (as across a frictionless contact)
// and is left out of the velocity gradient and the density rate.
//
// "Between" (the three-point coupling of Spheral's damage models, in our own form): the failed
// particle k lies inside the circle (sphere) on x_i x_j as diameter, (x_i - x_k).(x_j - x_k) < 0,
// and interacts with both. Without it, two intact particles on either side of a crack one
// particle wide are still inside each other's kernel, and the pieces pull on each other.
//
// Each row finds the k of its pairs among its own failed neighbors, and the test asks that k
// interact with both i and j by the pair predicate (the kernel of either reaches the other), which
// every neighbor list satisfies: so rows i and j find the same k, the pair is cracked from both
// sides or neither (momentum stays conserved), and what a row decides does not depend on which
// rank owns its neighbors.
#include "spall/core/MemoryAccounting.hpp"
#include "spall/core/Types.hpp"
#include "spall/neighbors/NeighborList.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace spall::solvers {

// The pair predicate of the kernels: the support of either particle reaches the other, for
// scalar h (the larger of the two) or ASPH metrics G = H^T H.
template <int Dim> bool reaches(const Vec<Dim>& r, double hMax, double support) {
  return r.squaredNorm() < (support * hMax) * (support * hMax);
}
template <int Dim>
bool reaches(const Vec<Dim>& r, const Tensor<Dim>& Ga, const Tensor<Dim>& Gb, double support) {
  return r.dot(Ga * r) < support * support || r.dot(Gb * r) < support * support;
}

template <int Dim> class CrackedPairs {
public:
  // Marks every row (ghosts included) that failed and carries no tension; whether any did.
  bool mark(std::span<const double> D, std::span<const std::int32_t> material,
            const std::vector<bool>& carriesNoTension) {
    failed_.resize(D.size());
    bool any = false;
    for (std::size_t j = 0; j < D.size(); ++j) {
      failed_[j] = D[j] >= 1.0 && carriesNoTension[static_cast<std::size_t>(material[j])];
      any = any || failed_[j] != 0;
    }
    return any;
  }
  bool failed(std::size_t j) const { return failed_[j] != 0; }

  // The failed neighbors of each of the first n rows.
  void collect(const neighbors::NeighborList& nl, std::size_t n) {
    start_.assign(n + 1, 0);
    list_.clear();
    std::vector<std::uint32_t> row;
    for (std::size_t i = 0; i < n; ++i) {
      for (std::uint32_t k : nl.of(i, row))
        if (failed_[k] != 0) list_.push_back(k);
      start_[i + 1] = static_cast<std::uint32_t>(list_.size());
    }
  }
  bool besideCrack(std::size_t i) const { return start_[i] != start_[i + 1]; }

  // Whether the pair (i, j) of the force loop (i a row of collect) is cracked. interacts(a, b):
  // the pair predicate of the kernels (reaches).
  template <class Interacts>
  bool cracked(std::size_t i, std::size_t j, std::span<const Vec<Dim>> x,
               const Interacts& interacts) const {
    if ((failed_[i] | failed_[j]) != 0) return true;
    for (std::uint32_t a = start_[i]; a < start_[i + 1]; ++a) {
      const std::uint32_t k = list_[a];
      if ((x[i] - x[k]).dot(x[j] - x[k]) < 0.0 && interacts(i, k) && interacts(j, k)) return true;
    }
    return false;
  }

  std::size_t bytes() const { return allocatedBytes(failed_, start_, list_); }

private:
  std::vector<std::uint8_t> failed_;
  std::vector<std::uint32_t> start_, list_;
};

} // namespace spall::solvers
