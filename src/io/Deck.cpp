// Deck reading: parse (toml++), apply --set overrides, then validate into the typed config. Each
// check reports the position of the value it rejects (docs/reference.md, "Bad input").
#include "spall/io/Deck.hpp"

#include "DeckDetail.hpp"
#include "keys/Keys.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

namespace spall {

namespace {

using io::deck_detail::Context;
using io::deck_detail::DeckNotes;
using io::deck_detail::Names;
using io::deck_detail::TableReader;
namespace dd = io::deck_detail;
namespace keys = io::keys;

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

// Plausibility of speeds (docs/reference.md, "Warnings").
constexpr double kFastest = 1e5, kSlowestPenetrator = 10.0;

class DeckReader {
public:
  DeckReader(const toml::table& root, const std::string& path, DeckNotes& notes)
      : root_(root), path_(path), notes_(notes) {}
  void read(Deck& deck);

private:
  TableReader reader(const toml::table& t, Context c) const {
    return {t, std::move(c), path_, &notes_};
  }
  std::string readName(const TableReader& r, std::string_view kind,
                       std::map<std::string, SourceLocation>& seen) const;

  void readRun(const TableReader& r, RunConfig& run);
  void readBody(const TableReader& r, const std::vector<MaterialConfig>& materials,
                BodyConfig& b) const;
  void readBoundary(const TableReader& r, BoundaryConfig& b, const std::vector<BodyConfig>& bodies,
                    SolverMethod method) const;
  // The index of the body `name` names (key `key` of r), or a DeckError with a did-you-mean.
  std::int32_t bodyIndex(const TableReader& r, std::string_view key, const std::string& name,
                         const std::vector<BodyConfig>& bodies) const;
  void readPenetration(const TableReader& r, PenetrationConfig& c,
                       const std::vector<BodyConfig>& bodies) const;

  const toml::table& root_;
  const std::string& path_;
  DeckNotes& notes_;
  std::size_t dimension_ = 0;
  std::vector<std::string> jetNames_; // [[jet]] names: a penetrator may name a whole jet
  bool rz_ = false;                   // run.geometry = "rz"
  double resolution_ = 1.0;           // run.resolution
};

void DeckReader::read(Deck& deck) {
  const TableReader top(root_, Context{}, path_, &notes_);
  top.allowOnly(*dd::schemaKeys(""));
  const SourceLocation start{path_, 1, 1}; // where a missing top-level table is reported

  const toml::table* run = top.subtable("run");
  if (!run) throw DeckError(start, "missing required table [run]");
  readRun(reader(*run, Context{}.child("run")), deck.run);
  // Without a [solver] table, its defaults as an empty one gives them (contact "auto").
  static const toml::table noSolver;
  const auto* solver = top.subtable("solver");
  keys::readSolver(reader(solver ? *solver : noSolver, Context{}.child("solver")), deck.solver);
  deck.solver.geometry = deck.run.geometry;
  if (const auto* t = top.subtable("decomposition"))
    keys::readDecomposition(reader(*t, Context{}.child("decomposition")), deck.decomposition);

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
  // Flaws activate at any tension, and a free surface's one-sided sums ring into tension when a
  // shock arrives there or reflects: a flyer's rear face failed its two outermost rows as the
  // 3 GPa shock reached it (+234 MPa where the stress is 0), a target's rear its outermost. The
  // corrected gradient, exact for a linear field where the support is cut, keeps them whole
  // (tests/verification/test_contact_faces.py; decks/topics/damage.md).
  const bool flaws = std::any_of(deck.materials.begin(), deck.materials.end(), [](const auto& m) {
    return !m.strength.none() && std::holds_alternative<materials::GradyKipp>(m.damage.model);
  });
  if (!deck.solver.velocityGradientGiven)
    deck.solver.velocity_gradient = flaws ? VelocityGradient::Corrected : VelocityGradient::Sph;

  entries("energy_source", deck.energy_sources, [&](const TableReader& r, EnergySourceConfig& e) {
    keys::readEnergySource(r, e, dimension_);
  });
  entries("boundary", deck.boundaries, [&](const TableReader& r, BoundaryConfig& b) {
    readBoundary(r, b, deck.bodies, deck.solver.method);
  });
  // One pressure table per body; one period per axis (two would contradict each other, and the
  // halo's periodic images count on one).
  for (std::size_t i = 0; i < deck.boundaries.size(); ++i)
    for (std::size_t k = 0; k < i; ++k) {
      const BoundaryConfig &a = deck.boundaries[i], &b = deck.boundaries[k];
      if (a.type != b.type) continue;
      if (a.type == BoundaryType::Pressure && a.bodyIndex == b.bodyIndex)
        throw DeckError(a.where, "body '" + a.body +
                                     "' has a pressure boundary already (one table per body)");
      if (a.type == BoundaryType::Periodic && a.axis == b.axis)
        throw DeckError(a.where, fmt::format("axis {} is periodic already (one periodic "
                                             "boundary per axis)",
                                             a.axis));
    }
  if (const auto* t = top.subtable("damping"))
    keys::readDamping(reader(*t, Context{}.child("damping")), deck.damping.emplace());

  const toml::table* output = top.subtable("output");
  if (!output) throw DeckError(start, "missing required table [output]");
  keys::readOutput(reader(*output, Context{}.child("output")), deck.output, deck.run.end_time,
                   deck.solver.method);
  if (const auto* t = top.subtable("checkpoint"))
    keys::readCheckpoint(reader(*t, Context{}.child("checkpoint")), deck.checkpoint.emplace());
  if (const auto* t = top.subtable("fragments"))
    keys::readFragments(reader(*t, Context{}.child("fragments")), deck.fragments.emplace(),
                        deck.solver.nodes_per_h);
  if (const auto* t = top.subtable("penetration"))
    readPenetration(reader(*t, Context{}.child("penetration")), deck.penetration.emplace(),
                    deck.bodies);

  names.clear();
  entries("probe", deck.probes, [&](const TableReader& r, ProbeConfig& p) {
    p.name = readName(r, "probe", names);
    keys::readProbe(r, p, dimension_);
  });
  dd::checkMpmScope(deck);
  dd::resolutionWarnings(deck, notes_);
  dd::loadedBalsaraWarning(deck, notes_);
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
  keys::readRun(r, run);
  run.endTimeWhere = r.whereValue("end_time");
  notes_.si = run.units == Units::SI; // a scaled deck's numbers have no SI bounds to meet
  dimension_ = static_cast<std::size_t>(run.dimension);
  rz_ = run.geometry == Geometry::RZ;
  resolution_ = run.resolution;
}

void DeckReader::readBody(const TableReader& r, const std::vector<MaterialConfig>& materials,
                          BodyConfig& b) const {
  r.allowOnly(*dd::schemaKeys("body"));
  b.where = r.where();
  keys::readBody(r, b, dimension_);
  b.spacingWhere = r.whereValue("spacing");
  b.velocityWhere = r.whereValue("velocity");
  // Faster than any impact a hydrocode is run for (meteoroids reach 72 km/s): a velocity typed in
  // mm/s or cm/s.
  if (const double v = dd::norm(b.velocity); v > kFastest)
    r.warn("velocity",
           fmt::format("{} is {} m/s, above {} m/s: mm/s or cm/s typed for m/s?",
                       r.quoted("velocity"), dd::formatNumber(v), dd::formatNumber(kFastest)));
  b.material_index = dd::materialIndex(r, b.material, materials);
  const toml::table* shape = r.subtable("shape");
  if (!shape) r.missing("shape");
  keys::readShape(reader(*shape, r.context().child("shape")), b.shape, dimension_, rz_);
  if (b.lattice_transform) {
    const double det = determinant(*b.lattice_transform);
    r.check(det != 0.0, "lattice_transform", "invertible (non-zero determinant)", det);
  }
  keys::readVelocityFields(r, dimension_, b);
  keys::readGrading(r, dimension_, b);
  if (b.shape.type == ShapeType::Particles) {
    // A file's particles are as the mesher made them: each one's spacing is its volume's root.
    // (lattice = "cubic" is the default the deck as run writes: no lattice is made either way.)
    // The body's spacing is their coarsest, run.resolution undone (spacing / resolution is a
    // body's spacing as made, everywhere it is read).
    for (const char* key : {"spacing", "lattice", "lattice_transform", "grading"})
      if (r.has(key) && !(key == std::string_view("lattice") && b.lattice == Lattice::Cubic))
        r.fail(key, r.quoted(key) + " is for lattice shapes: a 'particles' shape's are the "
                                    "file's, each with the spacing of its own volume");
    b.spacing = b.shape.cloud->coarsest * resolution_;
    b.spacingWhere = b.shape.where;
  } else if (!r.has("spacing")) {
    r.missing("spacing");
  }
  // Graded bodies are layers of their own lattice (app/GradedSites.cpp).
  if (b.grading && (b.lattice != Lattice::Cubic || b.lattice_transform))
    r.fail("grading", r.quoted("grading") +
                          " lays the body in layers of a cubic lattice: it takes neither lattice = "
                          "\"hexagonal\" nor lattice_transform");
  // A fixed body has no acceleration: at rest it is a clamp, with a uniform velocity a piston
  // driven at that speed. A velocity field would shear it forever.
  if (b.fixed &&
      (b.radial_velocity || b.cantilever_velocity || b.linear_velocity || b.sine_velocity))
    r.fail("fixed", r.quoted("fixed") +
                        " body moves rigidly (at rest, or at its uniform `velocity`: a piston) and "
                        "cannot be given a velocity field");
}

void DeckReader::readBoundary(const TableReader& r, BoundaryConfig& b,
                              const std::vector<BodyConfig>& bodies, SolverMethod method) const {
  keys::readBoundary(r, b, dimension_, rz_);
  switch (b.type) {
  case BoundaryType::RigidWall: {
    // SPH's wall is a mirror: its images carry no shear to rub with.
    if (b.friction > 0.0 && method != SolverMethod::Mpm)
      r.fail("friction", r.quoted("friction") + " of a rigid wall is the material point "
                                                "method's (its grid nodes on the wall); SPH's "
                                                "and ASPH's walls are mirrors and slip");
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
    b.bodyIndex = bodyIndex(r, "body", b.body, bodies);
    break;
  case BoundaryType::Periodic:
    break;
  }
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

void DeckReader::readPenetration(const TableReader& r, PenetrationConfig& c,
                                 const std::vector<BodyConfig>& bodies) const {
  keys::readPenetration(r, c, dimension_);
  const auto knownBody = [&](std::string_view key, const std::string& name) {
    bodyIndex(r, key, name, bodies);
  };
  // A [[jet]]'s name stands for all its segments.
  const std::vector<std::string> listed = std::move(c.penetrator);
  c.penetrator.clear();
  for (const auto& name : listed) {
    if (std::find(jetNames_.begin(), jetNames_.end(), name) != jetNames_.end()) {
      for (const auto& b : bodies)
        if (b.name.rfind(name + "_segment", 0) == 0) c.penetrator.push_back(b.name);
      continue;
    }
    knownBody("penetrator", name);
    c.penetrator.push_back(name);
  }
  knownBody("target", c.target);
  // A penetrator slower than a dropped tool (10 m/s): a speed typed in km/s.
  for (const auto& b : bodies)
    if (std::find(c.penetrator.begin(), c.penetrator.end(), b.name) != c.penetrator.end())
      if (const double v = dd::norm(b.velocity); v > 0.0 && v < kSlowestPenetrator)
        notes_.unitWarning(
            {b.velocityWhere,
             fmt::format("'body.{}.velocity' is {} m/s for a penetrator ([penetration]): km/s "
                         "typed for m/s?",
                         b.name, dd::formatNumber(v))});
  if (std::find(c.penetrator.begin(), c.penetrator.end(), c.target) != c.penetrator.end())
    r.fail("target", "body '" + c.target + "' is both the target and a penetrator");
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

std::string resolvedText(toml::table root, const std::string& path,
                         const std::vector<std::string>& overrides,
                         const std::vector<std::string>& libraries) {
  // A jet's rows are inline (inlineJetFiles): its file, relative to this deck, would not be found
  // from where the deck as run is read again.
  if (toml::array* jets = root["jet"].as_array())
    for (auto& node : *jets)
      if (toml::table* t = node.as_table()) t->erase("file");
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
  os << "\n# every default the reader applied is written out\n";
  for (const auto& l : libraries) os << "# material library: " << l << ", merged in\n";
  std::ostringstream body;
  body << root << "\n";
  os << dd::shortestFloats(body.str());
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
  const auto libraries = dd::inlineMaterialLibrary(root, path);
  dd::inlineJetFiles(root, path);

  Deck deck;
  deck.path = path;
  DeckNotes notes;
  DeckReader(root, path, notes).read(deck);
  dd::writeDefaults(root, notes.defaults);
  deck.resolved_toml = resolvedText(root, path, overrides, libraries);
  deck.warnings = std::move(notes.warnings);
  return deck;
}

std::string deckAsRun(const Deck& deck, const std::string& outputDir) {
  toml::table root =
      toml::parse(std::string_view(deck.resolved_toml), std::string_view("deck as run"));
  // The leading comment lines say what the deck was resolved from; the parse drops them.
  std::string comments;
  std::istringstream lines(deck.resolved_toml);
  for (std::string l; std::getline(lines, l) && l.starts_with("#");) comments += l + "\n";
  toml::table* output = root["output"].as_table();
  if (!output) output = root.insert_or_assign("output", toml::table{}).first->second.as_table();
  output->insert_or_assign("directory", outputDir);
  std::ostringstream body;
  body << root << "\n";
  return comments + "# run with its output in " + outputDir + "\n" + dd::shortestFloats(body.str());
}

} // namespace spall
