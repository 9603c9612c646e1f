#include "GradedSites.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <fmt/format.h>
#include <numbers>

namespace spall::app::sites {

namespace {

constexpr double kPi = std::numbers::pi;

// Layer j is fine (the body's spacing) while a whole layer of s0 ends within `within`; the
// tolerance takes round-off out of a `within` that is a multiple of s0.
bool fine(double start, double s0, double within) {
  return start + s0 <= within + 1e-9 * s0;
}

// Calls visit(layer) from the reference out to `end`: geometric growth from the first layer
// beyond `within`. (Easing the growth in and out over 4-16 layers leaves a plane wave's
// reflection as it is, 0.88-0.89% at ratio 1.05: it comes from the gradient itself, not from
// where it starts.)
template <class Visit>
void forEachLayer(double s0, double within, double ratio, double smax, double end, Visit&& visit) {
  double b = 0.0, s = s0;
  for (bool first = true; b < end; first = false) {
    if (!first && !fine(b, s0, within)) s = std::min(smax, s * ratio);
    visit(Layer{b, s});
    b += s;
  }
}

// The reference as the layers see it: a line in 2D and a point in 1D are planes (slabs along
// them); a line in 3D is a line (cylinders), a point in 2D or 3D a point (rings, shells).
template <int Dim> struct Reference {
  enum class Kind { Plane, Line, Point } kind;
  Vec<Dim> p, n; // a point on it; a plane's unit normal, a line's unit direction
};

template <int Dim> Reference<Dim> referenceOf(const GradingConfig& g) {
  using K = typename Reference<Dim>::Kind;
  if (g.plane) return {K::Plane, toVec<Dim>(g.plane->point), toVec<Dim>(g.plane->normal)};
  if (g.line) {
    const Vec<Dim> p = toVec<Dim>(g.line->point), d = toVec<Dim>(g.line->direction);
    if constexpr (Dim == 2) return {K::Plane, p, Vec<Dim>(d[1], -d[0])};
    return {K::Line, p, d};
  }
  const Vec<Dim> p = toVec<Dim>(g.point);
  if constexpr (Dim == 1) return {K::Plane, p, Vec<Dim>::Ones()};
  return {K::Point, p, Vec<Dim>::Zero()};
}

// The coordinate axis a unit vector lies along, or -1.
template <int Dim> int axisOf(const Vec<Dim>& n) {
  for (int a = 0; a < Dim; ++a)
    if (std::abs(std::abs(n[a]) - 1.0) < 1e-12) return a;
  return -1;
}

// Unit vectors completing n to an orthonormal basis.
template <int Dim> std::array<Vec<Dim>, Dim - 1> tangents(const Vec<Dim>& n) {
  std::array<Vec<Dim>, Dim - 1> t;
  if constexpr (Dim == 2) t[0] = Vec<Dim>(-n[1], n[0]);
  if constexpr (Dim == 3) {
    int least = 0;
    for (int a = 1; a < 3; ++a)
      if (std::abs(n[a]) < std::abs(n[least])) least = a;
    Vec<3> e = Vec<3>::Zero();
    e[least] = 1.0;
    t[0] = (e - e.dot(n) * n).normalized();
    t[1] = n.cross(t[0]);
  }
  return t;
}

// Positions along a span of length L split into whole steps near s: {first, step, count}.
struct Fill {
  double first, step;
  std::int64_t count;
};
Fill exactFill(double lo, double hi, double s) {
  const std::int64_t n = std::max<std::int64_t>(1, std::llround((hi - lo) / s));
  const double step = (hi - lo) / static_cast<double>(n);
  return {lo + 0.5 * step, step, n};
}
// Half-integer multiples of s about `centre`, covering +-reach.
Fill centredFill(double centre, double reach, double s) {
  const std::int64_t n = static_cast<std::int64_t>(std::ceil(reach / s)) + 1;
  return {centre - (static_cast<double>(n) - 0.5) * s, s, 2 * n};
}

struct Grader {
  double s0, within, ratio, smax;
  std::vector<Layer> layers(double end, bool fit) const {
    auto out = gradedLayers(s0, within, ratio, smax, end);
    if (fit) fitLayers(out, within, s0, end);
    return out;
  }
};

template <int Dim, class Keep>
void planeSites(const Reference<Dim>& ref, const Shape<Dim>& shape, const Grader& gr, Keep&& keep) {
  const ShapeConfig& sc = shape.c;
  const Vec<Dim> c = shape.center();
  const double E = shape.extent(), dc = (c - ref.p).dot(ref.n);
  const Vec<Dim> q = c - dc * ref.n; // the centre's projection onto the plane
  const int a = sc.type == ShapeType::Box ? axisOf(ref.n) : -1;
  const auto t = tangents<Dim>(ref.n);
  // The shape's signed distances from the plane: a box's exactly, else its ball's.
  double lo = dc - E, hi = dc + E;
  if (a >= 0) {
    const double u = (sc.min[a] - ref.p[a]) * ref.n[a], w = (sc.max[a] - ref.p[a]) * ref.n[a];
    lo = std::min(u, w), hi = std::max(u, w);
  }
  for (const double side : {1.0, -1.0}) {
    const double end = side > 0 ? hi : -lo, start = std::max(0.0, side > 0 ? lo : -hi);
    if (end <= 0.0) continue;
    const auto layers = gr.layers(end, a >= 0);
    for (const Layer& L : layers) {
      if (L.start + L.thickness <= start) continue;
      const double s = L.thickness, d = side * (L.start + 0.5 * s);
      // Along each tangent: a box's span split into whole steps, else the lattice about q.
      std::array<Fill, 3> fill{Fill{0.0, 1.0, 1}, Fill{0.0, 1.0, 1}, Fill{0.0, 1.0, 1}};
      std::array<int, 3> axis{-1, -1, -1};
      for (int k = 0, b = 0; k < Dim - 1; ++k) {
        if (a >= 0) {
          if (b == a) ++b;
          axis[static_cast<std::size_t>(k)] = b;
          fill[static_cast<std::size_t>(k)] = exactFill(sc.min[b], sc.max[b], s);
          ++b;
        } else {
          fill[static_cast<std::size_t>(k)] = centredFill(0.0, E, s);
        }
      }
      double volume = s;
      for (int k = 0; k < Dim - 1; ++k) volume *= fill[static_cast<std::size_t>(k)].step;
      for (std::int64_t j = 0; j < fill[1].count; ++j)
        for (std::int64_t i = 0; i < fill[0].count; ++i) {
          const double u[2] = {fill[0].first + static_cast<double>(i) * fill[0].step,
                               fill[1].first + static_cast<double>(j) * fill[1].step};
          Vec<Dim> x = q + d * ref.n;
          for (int k = 0; k < Dim - 1; ++k) {
            if (a >= 0)
              x[axis[static_cast<std::size_t>(k)]] = u[k];
            else
              x += u[k] * t[static_cast<std::size_t>(k)];
          }
          keep(x, volume);
        }
    }
  }
}

template <class Keep>
void lineSites(const Reference<3>& ref, const Shape<3>& shape, const Grader& gr, Keep&& keep) {
  const ShapeConfig& sc = shape.c;
  const Vec<3> c = shape.center(), d = ref.n;
  const double E = shape.extent(), along = (c - ref.p).dot(d);
  const double rhoC = (c - ref.p - along * d).norm();
  const auto e = tangents<3>(d);
  // A cylinder on the line: its radius and its ends exactly; a box along the line: its ends.
  bool coaxial = false, ends = false;
  double zlo = 0.0, zhi = 0.0; // the ends' coordinates along the line
  if (sc.type == ShapeType::Cylinder) {
    const Vec<3> axis = toVec<3>(sc.axis).normalized(), base = toVec<3>(sc.base);
    const double b = (base - ref.p).dot(d);
    coaxial =
        std::abs(std::abs(axis.dot(d)) - 1.0) < 1e-12 && (base - ref.p - b * d).norm() < 1e-12 * E;
    zlo = std::min(b, b + axis.dot(d) * sc.length), zhi = std::max(b, b + axis.dot(d) * sc.length);
    ends = coaxial;
  }
  if (const int a = sc.type == ShapeType::Box ? axisOf(d) : -1; a >= 0) {
    const double u = (sc.min[a] - ref.p[a]) * d[a], w = (sc.max[a] - ref.p[a]) * d[a];
    zlo = std::min(u, w), zhi = std::max(u, w), ends = true;
  }
  const double end = coaxial ? sc.radius : rhoC + E,
               start = coaxial ? 0.0 : std::max(0.0, rhoC - E);
  const auto layers = gr.layers(end, coaxial);
  for (std::size_t j = 0; j < layers.size(); ++j) {
    const Layer& L = layers[j];
    if (L.start + L.thickness <= start) continue;
    const double s = L.thickness, rho = L.start + 0.5 * s;
    const Fill f = ends ? exactFill(zlo, zhi, s) : centredFill(along, E, s);
    const double area = 2.0 * kPi * rho * s;
    const std::int64_t n = std::max<std::int64_t>(1, std::llround(area / (s * s)));
    const double volume = area / static_cast<double>(n) * f.step;
    const double phase = 0.5 * static_cast<double>(j & 1);
    for (std::int64_t i = 0; i < f.count; ++i) {
      const Vec<3> axisPoint = ref.p + (f.first + static_cast<double>(i) * f.step) * d;
      for (std::int64_t k = 0; k < n; ++k) {
        const double phi = 2.0 * kPi * (static_cast<double>(k) + phase) / static_cast<double>(n);
        keep(Vec<3>(axisPoint + rho * (std::cos(phi) * e[0] + std::sin(phi) * e[1])), volume);
      }
    }
  }
}

template <int Dim, class Keep>
void pointSites(const Reference<Dim>& ref, const Shape<Dim>& shape, const Grader& gr, bool rz,
                Keep&& keep) {
  const ShapeConfig& sc = shape.c;
  const Vec<Dim> c = shape.center();
  const double E = shape.extent(), dc = (c - ref.p).norm();
  // A ball or annulus about the point: its outer radius exactly.
  const bool concentric =
      (sc.type == ShapeType::Sphere || sc.type == ShapeType::Ring) && dc < 1e-12 * E;
  const double end = concentric ? E : dc + E, start = concentric ? 0.0 : std::max(0.0, dc - E);
  const auto layers = gr.layers(end, concentric);
  // rz about a point on the axis: half rings, r > 0 (the other half is the same rings).
  const bool half = rz && ref.p[0] == 0.0;
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  for (std::size_t j = 0; j < layers.size(); ++j) {
    const Layer& L = layers[j];
    if (L.start + L.thickness <= start) continue;
    const double s = L.thickness, rho = L.start + 0.5 * s;
    if constexpr (Dim == 2) {
      const double arc = half ? kPi : 2.0 * kPi, area = arc * rho * s;
      const std::int64_t n = std::max<std::int64_t>(1, std::llround(area / (s * s)));
      const double phase = half ? 0.5 : 0.5 * static_cast<double>(j & 1);
      for (std::int64_t k = 0; k < n; ++k) {
        const double phi = (half ? -0.5 * kPi : 0.0) +
                           arc * (static_cast<double>(k) + phase) / static_cast<double>(n);
        keep(Vec<2>(ref.p + rho * Vec<2>(std::cos(phi), std::sin(phi))),
             area / static_cast<double>(n));
      }
    } else if constexpr (Dim == 3) {
      // A shell's sites on a Fibonacci spiral (equal areas), turned by the golden angle from
      // one shell to the next.
      const double volume = 4.0 * kPi * rho * rho * s + kPi * s * s * s / 3.0;
      const std::int64_t n = std::max<std::int64_t>(1, std::llround(volume / (s * s * s)));
      for (std::int64_t k = 0; k < n; ++k) {
        const double zk = 1.0 - (2.0 * static_cast<double>(k) + 1.0) / static_cast<double>(n);
        const double rk = std::sqrt(std::max(0.0, 1.0 - zk * zk));
        const double phi = golden * static_cast<double>(k + static_cast<std::int64_t>(j));
        keep(Vec<3>(ref.p + rho * Vec<3>(rk * std::cos(phi), rk * std::sin(phi), zk)),
             volume / static_cast<double>(n));
      }
    }
  }
}

template <int Dim, class Keep>
void forEachGradedSite(const Deck& deck, const BodyConfig& body, Keep&& keep) {
  const GradingConfig& g = *body.grading;
  const Grader gr{body.spacing / deck.run.resolution, g.within, g.ratio,
                  g.max_spacing / deck.run.resolution};
  const Shape<Dim> shape{body.shape};
  const Reference<Dim> ref = referenceOf<Dim>(g);
  using K = typename Reference<Dim>::Kind;
  if (ref.kind == K::Plane) return planeSites<Dim>(ref, shape, gr, keep);
  if constexpr (Dim == 3)
    if (ref.kind == K::Line) return lineSites(ref, shape, gr, keep);
  if constexpr (Dim >= 2) pointSites<Dim>(ref, shape, gr, deck.run.geometry == Geometry::RZ, keep);
}

} // namespace

std::vector<Layer> gradedLayers(double s0, double within, double ratio, double smax, double end) {
  std::vector<Layer> out;
  forEachLayer(s0, within, ratio, smax, end, [&](const Layer& L) { out.push_back(L); });
  return out;
}

void fitLayers(std::vector<Layer>& layers, double within, double s0, double end) {
  if (layers.empty()) return;
  std::size_t g = 0;
  while (g < layers.size() && fine(layers[g].start, s0, within)) ++g;
  if (g == layers.size()) g = 0; // all fine: whole layers of a spacing near s0, as a uniform box
  const std::size_t J = layers.size() - 1;
  const double from = layers[g].start;
  const double keepAll = (end - from) / (layers[J].start + layers[J].thickness - from);
  const double dropLast = J > g ? (end - from) / (layers[J].start - from) : 0.0;
  const bool drop = J > g && std::abs(std::log(dropLast)) < std::abs(std::log(keepAll));
  if (drop) layers.pop_back();
  const double f = drop ? dropLast : keepAll;
  double b = from;
  for (std::size_t j = g; j < layers.size(); ++j) {
    layers[j].start = b;
    layers[j].thickness *= f;
    b += layers[j].thickness;
  }
}

template <int Dim> std::vector<Site<Dim>> gradedSites(const Deck& deck, const BodyConfig& body) {
  const Shape<Dim> shape{body.shape};
  const bool rz = deck.run.geometry == Geometry::RZ;
  std::vector<Site<Dim>> out;
  forEachGradedSite<Dim>(deck, body, [&](const Vec<Dim>& x, double volume) {
    if (shape.contains(x) && (!rz || x[0] > 0.0)) out.push_back({x, volume});
  });
  return out;
}

namespace {
// The distance from the reference to the far side of the body's ball (the last layer's end).
template <int Dim> double farEnd(const Reference<Dim>& ref, const Shape<Dim>& shape) {
  using K = typename Reference<Dim>::Kind;
  const Vec<Dim> rel = shape.center() - ref.p;
  const double dc = ref.kind == K::Plane  ? std::abs(rel.dot(ref.n))
                    : ref.kind == K::Line ? (rel - rel.dot(ref.n) * ref.n).norm()
                                          : rel.norm();
  return dc + shape.extent();
}

} // namespace

template <int Dim> void checkGradedLayers(const Deck& deck, const BodyConfig& body) {
  const GradingConfig& g = *body.grading;
  const double s0 = body.spacing / deck.run.resolution, smax = g.max_spacing / deck.run.resolution;
  const double end = farEnd(referenceOf<Dim>(g), Shape<Dim>{body.shape});
  // At most within/s0 fine layers, log(smax/s0)/log(ratio) growing ones, then end/smax.
  const double growing = g.ratio > 1.0 ? std::log(smax / s0) / std::log(g.ratio) : 0.0;
  const double layers = std::min(g.within, end) / s0 + growing + end / smax;
  if (!(layers < 1e8))
    throw DeckError(g.where, fmt::format("body '{}': its grading lays ~{:.3g} layers out to the "
                                         "far side of the body, {:g} m from the reference "
                                         "(at most 1e8: a reference far from the body, or a "
                                         "max_spacing far below that distance?)",
                                         body.name, layers, end));
}

template <int Dim> double gradedSiteEstimate(const Deck& deck, const BodyConfig& body) {
  // Each layer's sites over the shape's ball: a plane's slab holds (2E/s + 2)^(Dim-1) of them
  // on a side, a cylinder (2 pi rho/s + 1)(2E/s + 2), a ring 2 pi rho/s + 1, a shell
  // 4 pi rho^2/s^2 + 1. Counted without making them.
  const GradingConfig& g = *body.grading;
  const Grader gr{body.spacing / deck.run.resolution, g.within, g.ratio,
                  g.max_spacing / deck.run.resolution};
  const Shape<Dim> shape{body.shape};
  const Reference<Dim> ref = referenceOf<Dim>(g);
  const double E = shape.extent(), dc = farEnd(ref, shape) - E;
  using K = typename Reference<Dim>::Kind;
  double sites = 0.0;
  forEachLayer(gr.s0, gr.within, gr.ratio, gr.smax, dc + E, [&](const Layer& L) {
    if (L.start + L.thickness <= dc - E) return;
    const double s = L.thickness, rho = L.start + 0.5 * s, across = 2.0 * E / s + 2.0;
    if (ref.kind == K::Plane)
      sites += 2.0 * std::pow(across, Dim - 1);
    else if (ref.kind == K::Line)
      sites += (2.0 * kPi * rho / s + 1.0) * across;
    else
      sites += Dim == 2 ? 2.0 * kPi * rho / s + 1.0 : 4.0 * kPi * rho * rho / (s * s) + 1.0;
  });
  return sites;
}

#define SPALL_INSTANTIATE(D)                                                                       \
  template std::vector<Site<D>> gradedSites<D>(const Deck&, const BodyConfig&);                    \
  template double gradedSiteEstimate<D>(const Deck&, const BodyConfig&);                           \
  template void checkGradedLayers<D>(const Deck&, const BodyConfig&);
SPALL_INSTANTIATE(1)
SPALL_INSTANTIATE(2)
SPALL_INSTANTIATE(3)
#undef SPALL_INSTANTIATE

} // namespace spall::app::sites
