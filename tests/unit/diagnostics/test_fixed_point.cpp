// FixedPoint (diagnostics/OrderFreeSums.hpp) rounds a term to its fixed-point integer inline:
// the same integer as llround(ldexp(x, E)) (the library's rounding, half away from zero) for
// terms of every magnitude below the largest, exact halves of both signs, and largest values
// whose scale 2^E is not a normal double (tiny and huge).
#include "spall/diagnostics/OrderFreeSums.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using spall::diagnostics::FixedPoint;
using spall::diagnostics::Int128;

namespace {

// The reference: the library calls FixedPoint made before it was inlined.
Int128 reference(double x, double largest) {
  int e = 0;
  std::frexp(largest > 0.0 ? largest : 1.0, &e);
  return static_cast<Int128>(std::llround(std::ldexp(x, 62 - e)));
}

} // namespace

TEST(FixedPoint, RoundsAsTheLibraryDoes) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double largest : {1.0, 3.7e9, 2.5e-7, 1e-300, 4.9e-320, 1e300, 1.7e308}) {
    const FixedPoint fp(largest);
    int e = 0;
    std::frexp(largest, &e);
    const int E = 62 - e;
    for (int k = 0; k < 20000; ++k) {
      // Terms from the largest down to 2^-70 of it, both signs.
      const double x = largest * u(rng) * std::exp2(-70.0 * std::abs(u(rng)));
      ASSERT_TRUE(fp.of(x) == reference(x, largest)) << x << " of " << largest;
    }
    // Exact halves and their neighbours (where the scaled value is small enough to have them).
    for (double m : {0.5, 1.5, 2.5, 1e6 + 0.5, 0x1p51 + 0.5}) {
      for (double s : {1.0, -1.0}) {
        const double x = std::ldexp(s * m, -E);
        if (!(std::abs(x) <= largest) || x == 0.0) continue;
        for (double y : {x, std::nextafter(x, 0.0), std::nextafter(x, 2.0 * x)})
          EXPECT_TRUE(fp.of(y) == reference(y, largest)) << y << " of " << largest;
      }
    }
    EXPECT_TRUE(fp.of(largest) == reference(largest, largest));
    EXPECT_TRUE(fp.of(-largest) == reference(-largest, largest));
    EXPECT_TRUE(fp.of(0.0) == 0);
  }
}
