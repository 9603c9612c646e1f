// The deck's top level (the tables it may hold), [run] and [decomposition]: the rows and reads
// (Keys.hpp).
#include "Keys.hpp"

#include <fmt/format.h>

namespace spall::io::keys {

namespace {

template <class K> void keysOf(K& k, RunConfig& run) {
  k.section("", "What is run, and for how long.");
  k.text("title", run.title, keep, "Printed by `spall check` and kept in outputs.");
  k.integer("dimension", run.dimension, required, "", within(1, 3),
            "The number of space dimensions.");
  k.choice("geometry", run.geometry, kGeometryNames, keep,
           "rz: axisymmetric, x the radius and y the axis.");
  k.require("geometry", "rz needs dimension 2", run.geometry != Geometry::RZ || run.dimension == 2,
            fmt::format(
                "is 'rz' (axisymmetric: x = r, y = z), which needs run.dimension 2 (run.dimension "
                "is {})",
                run.dimension));
  k.choice("units", run.units, kUnitNames, keep,
           "si: values a unit slip would give are warned of; scaled: a consistent "
           "nondimensional set (a benchmark), which none of SI's bounds fit.");
  k.number("end_time", run.end_time, required, "s", above(0),
           "Simulated time at which the run stops.");
  k.note("end_time", "warns beyond 100 or under 0.01 times the largest body's crossing time by "
                     "sound and flow (a time unit typed wrong?)");
  k.integer("max_steps", run.max_steps, Depends{"no limit"}, "", atLeast(0),
            "The run stops after this many steps even before end_time.");
  k.number("resolution", run.resolution, keep, "", above(0),
           "Multiplies the particles per unit length of every body (spacing / resolution).");
  k.integer("seed", run.seed, keep, "", atLeast(0),
            "Seeds the random numbers (jitter, Weibull flaws).");
}

template <class K> void keysOf(K& k, DecompositionConfig& d) {
  k.section("", "How particles are shared among MPI ranks; results are the same bits on any "
                "rank count.");
  k.choice("curve", d.curve, kCurveNames, keep,
           "The space-filling curve that orders particles for the partition.");
  k.choice("partitioner", d.partitioner, kPartitionerNames, keep,
           "sfc: cut the curve into equal-cost pieces; metis: partition the neighbor graph.");
  k.choice("cost", d.cost, kBalanceCostNames, keep,
           "counted: a particle's neighbor pairs (the same cuts every run); timed: those "
           "weighted by the seconds per pair its rank measured since the last cut.");
  k.integer("rebalance_every", d.rebalance_every, keep, "steps", atLeast(0),
            "Steps between repartitions; 0: only when imbalance_threshold is crossed.");
  k.number("imbalance_threshold", d.imbalance_threshold, keep, "", atLeast(1),
           "Max/mean cost over ranks that triggers a repartition at any step.");
  k.flag("reproducible", d.reproducible, keep,
         "Neighbor sums in an order independent of the rank count (bit-for-bit results).");
}

const auto kKeys = [](auto& k, auto& c) -> decltype(keysOf(k, c)) { keysOf(k, c); };

} // namespace

std::vector<KeySection> topLevel() {
  return {
      {"",
       "",
       "The tables a deck may hold; [run], [output] and at least one [[material]] and [[body]] "
       "are required.",
       {
           {"run", "table", "required", "", "", "Dimension, geometry, end time, resolution."},
           {"solver", "table", "defaults", "", "", "Method (SPH, ASPH, MPM) and its options."},
           {"decomposition", "table", "defaults", "", "",
            "How particles are shared among MPI ranks."},
           {"material", "[[table]]", "required", "", "one or more",
            "A material: density, equation of state, strength, damage, porosity."},
           {"body", "[[table]]", "required", "", "one or more",
            "A body: a shape filled with particles of one material."},
           {"energy_source", "[[table]]", "none", "", "",
            "Energy deposited at t = 0 in a sphere (blast waves)."},
           {"boundary", "[[table]]", "none", "", "",
            "A rigid wall, a periodic axis or a pressure on a body's surface."},
           {"output", "table", "required", "", "",
            "Where results go: snapshots, history, progress."},
           {"checkpoint", "table", "none", "", "", "Checkpoints a run can restart from."},
           {"probe", "[[table]]", "none", "", "", "Fields recorded at a point or on a particle."},
           {"fragments", "table", "none", "", "", "Fragment statistics at each snapshot."},
           {"penetration", "table", "none", "", "", "Depth of penetration over time."},
           {"jet", "[[table]]", "none", "", "", "A discrete jet: segments that enter over time."},
           {"damping", "table", "none", "", "",
            "Velocity damping for a quasi-static start (confining pressure)."},
       }},
      sectionOf<RunConfig>("run", kKeys),
      sectionOf<DecompositionConfig>("decomposition", kKeys),
  };
}

void readRun(const deck_detail::TableReader& r, RunConfig& run) {
  r.allowOnly(*deck_detail::schemaKeys("run"));
  Read read(r);
  keysOf(read, run);
}

void readDecomposition(const deck_detail::TableReader& r, DecompositionConfig& d) {
  r.allowOnly(*deck_detail::schemaKeys("decomposition"));
  Read read(r);
  keysOf(read, d);
}

} // namespace spall::io::keys
