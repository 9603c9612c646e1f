#include "spall/app/BodyGenerator.hpp"

#include "BodyShape.hpp"
#include "CloudSites.hpp"
#include "GradedSites.hpp"

#include "spall/app/SystemInfo.hpp"
#include "spall/core/Random.hpp"
#include "spall/kernels/Kernels.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <numbers>
#include <optional>
#include <span>

namespace spall::app {

namespace {

using sites::Shape;
using sites::Site;
using sites::toVec;

// A graded body's or a file's particles each have a spacing of their own: their cell's size.
bool ownSpacing(const BodyConfig& body) {
  return body.grading || body.shape.type == ShapeType::Particles;
}

// Lattice sites about the origin with nearest spacing dx: cubic, or hexagonal (triangular in 2D,
// hexagonal close packing in 3D). Returns the volume per site.
template <int Dim, class F>
double forEachLatticeSite(bool hexagonal, double dx, double radius, F&& visit) {
  const int n = static_cast<int>(std::ceil(radius / dx)) + 2;
  if (!hexagonal || Dim == 1) {
    // Sites at half-integer offsets so a symmetric shape gets a symmetric lattice.
    const int nz = Dim == 3 ? n : 0, ny = Dim >= 2 ? n : 0;
    for (int k = -nz; k <= nz; ++k)
      for (int j = -ny; j <= ny; ++j)
        for (int i = -n; i <= n; ++i) {
          Vec<Dim> x;
          x[0] = (i + 0.5) * dx;
          if constexpr (Dim >= 2) x[1] = (j + 0.5) * dx;
          if constexpr (Dim == 3) x[2] = (k + 0.5) * dx;
          visit(x);
        }
    return std::pow(dx, Dim);
  }
  const double dy = dx * std::sqrt(3.0) / 2.0;
  const double dz = dx * std::sqrt(2.0 / 3.0);
  const int ny = static_cast<int>(std::ceil(radius / dy)) + 2;
  const int nz = Dim == 3 ? static_cast<int>(std::ceil(radius / dz)) + 2 : 0;
  for (int k = -nz; k <= nz; ++k)
    for (int j = -ny; j <= ny; ++j)
      for (int i = -n; i <= n; ++i) {
        Vec<Dim> x;
        const bool layerB = (k & 1) != 0;
        x[0] = (i + 0.5 * (j & 1) + (layerB ? 0.5 : 0.0)) * dx;
        x[1] = j * dy + (layerB ? dx / (2.0 * std::sqrt(3.0)) : 0.0);
        if constexpr (Dim == 3) x[2] = k * dz;
        visit(x);
      }
  return Dim == 2 ? dx * dy : dx * dx * dx / std::sqrt(2.0);
}

// Contact groups by body. Merged (contact "auto"): two bodies whose particles come within 1.5
// times the larger of their spacings of each other at t = 0 touch, and touching bodies are one
// group (transitively): a bonded assembly (or a striker set against its target) stays welded,
// bodies that meet later meet frictionless. (A flyer set against its target stays welded too:
// started in contact, the frictionless pair term bounces Lam's copper striker back at 16 of its
// 20 m/s, where the water hammer leaves it at rest; from a 3-spacing gap it ends at -0.3 m/s.)
// Otherwise every body is its own group. For each pair of bodies whose boxes come that close, the
// finer body's particles near the other are looked up in a grid of the coarser body's (cell = that
// reach), so a lookup sees ~100 candidates whatever the spacing ratio.
template <int Dim>
std::vector<std::int32_t>
contactGroups(std::span<const Vec<Dim>> x, std::span<const std::int32_t> body,
              std::span<const double> local, std::size_t bodies, bool merge) {
  // A body's spacing here is its coarsest (a graded body's); a pair touches within 1.5 times
  // the larger of its two particles' own spacings.
  std::vector<double> spacing(bodies, 0.0);
  for (std::size_t i = 0; i < x.size(); ++i) {
    const auto b = static_cast<std::size_t>(body[i]);
    spacing[b] = std::max(spacing[b], local[i]);
  }
  std::vector<std::int32_t> root(bodies);
  for (std::size_t b = 0; b < bodies; ++b) root[b] = static_cast<std::int32_t>(b);
  if (!merge || bodies < 2) return root;
  const auto find = [&](std::int32_t b) {
    while (root[static_cast<std::size_t>(b)] != b) b = root[static_cast<std::size_t>(b)];
    return b;
  };
  std::vector<std::vector<std::size_t>> members(bodies);
  std::vector<Vec<Dim>> lo(bodies, Vec<Dim>::Constant(std::numeric_limits<double>::infinity())),
      hi(bodies, Vec<Dim>::Constant(-std::numeric_limits<double>::infinity()));
  for (std::size_t i = 0; i < x.size(); ++i) {
    const auto b = static_cast<std::size_t>(body[i]);
    members[b].push_back(i);
    lo[b] = lo[b].cwiseMin(x[i]);
    hi[b] = hi[b].cwiseMax(x[i]);
  }
  using Key = std::array<std::int64_t, 3>;
  for (std::size_t a = 0; a < bodies; ++a)
    for (std::size_t b = a + 1; b < bodies; ++b) {
      if (find(static_cast<std::int32_t>(a)) == find(static_cast<std::int32_t>(b))) continue;
      const double reach = 1.5 * std::max(spacing[a], spacing[b]);
      // The overlap of the two boxes grown by the reach; nothing to do when it is empty.
      const Vec<Dim> olo = lo[a].cwiseMax(lo[b]) - Vec<Dim>::Constant(reach);
      const Vec<Dim> ohi = hi[a].cwiseMin(hi[b]) + Vec<Dim>::Constant(reach);
      if ((olo.array() > ohi.array()).any()) continue;
      const std::size_t fine = spacing[a] <= spacing[b] ? a : b, coarse = fine == a ? b : a;
      const auto inside = [&](const Vec<Dim>& p) {
        return (p.array() >= olo.array()).all() && (p.array() <= ohi.array()).all();
      };
      const auto keyOf = [&](const Vec<Dim>& p) {
        Key k{0, 0, 0};
        for (int d = 0; d < Dim; ++d)
          k[static_cast<std::size_t>(d)] =
              static_cast<std::int64_t>(std::floor((p[d] - olo[d]) / reach));
        return k;
      };
      std::vector<std::pair<Key, std::size_t>> grid;
      for (std::size_t i : members[coarse])
        if (inside(x[i])) grid.emplace_back(keyOf(x[i]), i);
      std::sort(grid.begin(), grid.end());
      bool touching = false;
      const std::int64_t r1 = 1, r2 = Dim >= 2 ? 1 : 0, r3 = Dim == 3 ? 1 : 0;
      for (std::size_t i : members[fine]) {
        if (touching) break;
        if (!inside(x[i])) continue;
        const Key k = keyOf(x[i]);
        for (std::int64_t dz = -r3; dz <= r3 && !touching; ++dz)
          for (std::int64_t dy = -r2; dy <= r2 && !touching; ++dy)
            for (std::int64_t dx = -r1; dx <= r1 && !touching; ++dx) {
              const Key c{k[0] + dx, k[1] + dy, k[2] + dz};
              auto it =
                  std::lower_bound(grid.begin(), grid.end(), std::make_pair(c, std::size_t{0}));
              for (; it != grid.end() && it->first == c; ++it)
                if (const double r = 1.5 * std::max(local[i], local[it->second]);
                    (x[i] - x[it->second]).squaredNorm() < r * r)
                  touching = true;
            }
      }
      if (touching) {
        const std::int32_t ra = find(static_cast<std::int32_t>(a)),
                           rb = find(static_cast<std::int32_t>(b));
        root[static_cast<std::size_t>(std::max(ra, rb))] = std::min(ra, rb);
      }
    }
  for (std::size_t b = 0; b < bodies; ++b) root[b] = find(static_cast<std::int32_t>(b));
  return root;
}

// The sites of a box's exact lattice (n_k = round(L_k/dx) cells of L_k/n_k from its min corner)
// that lie in `shape`, over the shape's bounding box; rz: r > 0.
template <int Dim>
void anchoredSites(const Shape<Dim>& shape, const Vec<Dim>& lo, const Vec<Dim>& hi, double dx,
                   bool rz, std::vector<Site<Dim>>& out) {
  const auto [blo, bhi] = shape.bounds();
  Vec<Dim> step;
  std::int64_t first[3] = {0, 0, 0}, last[3] = {0, 0, 0};
  double volume = 1.0;
  for (int d = 0; d < Dim; ++d) {
    const double n = std::max(1.0, std::round((hi[d] - lo[d]) / dx));
    step[d] = (hi[d] - lo[d]) / n;
    volume *= step[d];
    first[d] = static_cast<std::int64_t>(std::floor((blo[d] - lo[d]) / step[d])) - 1;
    last[d] = static_cast<std::int64_t>(std::ceil((bhi[d] - lo[d]) / step[d])) + 1;
  }
  for (std::int64_t k = first[2]; k <= last[2]; ++k)
    for (std::int64_t j = first[1]; j <= last[1]; ++j)
      for (std::int64_t i = first[0]; i <= last[0]; ++i) {
        const std::int64_t idx[3] = {i, j, k};
        Vec<Dim> x;
        for (int d = 0; d < Dim; ++d) x[d] = lo[d] + (static_cast<double>(idx[d]) + 0.5) * step[d];
        if (shape.contains(x) && (!rz || x[0] > 0.0)) out.push_back({x, volume});
      }
}

// The lattice sites of a body's shape and the volume each stands for (run.resolution applied;
// rz: the half-plane's sites, r > 0).
template <int Dim> std::vector<Site<Dim>> latticeSites(const Deck& deck, const BodyConfig& body) {
  if (body.grading) return sites::gradedSites<Dim>(deck, body);
  const Shape<Dim> shape{body.shape};
  if (body.shape.type == ShapeType::Particles) return sites::cloudSites<Dim>(*body.shape.cloud);
  const double dx = body.spacing / deck.run.resolution;
  const bool rz = deck.run.geometry == Geometry::RZ;
  Tensor<Dim> A = Tensor<Dim>::Identity();
  if (body.lattice_transform)
    for (int r = 0; r < Dim; ++r)
      for (int c = 0; c < Dim; ++c) A(r, c) = (*body.lattice_transform)[r][c];
  const double detA = std::abs(A.determinant());
  std::vector<Site<Dim>> out;
  if (body.shape.type == ShapeType::Box && body.lattice == Lattice::Cubic &&
      !body.lattice_transform) {
    // Fill the box exactly: n_k = round(L_k/dx) cells, spacing adjusted to L_k/n_k.
    Vec<Dim> lo = toVec<Dim>(body.shape.min), hi = toVec<Dim>(body.shape.max), step;
    std::int64_t n[3] = {1, 1, 1};
    double volume = 1.0;
    for (int d = 0; d < Dim; ++d) {
      // Thinner than half a spacing: no particles (as for every other shape).
      n[d] = (hi[d] - lo[d]) / dx < 0.5 ? 0 : std::llround((hi[d] - lo[d]) / dx);
      step[d] = (hi[d] - lo[d]) / static_cast<double>(n[d]);
      volume *= step[d];
    }
    for (std::int64_t k = 0; k < n[2]; ++k)
      for (std::int64_t j = 0; j < n[1]; ++j)
        for (std::int64_t i = 0; i < n[0]; ++i) {
          Vec<Dim> x;
          x[0] = lo[0] + (static_cast<double>(i) + 0.5) * step[0];
          if constexpr (Dim >= 2) x[1] = lo[1] + (static_cast<double>(j) + 0.5) * step[1];
          if constexpr (Dim == 3) x[2] = lo[2] + (static_cast<double>(k) + 0.5) * step[2];
          out.push_back({x, volume});
        }
  } else if (const ShapeConfig& box = shape.primary(); box.type == ShapeType::Box &&
                                                       body.lattice == Lattice::Cubic &&
                                                       !body.lattice_transform) {
    // A union or difference built on a box (a rod and its nose, a plate with a hole): the box's
    // exact lattice, continued over the whole shape.
    anchoredSites<Dim>(shape, toVec<Dim>(box.min), toVec<Dim>(box.max), dx, rz, out);
  } else {
    // The lattice is mapped by A about the shape centre, so cover the preimage of the shape.
    Vec<Dim> c = shape.center();
    // A cylinder (or a cone, an ogive) along a lattice axis whose length is an odd number of
    // spacings: the sites' half-integer offsets about the centre would put layers on both end
    // planes (one kept, one not, by rounding); half a spacing along the axis puts them half a
    // spacing inside, as for an even count (a Taylor bar then starts in contact with its wall
    // at any resolution; a cone does not gain a layer on its base).
    if (const ShapeType t = shape.primary().type;
        (t == ShapeType::Cylinder || t == ShapeType::Cone || t == ShapeType::Ogive) &&
        body.lattice == Lattice::Cubic && !body.lattice_transform) {
      const ShapeConfig& cyl = shape.primary();
      const Vec<Dim> axis = toVec<Dim>(cyl.axis).normalized();
      const double layers = cyl.length / dx, nearest = std::round(layers);
      const bool odd = std::abs(layers - nearest) < 1e-6 * layers && std::fmod(nearest, 2.0) == 1.0;
      const bool alongLatticeAxis = std::abs(axis.cwiseAbs().maxCoeff() - 1.0) < 1e-12;
      if (odd && alongLatticeAxis) c += (0.5 * dx) * axis;
    }
    // |A^-1|_F bounds the operator norm of A^-1 from above: a conservative cover.
    const double radius = shape.extent() * A.inverse().norm();
    const double volume = forEachLatticeSite<Dim>(body.lattice == Lattice::Hexagonal, dx, radius,
                                                  [&](const Vec<Dim>& site) {
                                                    const Vec<Dim> x = c + A * site;
                                                    if (shape.contains(x) && (!rz || x[0] > 0.0))
                                                      out.push_back({x, 0.0});
                                                  });
    for (auto& s : out) s.volume = volume * detA;
  }
  return out;
}

// Body b's particles in rows [row, row + sites.size()), ids from firstId (the t = 0 numbering):
// position (with jitter drawn from the seed and the id), velocity, mass, density, energy, h,
// material and body; returns the body's mass.
template <int Dim>
double fillBody(const Deck& deck, const std::vector<materials::Material>& materials, std::size_t b,
                std::span<const Site<Dim>> sites, std::size_t row, ParticleId firstId,
                ParticleStore& store, const ParticleFields<Dim>& f) {
  const bool rz = deck.run.geometry == Geometry::RZ;
  auto id = store[f.id];
  auto x = store[f.x];
  auto v = store[f.v];
  auto m = store[f.m];
  auto rho = store[f.rho];
  auto e = store[f.e];
  auto h = store[f.h];
  auto mat = store[f.material];
  auto bod = store[f.body];
  const BodyConfig& body = deck.bodies[b];
  const MaterialConfig& material = deck.materials[static_cast<std::size_t>(body.material_index)];
  const materials::Material& model = materials[static_cast<std::size_t>(body.material_index)];
  // A porous material's density is its matrix's: the body starts at distension alpha0.
  const double alpha0 = model.porosity ? model.porosity->alpha0 : 1.0;
  double rho0 = body.initial_density.value_or(material.density / alpha0);
  double e0 = body.initial_specific_energy.value_or(0.0);
  if (body.initial_pressure && model.cap) {
    // A cap material's pressure is its elastic strain's: the start density carries it.
    if (body.initial_density)
      throw DeckError(body.where, fmt::format("body '{}': initial_pressure and "
                                              "initial_density both set the density of a "
                                              "'cap' material; give one",
                                              body.name));
    const auto rho = model.cap->densityForPressure(*body.initial_pressure);
    if (!rho)
      throw DeckError(body.where,
                      fmt::format("body '{}': initial_pressure {:g} Pa puts material '{}' "
                                  "outside its yield surface (the cap starts at I1 = "
                                  "crush_p0; the tensile vertex is peak_i1)",
                                  body.name, *body.initial_pressure, material.name));
    rho0 = *rho;
  } else if (body.initial_pressure) {
    // With elastic distension the pressure has closed pores already: alpha = alpha0 + a P0
    // (materials/Porosity.hpp, Eq. 2), which the first evaluation finds again.
    const double P0 = *body.initial_pressure;
    const double alpha = model.porosity && model.porosity->elastic()
                             ? alpha0 + model.porosity->elasticSlope(alpha0) * P0
                             : alpha0;
    const auto ep = std::visit(
        [&](const auto& eos) { // P = P_eos(alpha rho, e) / alpha
          return eos.energyForPressure(alpha * rho0, alpha * P0);
        },
        model.eos);
    if (!ep) {
      throw DeckError(body.where, fmt::format("body '{}': initial_pressure cannot be set with the "
                                              "'{}' EOS of material '{}' (its pressure does not "
                                              "depend on the internal energy); use initial_density",
                                              body.name, eosTypeName(material.eos), material.name));
    }
    e0 = *ep;
  }
  const Vec<Dim> v0 = toVec<Dim>(body.velocity);
  const double dx = body.spacing / deck.run.resolution;
  double mass = 0.0;
  std::size_t k = row;
  for (const auto& s : sites) {
    const ParticleId idk = firstId + (k - row);
    id[k] = idk;
    Vec<Dim> xi = s.x;
    if (body.jitter > 0.0) {
      // A graded body's offsets follow its local spacing.
      const double scale = ownSpacing(body) ? std::pow(s.volume, 1.0 / Dim) : dx;
      for (int d = 0; d < Dim; ++d)
        xi[d] +=
            body.jitter * scale * hashedUniform(deck.run.seed, idk, static_cast<std::uint64_t>(d));
    }
    if (rz) xi[0] = std::abs(xi[0]); // jitter never takes a ring across the axis
    x[k] = xi;
    v[k] = v0;
    if (body.radial_velocity) {
      const Vec<Dim> r = xi - toVec<Dim>(body.radial_velocity->center);
      const double rn = r.norm();
      if (rn > 0.0) v[k] += body.radial_velocity->speed / rn * r;
    }
    if (body.cantilever_velocity)
      v[k][1] += cantileverModeVelocity(*body.cantilever_velocity, xi[0]);
    if (body.linear_velocity) { // v += G (x - c): a homogeneous stretch, shear or spin
      const Vec<Dim> r = xi - toVec<Dim>(body.linear_velocity->center);
      for (int a = 0; a < Dim; ++a)
        for (int c = 0; c < Dim; ++c)
          v[k][a] += body.linear_velocity
                         ->gradient[static_cast<std::size_t>(a)][static_cast<std::size_t>(c)] *
                     r[c];
    }
    if (const auto& sw = body.sine_velocity)
      v[k] += std::sin((xi - toVec<Dim>(sw->origin)).dot(toVec<Dim>(sw->wavevector))) *
              toVec<Dim>(sw->amplitude);
    m[k] = rho0 * s.volume * (rz ? 2.0 * std::numbers::pi * xi[0] : 1.0);
    rho[k] = rho0;
    e[k] = e0;
    // Initial h from the lattice: n_h sites per smoothing scale.
    h[k] = deck.solver.nodes_per_h * std::pow(s.volume, 1.0 / Dim);
    mat[k] = body.material_index;
    bod[k] = static_cast<std::int32_t>(b);
    mass += m[k];
    ++k;
  }
  return mass;
}

} // namespace

template <int Dim>
std::vector<BodySummary> generateBodies(const Deck& deck,
                                        const std::vector<materials::Material>& materials,
                                        ParticleStore& store, const ParticleFields<Dim>& f) {
  std::vector<BodySummary> summary;
  std::vector<std::vector<Site<Dim>>> sites(deck.bodies.size());
  std::size_t total = 0;
  // Every rank makes every particle once: what the lattices visit must fit in this rank's share
  // of the memory, or the deck asks for more than the machine has (a misplaced exponent).
  const double available = static_cast<double>(availableMemoryBytes());
  // Per particle: its site, its fields and its neighbor indices at the target n_h.
  const double neighbors =
      std::pow(4.0 * deck.solver.nodes_per_h, Dim) * (Dim == 3   ? std::numbers::pi / 6.0
                                                      : Dim == 2 ? std::numbers::pi / 4.0
                                                                 : 1.0);
  const double perSite = static_cast<double>(sizeof(Site<Dim>)) +
                         1.1 * static_cast<double>(store.bytesPerParticle()) + 4.0 * neighbors;
  double made = 0.0;
  for (std::size_t b = 0; b < deck.bodies.size(); ++b) {
    const BodyConfig& body = deck.bodies[b];
    const Shape<Dim> shape{body.shape};
    const double dx = body.spacing / deck.run.resolution;
    Tensor<Dim> A = Tensor<Dim>::Identity();
    if (body.lattice_transform)
      for (int r = 0; r < Dim; ++r)
        for (int c = 0; c < Dim; ++c) A(r, c) = (*body.lattice_transform)[r][c];
    const double detA = std::abs(A.determinant());
    // Particles (the shape's measure over a site's, hexagonal lattices being denser by at most
    // sqrt 2) and the lattice sites visited to find them (a cube about the shape).
    const bool cloud = body.shape.type == ShapeType::Particles;
    const double across = cloud ? 0.0 : 2.0 * shape.extent() * A.inverse().norm() / dx + 4.0;
    if (body.grading && across < 1e8) sites::checkGradedLayers<Dim>(deck, body);
    made += cloud          ? static_cast<double>(body.shape.cloud->size())
            : body.grading ? sites::gradedSiteEstimate<Dim>(deck, body)
                           : 1.5 * shape.measure() / detA / std::pow(dx, Dim);
    if (!(made * perSite < available))
      throw DeckError(
          body.where,
          fmt::format("body '{}': a spacing of {:g} m (after run.resolution) makes "
                      "~{:.3g} particles with the bodies before it, ~{:.3g} GB on every "
                      "rank while they are made; {:.3g} GB are available",
                      body.name, dx, made, made * perSite / 1e9, available / 1e9));
    if (!(across < 1e8 && (body.grading || std::pow(across, Dim) < 1e12)))
      throw DeckError(body.where,
                      fmt::format("body '{}': a spacing of {:g} m (after run.resolution) is "
                                  "{:.3g} times smaller than the shape",
                                  body.name, dx, across));
    auto& out = sites[b];
    out = latticeSites<Dim>(deck, body);
    if (out.empty()) {
      throw DeckError(body.where,
                      fmt::format("body '{}' has no particles: its shape is smaller than "
                                  "the spacing {:g} m (after run.resolution)",
                                  body.name, dx));
    }
    // Overlap: a particle of this body inside an earlier body's shape. Not for a body that
    // joins later (a jet's segments enter where the one before them was): where the others are
    // then is for the run to know.
    if (!body.allow_overlap && !(body.insert_time > 0.0)) {
      for (std::size_t o = 0; o < b; ++o) {
        if (deck.bodies[o].insert_time > 0.0) continue;
        const ShapeConfig& oc = deck.bodies[o].shape;
        const Shape<Dim> other{oc};
        std::optional<sites::CloudRegion<Dim>> cells;
        if (oc.type == ShapeType::Particles) cells.emplace(*oc.cloud);
        for (const auto& s : out) {
          if (cells ? cells->contains(s.x) : other.contains(s.x)) {
            throw DeckError(body.where,
                            fmt::format("body '{}' overlaps body '{}' (a particle at distance "
                                        "{:g} m from the origin lies inside both); set "
                                        "allow_overlap = true in body '{}' if this is intended",
                                        body.name, deck.bodies[o].name, s.x.norm(), body.name));
          }
        }
      }
    }
    summary.push_back({body.name, out.size(), 0.0, dx});
    total += out.size();
  }

  store.resizeLocal(total);
  std::size_t k = 0;
  for (std::size_t b = 0; b < deck.bodies.size(); ++b) {
    summary[b].mass = fillBody<Dim>(deck, materials, b, sites[b], k, k, store, f);
    k += sites[b].size();
  }
  // Bodies that join the run later (insert_time) were made for their count and mass; they
  // leave the store until their time (insertBody).
  std::vector<std::uint32_t> present;
  present.reserve(total);
  for (std::size_t i = 0; i < total; ++i)
    if (!(deck.bodies[static_cast<std::size_t>(store[f.body][i])].insert_time > 0.0))
      present.push_back(static_cast<std::uint32_t>(i));
  if (present.size() < total) store.keepLocal(present);
  const auto x = store[f.x];
  const auto bod = store[f.body];
  const std::size_t kept = store.localCount();
  if (f.contactGroup.valid()) {
    // Each particle's own spacing: its body's, or a graded body's local one.
    std::vector<double> local;
    local.reserve(kept);
    for (std::size_t b = 0; b < deck.bodies.size(); ++b) {
      if (deck.bodies[b].insert_time > 0.0) continue;
      for (const auto& site : sites[b])
        local.push_back(ownSpacing(deck.bodies[b]) ? std::pow(site.volume, 1.0 / Dim)
                                                   : summary[b].spacing);
    }
    const auto group = contactGroups<Dim>(x.first(kept), bod.first(kept), local, summary.size(),
                                          deck.solver.contact == Contact::Auto);
    auto g = store[f.contactGroup];
    for (std::size_t i = 0; i < kept; ++i) g[i] = group[static_cast<std::size_t>(bod[i])];
  }
  return summary;
}

template <int Dim>
BodySummary insertBody(const Deck& deck, const std::vector<materials::Material>& materials,
                       std::size_t b, ParticleId firstId, ParticleStore& store,
                       const ParticleFields<Dim>& f) {
  const BodyConfig& body = deck.bodies[b];
  const std::vector<Site<Dim>> sites = latticeSites<Dim>(deck, body);
  const std::size_t row = store.appendLocal(sites.size());
  store.zeroRows(row, sites.size());
  const double mass = fillBody<Dim>(deck, materials, b, sites, row, firstId, store, f);
  // Its own contact group: frictionless against everything, as bodies that did not touch at
  // t = 0 are.
  if (f.contactGroup.valid())
    for (std::size_t i = row; i < store.localCount(); ++i)
      store[f.contactGroup][i] = static_cast<std::int32_t>(b);
  return {body.name, sites.size(), mass, body.spacing / deck.run.resolution};
}

std::string gradedText(const Deck& deck, std::size_t body) {
  const auto& g = deck.bodies.at(body).grading;
  return g ? fmt::format(" graded up to {:.4g} m", g->max_spacing / deck.run.resolution) : "";
}

// The first bending mode of a clamped-free beam (Euler-Bernoulli; the initial condition of Gray,
// Monaghan & Swift 2001's oscillating plate): phi(xi) = cosh k xi - cos k xi - s (sinh k xi -
// sin k xi), s = (cosh kL + cos kL)/(sinh kL + sin kL), with kL = 1.8751040687 the first root of
// cos kL cosh kL = -1; scaled so that the free end moves at tip_speed.
double cantileverModeVelocity(const CantileverVelocityConfig& c, double x) {
  constexpr double kL = 1.8751040687119611;
  const double xi = std::clamp(x - c.root[0], 0.0, c.length);
  const double k = kL / c.length;
  const double s = (std::cosh(kL) + std::cos(kL)) / (std::sinh(kL) + std::sin(kL));
  const auto phi = [&](double z) {
    return std::cosh(k * z) - std::cos(k * z) - s * (std::sinh(k * z) - std::sin(k * z));
  };
  return c.tip_speed * phi(xi) / phi(c.length);
}

template <int Dim>
void applyEnergySources(const Deck& deck, ParticleStore& store, const ParticleFields<Dim>& f) {
  const auto x = store[f.x];
  const auto m = store[f.m];
  const auto e = store[f.e];
  const std::size_t n = store.localCount();
  using W = kernels::Kernel<kernels::CubicSpline<Dim>, Dim>;
  for (const auto& src : deck.energy_sources) {
    const Vec<Dim> c = toVec<Dim>(src.center);
    if (src.radius <= 0.0) {
      std::size_t best = 0;
      double bestD = std::numeric_limits<double>::infinity();
      for (std::size_t i = 0; i < n; ++i) {
        const double d = (x[i] - c).squaredNorm();
        if (d < bestD) bestD = d, best = i; // lowest index (= id) wins a tie
      }
      e[best] += src.energy / m[best];
      continue;
    }
    // Specific energy proportional to a cubic-spline weight of support `radius`.
    const double hs = 0.5 * src.radius;
    double norm = 0.0;
    for (std::size_t i = 0; i < n; ++i) norm += m[i] * W::W((x[i] - c).norm(), hs);
    if (norm <= 0.0) {
      throw DeckError(src.where, "energy_source: no particle lies within its radius");
    }
    for (std::size_t i = 0; i < n; ++i) e[i] += src.energy * W::W((x[i] - c).norm(), hs) / norm;
  }
}

#define SPALL_INSTANTIATE(D)                                                                       \
  template std::vector<BodySummary> generateBodies<D>(const Deck&,                                 \
                                                      const std::vector<materials::Material>&,     \
                                                      ParticleStore&, const ParticleFields<D>&);   \
  template void applyEnergySources<D>(const Deck&, ParticleStore&, const ParticleFields<D>&);      \
  template BodySummary insertBody<D>(const Deck&, const std::vector<materials::Material>&,         \
                                     std::size_t, ParticleId, ParticleStore&,                      \
                                     const ParticleFields<D>&);
SPALL_INSTANTIATE(1)
SPALL_INSTANTIATE(2)
SPALL_INSTANTIATE(3)
#undef SPALL_INSTANTIATE

} // namespace spall::app
