#pragma once
// Owen (2010), Sec. II-A, Eq. 1: the zeroth moment Psi_0 = (sum_j W^H(eta_j))^(1/nu) of a uniform
// lattice with n_h nodes per smoothing scale, tabulated once at start-up for the chosen kernel
// and dimension. Psi_0 is nearly linear in n_h (Owen, Fig. 3), so inverting the table gives the
// effective n_h of any measured Psi_0.
#include <cmath>
#include <vector>

namespace spall::kernels {

class PsiTable {
public:
  // `WH` is the kernel's W^H(eta); `dim` the lattice dimension.
  template <class KernelT, int Dim> static PsiTable build() {
    return PsiTable(
        Dim, [](double eta) { return KernelT::WH(eta); }, KernelT::support);
  }

  // Psi_0 of a cubic lattice with spacing 1/nh in eta space.
  double psi0(double nh) const;
  // The effective n_h whose lattice has this Psi_0 (linear interpolation; beyond the table
  // Psi_0 is taken proportional to n_h, its asymptotic form).
  double nodesPerH(double psi0) const;

  double nhMin() const { return nh_.front(); }
  double nhMax() const { return nh_.back(); }

private:
  template <class F> PsiTable(int dim, F&& WH, double support) { tabulate(dim, WH, support); }
  template <class F> void tabulate(int dim, F& WH, double support);

  std::vector<double> nh_;
  std::vector<double> psi_; // strictly increasing after tabulate()
};

// Sum of W^H over a cubic lattice of spacing 1/nh in `dim` dimensions (origin excluded:
// W^H(0) = 0 for every kernel here).
template <class F> double latticeSum(int dim, F& WH, double support, double nh) {
  const int n = static_cast<int>(support * nh) + 1;
  double sum = 0.0;
  const int ny = dim >= 2 ? n : 0, nz = dim >= 3 ? n : 0;
  for (int k = -nz; k <= nz; ++k)
    for (int j = -ny; j <= ny; ++j)
      for (int i = -n; i <= n; ++i) {
        const double eta = std::sqrt(double(i * i + j * j + k * k)) / nh;
        if (eta < support) sum += WH(eta);
      }
  return sum;
}

template <class F> void PsiTable::tabulate(int dim, F& WH, double support) {
  // n_h from 0.55 (first neighbors just inside the support) to 8 (far more than anyone runs).
  const int count = 300;
  const double lo = 0.55, hi = 8.0;
  for (int k = 0; k < count; ++k) {
    const double nh = lo + (hi - lo) * k / (count - 1);
    const double psi = std::pow(latticeSum(dim, WH, support, nh), 1.0 / dim);
    // Lattice shells enter the support in steps, so Psi_0 can stall between them; keep the
    // table strictly increasing so the inverse is unique.
    if (!psi_.empty() && psi <= psi_.back()) continue;
    nh_.push_back(nh);
    psi_.push_back(psi);
  }
}

} // namespace spall::kernels
