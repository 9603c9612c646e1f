// [output], [checkpoint], [[probe]], [fragments], [penetration], [damping]: the reference's rows
// and the reader's reads (Keys.hpp); the deck reader (io/Deck.cpp) checks what they name.
#include "Keys.hpp"

#include <fmt/format.h>

namespace spall::io::keys {

namespace {

// `endTime`, `method`: run.end_time and solver.method.
template <class K> void keysOf(K& k, OutputConfig& o, double endTime, SolverMethod method) {
  k.section("", "Snapshots, history, progress lines and the run's failure checks.");
  k.text("directory", o.directory, required, "not empty",
         "Where the snapshots, history.csv and the run's other files go.");
  k.require("directory", "", !o.directory.empty(), "must not be empty");
  k.number("every", o.every, keep, "s", atLeast(0),
           "Simulated time between snapshots; 0: not by time.");
  // Every snapshot time is a step: 1e8 of them in a run is a misplaced exponent.
  k.require("every", "at most 1e8 snapshots", o.every == 0.0 || endTime / o.every <= 1e8,
            fmt::format("must be >= 1e-8 of run.end_time ({}): at most 1e8 snapshots (got {})",
                        deck_detail::formatNumber(endTime), deck_detail::formatNumber(o.every)));
  k.integer("every_steps", o.every_steps, keep, "steps", atLeast(0),
            "Steps between snapshots; 0: not by steps.");
  k.strings("fields", o.fields, Depends{"all fields"}, "",
            "The particle fields of a snapshot; position and id are always written.");
  k.flag("grid", o.grid, keep, "Writes MPM's background grid nodes into every snapshot (/grid).");
  k.require("grid", "needs method = \"mpm\"", !o.grid || method == SolverMethod::Mpm,
            fmt::format("writes MPM's background grid: it needs solver.method = \"mpm\" (this "
                        "run's is \"{}\")",
                        kSolverMethodNames(method)));
  k.integer("history_every_steps", o.history_every_steps, keep, "steps", atLeast(1),
            "Steps between rows of history.csv and probes.csv.");
  k.number("progress_seconds", o.progress_seconds, keep, "s", above(0),
           "Wall-clock seconds between progress lines in a batch log.");
  k.number("progress_percent", o.progress_percent, keep, "", within(0, 100),
           "A progress line at every so many percent of end_time; 0: not by percent.");
  k.integer("failure_history", o.failure_history, keep, "steps", within(0, 100000),
            "A failing run replays from a copy at most this old; 0: no copy, no replay.");
  k.number("dt_warning", o.dt_warning, keep, "", withinClosedOpen(0, 1),
           "Warns when dt falls below this fraction of its median over 100 steps; 0: off.");
  k.number("max_energy_error", o.max_energy_error, keep, "", atLeast(0),
           "Stops as a failure past this energy error over K0 + |U0| + |W|; 0: never.");
  k.integers("record_particles", o.record_particles, Depends{"none"}, "ids >= 0; at most 64",
             "Particles whose deformation gradient and stress are written every step.");
}

template <class K> void keysOf(K& k, CheckpointConfig& c) {
  k.section("", "Checkpoints a run can restart from (spall run --restart).");
  k.integer("every_steps", c.every_steps, keep, "steps", atLeast(0),
            "Steps between checkpoints; 0: not by steps.");
  k.number("every_wall_seconds", c.every_wall_seconds, keep, "s", atLeast(0),
           "Wall-clock seconds between checkpoints; 0: not by time.");
  k.integer("keep", c.keep, keep, "", atLeast(1), "How many of the latest checkpoints are kept.");
}

template <class K> void keysOf(K& k, ProbeConfig& p) {
  k.section("", "Fields recorded at a point or on a particle, a row of probes.csv each history "
                "step.");
  k.other("name", "string", "required", "", "unique, non-empty, no '.'",
          "Names the probe in probes.csv.");
  k.vector("position", p.position, required, "m", "", "Where it records.");
  k.choice("track", p.track, kProbeTrackNames, keep,
           "material: the particle nearest the position at t = 0; space: a kernel average there.");
  // A probe without fields would record nothing: say so rather than run silently.
  k.strings("fields", p.fields, required, "one or more",
            "The fields it records, by component: pressure, velocity_x, stress_xy, ...");
  k.require("fields", "", !p.fields.empty(), "must name at least one field");
}

// `nodesPerH`: solver.nodes_per_h.
template <class K> void keysOf(K& k, FragmentsConfig& c, double nodesPerH) {
  k.section("", "Friends-of-friends fragments at every snapshot: fragments.csv and a fragment "
                "field.");
  // Friends are found among the neighbors of the force loop: the link must stay within the
  // kernel's support (2 h for every kernel spall has), i.e. 2 n_h spacings.
  const double most = 2.0 * nodesPerH;
  k.number("link_length", c.link_length, keep, "", withinOpenClosed(0, "2 nodes_per_h", most),
           "The link distance, in particle spacings (h / nodes_per_h).");
  k.number("damage_threshold", c.damage_threshold, keep, "", withinOpenClosed(0, 1),
           "Particles at or above this damage link to nothing.");
}

template <class K> void keysOf(K& k, PenetrationConfig& c) {
  k.section("", "The depth of penetration over time: penetration.csv.");
  k.strings("penetrator", c.penetrator, required, "one or more [[body]] or [[jet]] names",
            "The penetrating bodies; a jet's name stands for all its segments.");
  k.require("penetrator", "", !c.penetrator.empty(), "must name at least one [[body]]");
  k.text("target", c.target, required, "a [[body]]'s name, not a penetrator",
         "The body penetrated.");
  k.vector("surface", c.surface, required, "m", "", "A point on the target's original surface.");
  k.vector("direction", c.direction, required, "", "not zero; in rz [0, 1] or [0, -1]",
           "The direction of penetration (any length).");
}

template <class K> void keysOf(K& k, DampingConfig& d) {
  k.section("", "a = a - c v on every particle until `until` (Austin 2013, Eq. 5.1): settle, "
                "then shoot.");
  k.number("coefficient", d.coefficient, required, "1/s", above(0), "c, the damping rate.");
  k.number("until", d.until, required, "s", above(0), "The time at which damping stops.");
}

const auto kKeys = [](auto& k, auto& c) -> decltype(keysOf(k, c)) { keysOf(k, c); };

// Reads section `path` of r with keys.
template <class T, class Keys>
void readSection(const deck_detail::TableReader& r, std::string_view path, T& c, Keys keys,
                 std::size_t dimension = 0) {
  r.allowOnly(*deck_detail::schemaKeys(path));
  c.where = r.where();
  Read read(r, dimension);
  keys(read, c);
}

} // namespace

std::vector<KeySection> output() {
  return {
      sectionOf<OutputConfig>("output",
                              [](auto& k, auto& o) { keysOf(k, o, 1.0, SolverMethod::Mpm); }),
      sectionOf<CheckpointConfig>("checkpoint", kKeys),
      sectionOf<ProbeConfig>("probe", kKeys),
      sectionOf<FragmentsConfig>("fragments", [](auto& k, auto& c) { keysOf(k, c, 1.5); }),
      sectionOf<PenetrationConfig>("penetration", kKeys),
      sectionOf<DampingConfig>("damping", kKeys),
  };
}

void readOutput(const deck_detail::TableReader& r, OutputConfig& o, double endTime,
                SolverMethod method) {
  readSection(r, "output", o, [&](auto& k, auto& c) { keysOf(k, c, endTime, method); });
  o.recordWhere = r.whereValue("record_particles");
  for (const std::int64_t id : o.record_particles)
    r.check(id >= 0, "record_particles", "particle ids >= 0", static_cast<double>(id));
  if (o.record_particles.size() > 64)
    r.fail("record_particles",
           fmt::format("{} records every step: at most 64 particles (got {})",
                       r.quoted("record_particles"), o.record_particles.size()));
}

void readCheckpoint(const deck_detail::TableReader& r, CheckpointConfig& c) {
  readSection(r, "checkpoint", c, kKeys);
}

void readFragments(const deck_detail::TableReader& r, FragmentsConfig& c, double nodesPerH) {
  readSection(r, "fragments", c, [&](auto& k, auto& f) { keysOf(k, f, nodesPerH); });
}

void readDamping(const deck_detail::TableReader& r, DampingConfig& d) {
  readSection(r, "damping", d, kKeys);
}

void readProbe(const deck_detail::TableReader& r, ProbeConfig& p, std::size_t dimension) {
  readSection(r, "probe", p, kKeys, dimension);
}

void readPenetration(const deck_detail::TableReader& r, PenetrationConfig& c,
                     std::size_t dimension) {
  readSection(r, "penetration", c, kKeys, dimension);
}

} // namespace spall::io::keys
