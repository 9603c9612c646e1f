#pragma once
// Dimension-templated small vectors and tensors (Eigen fixed size). Dim is 1, 2 or 3 everywhere.
#include <Eigen/Dense>
#include <cstdint>

namespace spall {

template <int Dim> using Vec = Eigen::Matrix<double, Dim, 1>;
template <int Dim> using Tensor = Eigen::Matrix<double, Dim, Dim>;

using ParticleId = std::uint64_t;

} // namespace spall
