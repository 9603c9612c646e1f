// Deck reading: parse (toml++), apply --set overrides, then validate into the typed config. Each
// check reports the position of the value it rejects (docs/reference.md, "Bad input").
#include "spall/io/Deck.hpp"

#include "DeckDetail.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

namespace spall {

namespace {

using io::deck_detail::Context;
using io::deck_detail::Names;
using io::deck_detail::TableReader;
namespace dd = io::deck_detail;

std::string readText(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw DeckError({path, 0, 0}, "cannot read the deck: no such file");
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in) throw DeckError({path, 0, 0}, "cannot read the deck");
  return text.str();
}

double determinant(const std::vector<std::vector<double>>& m) {
  switch (m.size()) {
  case 1:
    return m[0][0];
  case 2:
    return m[0][0] * m[1][1] - m[0][1] * m[1][0];
  default:
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  }
}

int toInt(const TableReader& r, std::string_view key, std::int64_t v, std::int64_t lowest) {
  r.check(v >= lowest && v <= std::numeric_limits<int>::max(), key,
          ">= " + std::to_string(lowest) + " (and fit an int)", static_cast<double>(v));
  return static_cast<int>(v);
}

class DeckReader {
public:
  DeckReader(const toml::table& root, const std::string& path) : root_(root), path_(path) {}
  void read(Deck& deck);

private:
  TableReader reader(const toml::table& t, Context c) const { return {t, std::move(c), path_}; }
  std::vector<double> point(const TableReader& r, std::string_view key) const {
    return r.required(r.vector(key, dimension_), key);
  }
  std::string readName(const TableReader& r, std::string_view kind,
                       std::map<std::string, SourceLocation>& seen) const;

  void readRun(const TableReader& r, RunConfig& run);
  void readDecomposition(const TableReader& r, DecompositionConfig& d) const;
  void readBody(const TableReader& r, const std::vector<MaterialConfig>& materials,
                BodyConfig& b) const;
  void readEnergySource(const TableReader& r, EnergySourceConfig& e) const;
  void readBoundary(const TableReader& r, BoundaryConfig& b,
                    const std::vector<BodyConfig>& bodies) const;
  void readDamping(const TableReader& r, DampingConfig& d) const;
  // The index of the body `name` names (key `key` of r), or a DeckError with a did-you-mean.
  std::int32_t bodyIndex(const TableReader& r, std::string_view key, const std::string& name,
                         const std::vector<BodyConfig>& bodies) const;
  void readOutput(const TableReader& r, OutputConfig& o, double endTime, SolverMethod method) const;
  void readCheckpoint(const TableReader& r, CheckpointConfig& c) const;
  void readFragments(const TableReader& r, FragmentsConfig& c, const SolverConfig& s) const;
  void readPenetration(const TableReader& r, PenetrationConfig& c,
                       const std::vector<BodyConfig>& bodies) const;
  void readProbe(const TableReader& r, ProbeConfig& p) const;

  const toml::table& root_;
  const std::string& path_;
  std::size_t dimension_ = 0;
  std::vector<std::string> jetNames_; // [[jet]] names: a penetrator may name a whole jet
  bool rz_ = false;                   // run.geometry = "rz"
};

void DeckReader::read(Deck& deck) {
  const TableReader top(root_, Context{}, path_);
  top.allowOnly(*dd::schemaKeys(""));
  const SourceLocation start{path_, 1, 1}; // where a missing top-level table is reported

  const toml::table* run = top.subtable("run");
  if (!run) throw DeckError(start, "missing required table [run]");
  readRun(reader(*run, Context{}.child("run")), deck.run);
  // Without a [solver] table, its defaults as an empty one gives them (contact "auto").
  static const toml::table noSolver;
  const auto* solver = top.subtable("solver");
  dd::readSolver(reader(solver ? *solver : noSolver, Context{}.child("solver")), deck.solver);
  deck.solver.geometry = deck.run.geometry;
  if (const auto* t = top.subtable("decomposition"))
    readDecomposition(reader(*t, Context{}.child("decomposition")), deck.decomposition);

  // Each [[kind]] entry, read by `read` into `out`.
  const auto entries = [&](std::string_view kind, auto& out, auto&& read) {
    const auto tables = top.tables(kind);
    for (std::size_t i = 0; i < tables.size(); ++i) {
      read(reader(*tables[i], Context::entry(kind, *tables[i], i)), out.emplace_back());
    }
    return tables.size();
  };

  std::map<std::string, SourceLocation> names;
  if (entries("material", deck.materials, [&](const TableReader& r, MaterialConfig& m) {
        m.name = readName(r, "material", names);
        dd::readMaterial(r, m);
      }) == 0)
    throw DeckError(top.whereValue("material"), "the deck needs at least one [[material]]");

  names.clear();
  if (entries("body", deck.bodies, [&](const TableReader& r, BodyConfig& b) {
        b.name = readName(r, "body", names);
        readBody(r, deck.materials, b);
      }) == 0)
    throw DeckError(top.whereValue("body"), "the deck needs at least one [[body]]");
  // [[jet]]: its segments join the bodies (after the deck's own, so their ids come last).
  std::map<std::string, SourceLocation> jetNames;
  const auto jets = top.tables("jet");
  for (std::size_t i = 0; i < jets.size(); ++i) {
    const TableReader r = reader(*jets[i], Context::entry("jet", *jets[i], i));
    const std::string name =
        r.has("name") ? readName(r, "jet", jetNames) : "jet" + std::to_string(i + 1);
    jetNames_.push_back(name);
    dd::readJet(r, dimension_, rz_, deck.materials, deck.bodies, name);
  }

  // Monaghan's artificial stress is on by default for decks with solids: without it, solids in
  // tension pair up and tear (the rubber rings of decks/topics/safe-defaults.md). So is the
  // linearly reconstructed viscosity: the plain one acts in plastic flow as a shear viscosity
  // comparable to the flow stress (a Taylor bar's face comes out 10% narrow; decks/README.md).
  const bool solids = std::any_of(deck.materials.begin(), deck.materials.end(),
                                  [](const MaterialConfig& m) { return !m.strength.none(); });
  if (!deck.solver.artificial_stress.given) deck.solver.artificial_stress.enabled = solids;
  if (!deck.solver.artificial_viscosity.reconstructGiven)
    deck.solver.artificial_viscosity.reconstruct = solids;

  entries("energy_source", deck.energy_sources,
          [&](const TableReader& r, EnergySourceConfig& e) { readEnergySource(r, e); });
  entries("boundary", deck.boundaries,
          [&](const TableReader& r, BoundaryConfig& b) { readBoundary(r, b, deck.bodies); });
  for (std::size_t i = 0; i < deck.boundaries.size(); ++i)
    for (std::size_t k = 0; k < i; ++k)
      if (deck.boundaries[i].type == BoundaryType::Pressure &&
          deck.boundaries[k].type == BoundaryType::Pressure &&
          deck.boundaries[i].bodyIndex == deck.boundaries[k].bodyIndex)
        throw DeckError(deck.boundaries[i].where,
                        "body '" + deck.boundaries[i].body +
                            "' has a pressure boundary already (one table per body)");
  if (const auto* t = top.subtable("damping"))
    readDamping(reader(*t, Context{}.child("damping")), deck.damping.emplace());

  const toml::table* output = top.subtable("output");
  if (!output) throw DeckError(start, "missing required table [output]");
  readOutput(reader(*output, Context{}.child("output")), deck.output, deck.run.end_time,
             deck.solver.method);
  if (const auto* t = top.subtable("checkpoint"))
    readCheckpoint(reader(*t, Context{}.child("checkpoint")), deck.checkpoint.emplace());
  if (const auto* t = top.subtable("fragments"))
    readFragments(reader(*t, Context{}.child("fragments")), deck.fragments.emplace(), deck.solver);
  if (const auto* t = top.subtable("penetration"))
    readPenetration(reader(*t, Context{}.child("penetration")), deck.penetration.emplace(),
                    deck.bodies);

  names.clear();
  entries("probe", deck.probes, [&](const TableReader& r, ProbeConfig& p) {
    p.name = readName(r, "probe", names);
    readProbe(r, p);
  });
  dd::checkMpmScope(deck);
}

// Names address entries in messages and in --set paths, so they are unique and dot-free.
std::string DeckReader::readName(const TableReader& r, std::string_view kind,
                                 std::map<std::string, SourceLocation>& seen) const {
  const std::string name = r.required(r.string("name"), "name");
  if (name.empty() || name.find('.') != std::string::npos)
    r.fail("name", std::string(kind) + " name '" + name +
                       "' must be non-empty and free of '.' (--set addresses entries by it)");
  const auto [it, inserted] = seen.emplace(name, r.whereValue("name"));
  if (!inserted) {
    std::string m = "duplicate " + std::string(kind) + " name '" + name + "'";
    if (it->second.line > 0) m += " (first at line " + std::to_string(it->second.line) + ")";
    r.fail("name", m);
  }
  return name;
}

void DeckReader::readRun(const TableReader& r, RunConfig& run) {
  r.allowOnly(*dd::schemaKeys("run"));
  run.title = r.string("title").value_or("");
  const std::int64_t dim = r.required(r.integer("dimension"), "dimension");
  r.check(dim >= 1 && dim <= 3, "dimension", "1, 2 or 3", static_cast<double>(dim));
  run.dimension = static_cast<int>(dim);
  dimension_ = static_cast<std::size_t>(dim);
  if (r.choice("geometry", {"cartesian", "rz"}, "cartesian") == "rz") {
    if (dim != 2)
      r.fail("geometry", "geometry 'rz' (axisymmetric: x = r, y = z) needs run.dimension 2 "
                         "(run.dimension is " +
                             std::to_string(dim) + ")");
    run.geometry = Geometry::RZ;
  }
  rz_ = run.geometry == Geometry::RZ;
  run.end_time = r.required(r.number("end_time"), "end_time");
  r.check(run.end_time > 0.0, "end_time", "> 0", run.end_time);
  if (const auto v = r.integer("max_steps")) {
    r.check(*v >= 0, "max_steps", ">= 0", static_cast<double>(*v));
    run.max_steps = *v;
  }
  if (const auto v = r.number("resolution")) {
    r.check(*v > 0.0, "resolution", "> 0", *v);
    run.resolution = *v;
  }
  if (const auto v = r.integer("seed")) {
    r.check(*v >= 0, "seed", ">= 0", static_cast<double>(*v));
    run.seed = static_cast<std::uint64_t>(*v);
  }
}

void DeckReader::readDecomposition(const TableReader& r, DecompositionConfig& d) const {
  r.allowOnly(*dd::schemaKeys("decomposition"));
  d.curve = r.choice("curve", kCurveNames, d.curve);
  d.partitioner = r.choice("partitioner", kPartitionerNames, d.partitioner);
  if (const auto v = r.integer("rebalance_every"))
    d.rebalance_every = toInt(r, "rebalance_every", *v, 0);
  d.imbalance_threshold = r.number("imbalance_threshold").value_or(d.imbalance_threshold);
  r.check(d.imbalance_threshold >= 1.0, "imbalance_threshold", ">= 1 (a max/mean cost ratio)",
          d.imbalance_threshold);
  d.reproducible = r.boolean("reproducible").value_or(d.reproducible);
}

void DeckReader::readBody(const TableReader& r, const std::vector<MaterialConfig>& materials,
                          BodyConfig& b) const {
  r.allowOnly(*dd::schemaKeys("body"));
  b.where = r.where();
  b.material = r.required(r.string("material"), "material");
  b.material_index = dd::materialIndex(r, b.material, materials);

  const toml::table* shape = r.subtable("shape");
  if (!shape) r.missing("shape");
  dd::readShape(reader(*shape, r.context().child("shape")), b.shape, dimension_, rz_);
  b.spacing = r.required(r.number("spacing"), "spacing");
  r.check(b.spacing > 0.0, "spacing", "> 0", b.spacing);
  b.lattice = r.choice("lattice", kLatticeNames, b.lattice);
  b.velocity = r.vector("velocity", dimension_).value_or(std::vector<double>(dimension_, 0.0));
  double speed2 = 0.0;
  for (double v : b.velocity) speed2 += v * v;
  r.check(std::sqrt(speed2) < 299792458.0, "velocity", "slower than light (a speed below 3e8 m/s)",
          std::sqrt(speed2));

  b.initial_density = r.number("initial_density");
  if (b.initial_density)
    r.check(*b.initial_density > 0.0, "initial_density", "> 0", *b.initial_density);
  b.initial_specific_energy = r.number("initial_specific_energy");
  if (b.initial_specific_energy)
    r.check(*b.initial_specific_energy >= 0.0, "initial_specific_energy", ">= 0",
            *b.initial_specific_energy);
  b.initial_pressure = r.number("initial_pressure");
  // Both would set the internal energy; which one wins is not for the reader to guess.
  if (b.initial_pressure && b.initial_specific_energy)
    r.fail("initial_pressure", r.quoted("initial_pressure") +
                                   " cannot be combined with initial_specific_energy (both set "
                                   "the internal energy; give one)");

  b.jitter = r.number("jitter").value_or(0.0);
  r.check(b.jitter >= 0.0 && b.jitter < 0.5, "jitter", "in [0, 0.5) (a fraction of the spacing)",
          b.jitter);
  b.insert_time = r.number("insert_time").value_or(0.0);
  r.check(b.insert_time >= 0.0, "insert_time", ">= 0", b.insert_time);
  b.lattice_transform = r.matrix("lattice_transform", dimension_);
  if (b.lattice_transform) {
    const double det = determinant(*b.lattice_transform);
    r.check(det != 0.0, "lattice_transform", "invertible (non-zero determinant)", det);
  }
  b.allow_overlap = r.boolean("allow_overlap").value_or(false);
  dd::readVelocityFields(r, dimension_, b);
  b.fixed = r.boolean("fixed").value_or(false);
  // A fixed body has no acceleration: at rest it is a clamp, with a uniform velocity a piston
  // driven at that speed. A velocity field would shear it forever.
  if (b.fixed &&
      (b.radial_velocity || b.cantilever_velocity || b.linear_velocity || b.sine_velocity))
    r.fail("fixed", r.quoted("fixed") +
                        " body moves rigidly (at rest, or at its uniform `velocity`: a piston) and "
                        "cannot be given a velocity field");
}

void DeckReader::readEnergySource(const TableReader& r, EnergySourceConfig& e) const {
  r.allowOnly(*dd::schemaKeys("energy_source"));
  e.where = r.where();
  e.center = point(r, "center");
  e.radius = r.number("radius").value_or(0.0);
  r.check(e.radius >= 0.0, "radius", ">= 0", e.radius);
  e.energy = r.required(r.number("energy"), "energy");
  r.check(e.energy >= 0.0, "energy", ">= 0", e.energy);
}

void DeckReader::readBoundary(const TableReader& r, BoundaryConfig& b,
                              const std::vector<BodyConfig>& bodies) const {
  b.where = r.where();
  b.type = dd::readType(r, "boundary", kBoundaryTypeNames, "boundary");
  switch (b.type) {
  case BoundaryType::RigidWall: {
    b.point = point(r, "point");
    b.normal = point(r, "normal");
    const double n = dd::norm(b.normal);
    if (n == 0.0) r.fail("normal", r.quoted("normal") + " must not be the zero vector");
    for (double& x : b.normal) x /= n;
    // A mirror plane in r-z is a plane (normal along z) or a cylinder (along r); an inclined
    // one would be a cone, which a mirror image does not model.
    if (rz_ && b.normal[0] != 0.0 && b.normal[1] != 0.0)
      r.fail("normal", r.quoted("normal") + " in geometry 'rz' is along r ([1, 0] or [-1, 0]: a "
                                            "cylindrical wall) or along z (a plane)");
    if (rz_ && b.normal[0] != 0.0 && b.point[0] <= 0.0)
      r.fail("point", r.quoted("point") + " of a cylindrical wall in geometry 'rz' needs r > 0 "
                                          "(the axis is a mirror already)");
    break;
  }
  case BoundaryType::Pressure:
    b.body = r.required(r.string("body"), "body");
    b.bodyIndex = bodyIndex(r, "body", b.body, bodies);
    b.pressure = dd::readPressureTable(r);
    break;
  case BoundaryType::Periodic: {
    const std::int64_t axis = r.required(r.integer("axis"), "axis");
    r.check(axis >= 0 && axis < static_cast<std::int64_t>(dimension_), "axis",
            "0 .. " + std::to_string(dimension_ - 1) + " (0 = x; run.dimension is " +
                std::to_string(dimension_) + ")",
            static_cast<double>(axis));
    b.axis = static_cast<int>(axis);
    if (rz_ && axis == 0)
      r.fail("axis", "a periodic boundary in geometry 'rz' is along z (axis 1); r is bounded "
                     "by the axis");
    b.min = r.required(r.number("min"), "min");
    b.max = r.required(r.number("max"), "max");
    r.check(b.min < b.max, "max", "> min (" + dd::formatNumber(b.min) + ")", b.max);
    break;
  }
  }
}

void DeckReader::readOutput(const TableReader& r, OutputConfig& o, double endTime,
                            SolverMethod method) const {
  r.allowOnly(*dd::schemaKeys("output"));
  o.where = r.where();
  o.directory = r.required(r.string("directory"), "directory");
  if (o.directory.empty()) r.fail("directory", r.quoted("directory") + " must not be empty");
  o.every = r.number("every").value_or(0.0);
  r.check(o.every >= 0.0, "every", ">= 0", o.every);
  // Every snapshot time is a step: 1e8 of them in a run is a misplaced exponent.
  r.check(o.every == 0.0 || endTime / o.every <= 1e8, "every",
          ">= 1e-8 of run.end_time (at most 1e8 snapshots)", o.every);
  o.every_steps = r.integer("every_steps").value_or(0);
  r.check(o.every_steps >= 0, "every_steps", ">= 0", static_cast<double>(o.every_steps));
  o.fields = r.strings("fields").value_or(std::vector<std::string>{});
  o.grid = r.boolean("grid").value_or(false);
  if (o.grid && method != SolverMethod::Mpm)
    r.fail("grid", r.quoted("grid") +
                       " writes MPM's background grid: it needs solver.method = "
                       "\"mpm\" (this run's is \"" +
                       std::string(kSolverMethodNames(method)) + "\")");
  o.history_every_steps = r.integer("history_every_steps").value_or(1);
  r.check(o.history_every_steps >= 1, "history_every_steps", ">= 1",
          static_cast<double>(o.history_every_steps));
  o.progress_seconds = r.number("progress_seconds").value_or(o.progress_seconds);
  r.check(o.progress_seconds > 0.0, "progress_seconds", "> 0", o.progress_seconds);
  o.progress_percent = r.number("progress_percent").value_or(o.progress_percent);
  r.check(o.progress_percent >= 0.0 && o.progress_percent <= 100.0, "progress_percent",
          "in [0, 100]", o.progress_percent);
  o.failure_history = r.integer("failure_history").value_or(o.failure_history);
  r.check(o.failure_history >= 0 && o.failure_history <= 100000, "failure_history",
          "in [0, 100000] steps", static_cast<double>(o.failure_history));
  o.dt_warning = r.number("dt_warning").value_or(o.dt_warning);
  r.check(o.dt_warning >= 0.0 && o.dt_warning < 1.0, "dt_warning", "in [0, 1)", o.dt_warning);
  o.max_energy_error = r.number("max_energy_error").value_or(o.max_energy_error);
  r.check(o.max_energy_error >= 0.0, "max_energy_error", ">= 0 (0: off)", o.max_energy_error);
  o.recordWhere = r.whereValue("record_particles");
  o.record_particles = r.integers("record_particles").value_or(std::vector<std::int64_t>{});
  for (const std::int64_t id : o.record_particles)
    r.check(id >= 0, "record_particles", "particle ids >= 0", static_cast<double>(id));
  if (o.record_particles.size() > 64)
    r.fail("record_particles", r.quoted("record_particles") +
                                   " records every step: at most 64 particles (got " +
                                   std::to_string(o.record_particles.size()) + ")");
}

void DeckReader::readFragments(const TableReader& r, FragmentsConfig& c,
                               const SolverConfig& s) const {
  r.allowOnly(*dd::schemaKeys("fragments"));
  c.where = r.where();
  c.link_length = r.number("link_length").value_or(c.link_length);
  // Friends are found among the neighbors of the force loop: the link must stay within the
  // kernel's support (2 h for every kernel spall has), i.e. 2 n_h spacings.
  const double most = 2.0 * s.nodes_per_h;
  r.check(c.link_length > 0.0 && c.link_length <= most, "link_length",
          "in (0, 2 nodes_per_h] (particle spacings; at most the kernel support, 2 h)",
          c.link_length);
  c.damage_threshold = r.number("damage_threshold").value_or(c.damage_threshold);
  r.check(c.damage_threshold > 0.0 && c.damage_threshold <= 1.0, "damage_threshold", "in (0, 1]",
          c.damage_threshold);
}

std::int32_t DeckReader::bodyIndex(const TableReader& r, std::string_view key,
                                   const std::string& name,
                                   const std::vector<BodyConfig>& bodies) const {
  Names bodyNames;
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    if (bodies[b].name == name) return static_cast<std::int32_t>(b);
    bodyNames.push_back(bodies[b].name);
  }
  r.fail(key, r.quoted(key) + " names no [[body]]: '" + name + "'" +
                  dd::didYouMean(name, bodyNames) + " (bodies: " + dd::joined(bodyNames) + ")");
}

void DeckReader::readDamping(const TableReader& r, DampingConfig& d) const {
  r.allowOnly(*dd::schemaKeys("damping"));
  d.where = r.where();
  d.coefficient = r.required(r.number("coefficient"), "coefficient");
  r.check(d.coefficient > 0.0, "coefficient", "> 0 (1/s)", d.coefficient);
  d.until = r.required(r.number("until"), "until");
  r.check(d.until > 0.0, "until", "> 0 (s)", d.until);
}

void DeckReader::readPenetration(const TableReader& r, PenetrationConfig& c,
                                 const std::vector<BodyConfig>& bodies) const {
  r.allowOnly(*dd::schemaKeys("penetration"));
  c.where = r.where();
  const auto knownBody = [&](std::string_view key, const std::string& name) {
    bodyIndex(r, key, name, bodies);
  };
  const auto listed = r.required(r.strings("penetrator"), "penetrator");
  if (listed.empty())
    r.fail("penetrator", r.quoted("penetrator") + " must name at least one [[body]]");
  // A [[jet]]'s name stands for all its segments.
  for (const auto& name : listed) {
    if (std::find(jetNames_.begin(), jetNames_.end(), name) != jetNames_.end()) {
      for (const auto& b : bodies)
        if (b.name.rfind(name + "_segment", 0) == 0) c.penetrator.push_back(b.name);
      continue;
    }
    knownBody("penetrator", name);
    c.penetrator.push_back(name);
  }
  c.target = r.required(r.string("target"), "target");
  knownBody("target", c.target);
  if (std::find(c.penetrator.begin(), c.penetrator.end(), c.target) != c.penetrator.end())
    r.fail("target", "body '" + c.target + "' is both the target and a penetrator");
  c.surface = r.required(r.vector("surface", dimension_), "surface");
  c.direction = r.required(r.vector("direction", dimension_), "direction");
  double norm = 0.0;
  for (double d : c.direction) norm += d * d;
  norm = std::sqrt(norm);
  if (!(norm > 0.0)) r.fail("direction", r.quoted("direction") + " must not be zero");
  for (double& d : c.direction) d /= norm;
  // An rz run is symmetric about the axis: penetration runs along it.
  if (rz_ && c.direction[0] != 0.0)
    r.fail("direction", "in an rz run (x = r, y = z) penetration runs along the axis: " +
                            r.quoted("direction") + " must be [0, 1] or [0, -1]");
}

void DeckReader::readCheckpoint(const TableReader& r, CheckpointConfig& c) const {
  r.allowOnly(*dd::schemaKeys("checkpoint"));
  c.where = r.where();
  c.every_steps = r.integer("every_steps").value_or(0);
  r.check(c.every_steps >= 0, "every_steps", ">= 0", static_cast<double>(c.every_steps));
  c.every_wall_seconds = r.number("every_wall_seconds").value_or(0.0);
  r.check(c.every_wall_seconds >= 0.0, "every_wall_seconds", ">= 0", c.every_wall_seconds);
  if (const auto v = r.integer("keep")) c.keep = toInt(r, "keep", *v, 1);
}

void DeckReader::readProbe(const TableReader& r, ProbeConfig& p) const {
  r.allowOnly(*dd::schemaKeys("probe"));
  p.where = r.where();
  p.position = point(r, "position");
  p.track = r.choice("track", kProbeTrackNames, p.track);
  // A probe without fields would record nothing: say so rather than run silently.
  p.fields = r.required(r.strings("fields"), "fields");
  if (p.fields.empty()) r.fail("fields", r.quoted("fields") + " must name at least one field");
}

std::string resolvedText(const toml::table& root, const std::string& path,
                         const std::vector<std::string>& overrides) {
  std::ostringstream os;
  os << "# resolved deck of " << path;
  if (overrides.empty())
    os << " (no overrides)";
  else
    os << " with overrides:";
  for (const auto& o : overrides) {
    std::string flat = o; // keep the comment on one line
    for (char& c : flat)
      if (c == '\n' || c == '\r') c = ' ';
    os << " --set " << flat;
  }
  os << "\n" << root << "\n";
  return os.str();
}

} // namespace

Deck loadDeck(const std::string& path, const std::vector<std::string>& overrides) {
  const std::string text = readText(path);
  toml::table root;
  try {
    root = toml::parse(std::string_view(text), std::string_view(path));
  } catch (const toml::parse_error& e) {
    const auto& b = e.source().begin;
    throw DeckError({path, static_cast<int>(b.line), static_cast<int>(b.column)},
                    std::string(e.description()));
  }
  dd::applyOverrides(root, overrides, path);
  dd::inlineJetFiles(root, path);

  Deck deck;
  deck.path = path;
  deck.resolved_toml = resolvedText(root, path, overrides);
  DeckReader(root, path).read(deck);
  return deck;
}

} // namespace spall
