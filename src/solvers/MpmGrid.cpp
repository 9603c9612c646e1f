#include "spall/solvers/MpmGrid.hpp"

#include "MpmGridContact.hpp"
#include "MpmGridImpl.hpp"
#include "MpmGridLoads.hpp"
#include "MpmGridWalls.hpp"

#include <stdexcept>

namespace spall::solvers {

template <int Dim>
std::unique_ptr<MpmGrid<Dim>> makeMpmGrid(const MpmConfig& config, const Vec<Dim>& origin,
                                          std::vector<GridWall<Dim>> walls, bool axisymmetric) {
  if (axisymmetric && Dim != 2) throw std::logic_error("axisymmetric MPM needs dimension 2");
  if (config.shape == MpmShape::Linear)
    return std::make_unique<grid::Grid<Dim, MpmShape::Linear>>(config, origin, std::move(walls),
                                                               axisymmetric);
  if (config.shape == MpmShape::Cpdi)
    return std::make_unique<grid::Grid<Dim, MpmShape::Cpdi>>(config, origin, std::move(walls),
                                                             axisymmetric);
  // uGIMP and cpGIMP: the same weights, cpGIMP's box from the points' domains (MpmParticles).
  return std::make_unique<grid::Grid<Dim, MpmShape::Gimp>>(config, origin, std::move(walls),
                                                           axisymmetric);
}

template std::unique_ptr<MpmGrid<1>> makeMpmGrid<1>(const MpmConfig&, const Vec<1>&,
                                                    std::vector<GridWall<1>>, bool);
template std::unique_ptr<MpmGrid<2>> makeMpmGrid<2>(const MpmConfig&, const Vec<2>&,
                                                    std::vector<GridWall<2>>, bool);
template std::unique_ptr<MpmGrid<3>> makeMpmGrid<3>(const MpmConfig&, const Vec<3>&,
                                                    std::vector<GridWall<3>>, bool);

} // namespace spall::solvers
