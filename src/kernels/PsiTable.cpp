#include "spall/kernels/PsiTable.hpp"

#include <algorithm>
#include <cmath>

namespace spall::kernels {

namespace {
double interpolate(const std::vector<double>& x, const std::vector<double>& y, double xv) {
  if (xv <= x.front()) return y.front() * xv / x.front();
  if (xv >= x.back()) return y.back() * xv / x.back();
  const auto it = std::upper_bound(x.begin(), x.end(), xv);
  const std::size_t i = static_cast<std::size_t>(it - x.begin());
  const double t = (xv - x[i - 1]) / (x[i] - x[i - 1]);
  return y[i - 1] + t * (y[i] - y[i - 1]);
}
} // namespace

double PsiTable::psi0(double nh) const {
  return interpolate(nh_, psi_, nh);
}
double PsiTable::nodesPerH(double psi0) const {
  return interpolate(psi_, nh_, psi0);
}

} // namespace spall::kernels
