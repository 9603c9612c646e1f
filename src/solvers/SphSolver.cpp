#include "spall/solvers/SphSolver.hpp"

#include "SphRatesLoop.hpp"
#include "SphVoronoiCells.hpp"

namespace spall::solvers {

namespace {
template <int Dim, bool Aniso>
std::unique_ptr<Solver<Dim>> makeSph(const SolverSetup& setup, ParticleStore& store,
                                     const ParticleFields<Dim>& f) {
  switch (setup.config.kernel) {
  case KernelType::CubicSpline:
    return std::make_unique<sph::Sph<Dim, kernels::CubicSpline<Dim>, Aniso>>(setup, store, f);
  case KernelType::WendlandC2:
    return std::make_unique<sph::Sph<Dim, kernels::WendlandC2<Dim>, Aniso>>(setup, store, f);
  case KernelType::WendlandC4:
    return std::make_unique<sph::Sph<Dim, kernels::WendlandC4<Dim>, Aniso>>(setup, store, f);
  }
  return nullptr;
}
} // namespace

template <int Dim>
std::unique_ptr<Solver<Dim>> makeSolver(const SolverSetup& setup, ParticleStore& store,
                                        const ParticleFields<Dim>& f) {
  return f.anisotropic() ? makeSph<Dim, true>(setup, store, f)
                         : makeSph<Dim, false>(setup, store, f);
}

template std::unique_ptr<Solver<1>> makeSolver<1>(const SolverSetup&, ParticleStore&,
                                                  const ParticleFields<1>&);
template std::unique_ptr<Solver<2>> makeSolver<2>(const SolverSetup&, ParticleStore&,
                                                  const ParticleFields<2>&);
template std::unique_ptr<Solver<3>> makeSolver<3>(const SolverSetup&, ParticleStore&,
                                                  const ParticleFields<3>&);

} // namespace spall::solvers
