#pragma once
// MPM's background grid as a snapshot shows it: the lattice nodes one rank writes, each once
// over all ranks (the rank owning the node's lowest-id particle), with the state's P2G sums.
#include "spall/core/Types.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace spall::solvers {

template <int Dim> struct GridNodes {
  std::vector<std::array<std::int64_t, Dim>> index; // lattice index k: X = origin + k cell_size
  std::vector<Vec<Dim>> x;                          // the node's place (m)
  std::vector<double> mass;                         // sum_p S_Ip m_p (kg; rz: of the rings)
  std::vector<Vec<Dim>> velocity;   // the centre of mass's, sum_p S_Ip m_p v_p / m_I (no wall,
                                    // contact or fixed-body constraint)
  std::vector<Vec<Dim>> force;      // the stress's, -sum_p V_p sigma_p grad S_Ip (N; rz: hoop too)
  std::vector<std::int32_t> fields; // velocity fields (contact groups) with mass at the node
  std::size_t size() const { return index.size(); }
};

} // namespace spall::solvers
