#include "spall/materials/CapPlasticity.hpp"

#include <cmath>
#include <limits>

namespace spall::materials {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// A root of fn in [a, b], where fa and fb differ in sign (either may be infinite): Brent's method
// (Brent 1973, ch. 4): inverse quadratic or secant steps while they shrink the bracket fast
// enough, else bisection (also while an end is infinite); a step is never shorter than the
// tolerance, so the bracket closes. Stops when the bracket is 4 ulp of `scale` wide, or at
// kMaxIterations evaluations: any point of it is then the answer.
template <class Fn>
double bracketedRoot(const Fn& fn, double a, double fa, double b, double fb, double scale,
                     int& count) {
  const double eps = std::numeric_limits<double>::epsilon();
  // No sign change: the root is at an end, up to the round-off of evaluating it (a trial a hair
  // outside the surface).
  if ((fa > 0.0) == (fb > 0.0)) return std::abs(fa) < std::abs(fb) ? a : b;
  double c = a, fc = fa, d = b - a, e = d; // b: the best point; c: the other end of the bracket
  for (int k = 0; k < CapPlasticity::kMaxIterations; ++k) {
    if ((fb > 0.0) == (fc > 0.0)) c = a, fc = fa, d = e = b - a;
    if (std::abs(fc) < std::abs(fb)) a = b, b = c, c = a, fa = fb, fb = fc, fc = fa;
    const double tol = 2.0 * eps * (std::abs(b) + scale), half = 0.5 * (c - b);
    if (std::abs(half) <= tol || fb == 0.0) return b;
    if (std::abs(e) >= tol && std::abs(fa) > std::abs(fb) && std::isfinite(fa) &&
        std::isfinite(fc)) {
      const double s = fb / fa;
      double p, q;
      if (a == c) { // secant
        p = 2.0 * half * s;
        q = 1.0 - s;
      } else { // inverse quadratic through a, b, c
        const double r = fb / fc, t = fa / fc;
        p = s * (2.0 * half * t * (t - r) - (b - a) * (r - 1.0));
        q = (t - 1.0) * (r - 1.0) * (s - 1.0);
      }
      if (p > 0.0) q = -q;
      p = std::abs(p);
      if (2.0 * p < std::min(3.0 * half * q - std::abs(tol * q), std::abs(e * q)))
        e = d, d = p / q; // accept the interpolation
      else
        d = half, e = d;
    } else {
      d = half, e = d;
    }
    a = b, fa = fb;
    b += std::abs(d) > tol ? d : std::copysign(tol, half);
    fb = fn(b);
    ++count;
  }
  return b;
}

} // namespace

double CapPlasticity::capPosition(double epsVp) const {
  if (!hardening) return P0;
  if (epsVp <= -P3) return -kInf; // every pore closed: no finite pressure gets there
  const double X = epsVp < 0.0 ? P0 + std::log1p(epsVp / P3) / P1 : P0 + epsVp / (P1 * P3);
  return std::min(X, peakI1);
}

double CapPlasticity::porosity(double epsVp) const {
  return -std::expm1(-(P3 + epsVp));
}

CapShape CapPlasticity::shape(double I1, double X) const {
  const double k = kappa(X), Ff = fSlope * (peakI1 - I1);
  if (I1 >= k) return {Ff, 1.0, -fSlope};
  const double w = k - X;
  if (!(w > 0.0)) return {Ff, 0.0, 0.0}; // the cap retracted onto the vertex: a point
  const double u = (k - I1) / w, Fc = std::sqrt(std::max(0.0, 1.0 - u * u));
  return {Ff, Fc, -fSlope * Fc * Fc + Ff * u / w};
}

double CapPlasticity::yieldRadius(double I1, double X) const {
  if (I1 > peakI1 || I1 < X) return 0.0;
  const CapShape c = shape(I1, X);
  return c.Ff * c.Fc;
}

double CapPlasticity::yieldSlope(double I1, double X) const {
  const CapShape c = shape(I1, X);
  if (!(c.Fc > 0.0)) return kInf; // the cap tip: the normal is the hydrostat
  return c.FpFc / c.Fc;
}

double CapPlasticity::yieldFunction(double I1, double q, double X) const {
  if (I1 > peakI1 || I1 < X) return kInf;
  return q - yieldRadius(I1, X);
}

double CapPlasticity::effectiveI1(double rho, double epsVp) const {
  return 3.0 * K * (std::log(rho0 / rho) - epsVp);
}

double CapPlasticity::porePressure(double rho, double epsVp) const {
  if (!(Kf > 0.0)) return pf0;
  const double epsF = std::log(porosity(epsVp) / porosity(0.0)) + std::log(rho0 / rho);
  return std::max(0.0, pf0 - Kf * epsF);
}

CapResponse CapPlasticity::respond(double rho, const CapState& s, double I1over) const {
  CapResponse r;
  r.X = capPosition(s.volumetricStrain);
  r.phi = porosity(s.volumetricStrain);
  r.pf = porePressure(rho, s.volumetricStrain);
  r.p = -(effectiveI1(rho, s.volumetricStrain) + I1over) / 3.0 + r.pf;
  // The undrained fluid stiffens compaction by at most K_f / phi (all the volume change into the
  // pores): the bound keeps the time step stable whatever the split.
  const double fluid = Kf > 0.0 ? Kf / std::max(r.phi, 1e-12) : 0.0;
  r.cs = std::sqrt((K + 4.0 * G / 3.0 + fluid) / rho);
  return r;
}

CapStep CapPlasticity::update(const CapState& s, const Mat3& L, double dt, double rho) const {
  CapStep out{s, 0};
  const Mat3 St = elasticTrial(s.S, L, dt, G);
  const double qt = std::sqrt(0.5 * St.squaredNorm());
  const double eps0 = s.volumetricStrain;
  const double I1t = effectiveI1(rho, eps0), Xn = capPosition(eps0);
  out.state.S = St;
  if (yieldFunction(I1t, qt, Xn) <= 0.0) return out;

  // The cap after the plastic volume change that takes the trial's I1t to I1.
  const auto Xof = [&](double I1) { return capPosition(eps0 + (I1t - I1) / (3.0 * K)); };
  double I1 = peakI1, q = 0.0; // the vertex, unless a branch below finds the surface
  // The Drucker-Prager side in closed form: q = qt - G dl, I1 = I1t - 9 K beta fs dl on the line.
  const double dl = (qt - fSlope * (peakI1 - I1t)) / (G + 9.0 * K * dilatancy * fSlope * fSlope);
  const double I1dp = I1t - 9.0 * K * dilatancy * fSlope * dl, qdp = qt - G * dl;
  if (dl > 0.0 && qdp > 0.0 && I1dp >= kappa(Xof(I1dp))) {
    I1 = I1dp, q = qdp;
  } else if (!(dl > 0.0 && qdp <= 0.0)) { // not past the vertex: the cap
    const double scale = std::abs(I1t) + std::abs(peakI1) + std::abs(Xn);
    // The cap tip the same return reaches: I1h = X(I1h) (I1 - X(I1) increases with I1; X = Xn at
    // I1 = I1t, so the root lies between I1t and Xn).
    double I1h = P0;
    if (hardening) {
      const auto g = [&](double x) { return x - Xof(x); };
      const double a = std::min(I1t, Xn), b = std::max(I1t, Xn);
      I1h = a == b ? a : bracketedRoot(g, a, g(a), b, g(b), scale, out.iterations);
    }
    if (I1h >= peakI1 - 1e-12 * scale) {
      I1 = peakI1; // the cap has retracted onto the vertex
    } else if (!(qt > 1e-12 * scale)) {
      I1 = I1h; // hydrostatic (up to round-off): the tip
    } else {
      // h Fc: the sign of h, but finite at the tip (shape() gives F' Fc).
      const auto at = [&](double x) { return shape(x, Xof(x)); };
      const auto h = [&](double x) {
        const CapShape c = at(x);
        const double beta = c.FpFc < 0.0 ? dilatancy : 1.0;
        return G * (I1t - x) * c.Fc + 9.0 * K * beta * c.FpFc * (qt - c.Ff * c.Fc);
      };
      // Roots in t = sqrt(I1 - I1h): Fc grows like sqrt(I1 - I1h) off the tip, so both functions
      // are near linear in t there (a nearly hydrostatic trial's root lies ~qt^2 off the tip).
      const double T = std::sqrt(peakI1 - I1h);
      const auto solve = [&](const auto& fn, double xa, double xb) {
        const auto ft = [&](double t) { return fn(I1h + t * t); };
        const double ta = std::sqrt(xa - I1h), tb = std::sqrt(xb - I1h);
        const double t = bracketedRoot(ft, ta, fn(xa), tb, fn(xb), T, out.iterations);
        return t == ta ? xa : t == tb ? xb : std::min(I1h + t * t, peakI1);
      };
      // A root on the compaction side (F' > 0) lies right of I1t, one on the dilation side left
      // of it; a root on the wrong side would be a farthest point (dlambda < 0). Usually the
      // whole bracket gives the right one; if not, the top of the cap (F' = 0) parts the sides.
      I1 = solve(h, I1h, peakI1);
      const double FpFc = at(I1).FpFc;
      if ((FpFc > 0.0 && I1 < I1t) || (FpFc < 0.0 && I1 > I1t)) {
        const double top = solve([&](double x) { return at(x).FpFc; }, I1h, peakI1);
        I1 = I1t < top ? solve(h, std::max(I1t, I1h), top) : solve(h, top, std::min(I1t, peakI1));
      }
      q = std::min(yieldRadius(I1, Xof(I1)), qt); // dlambda >= 0 (the root's last ulp)
    }
  }
  out.state.volumetricStrain = eps0 + (I1t - I1) / (3.0 * K);
  out.state.S = qt > 0.0 ? Mat3(St * (q / qt)) : Mat3::Zero();
  // |de^p| = sqrt2 (qt - q) / 2G; the equivalent strain is sqrt(2/3) of it.
  out.state.plasticStrain += (qt - q) / (std::sqrt(3.0) * G);
  return out;
}

double CapPlasticity::relaxationTime(const Mat3& L) const {
  const double rate = std::max(0.5 * (L + L.transpose()).norm(), 1e-15);
  return T2 == 0.0 ? T1 : T1 * std::pow(1.0 / rate, T2);
}

CapOverstress CapPlasticity::relax(const CapOverstress& o, const Mat3& Sn, const CapState& qs0,
                                   const CapState& qs1, const Mat3& L, double dt) const {
  const double x = dt / relaxationTime(L);
  const double r = std::exp(-x);
  const double R = x > 0.0 ? -std::expm1(-x) / x : 1.0; // (1 - r)/x, without cancellation

  const Mat3 trial = elasticTrial(Sn, L, dt, G) - Sn;
  CapOverstress next;
  next.S = o.S * r + (trial - (qs1.S - qs0.S)) * R;
  next.I1 = o.I1 * r + 3.0 * K * (qs1.volumetricStrain - qs0.volumetricStrain) * R;
  return next;
}

std::optional<double> CapPlasticity::densityForPressure(double p) const {
  // p = -K eps + p_f(eps), eps = ln(rho0/rho), decreasing in eps; p_f = pf0 - Kf eps until the
  // fluid cavitates at eps = pf0 / Kf.
  double eps = (pf0 - p) / (K + std::max(Kf, 0.0));
  if (Kf > 0.0 && eps > pf0 / Kf) eps = -p / K;
  if (yieldFunction(3.0 * K * eps, 0.0, capPosition(0.0)) > 0.0) return std::nullopt;
  return rho0 * std::exp(-eps);
}

} // namespace spall::materials
