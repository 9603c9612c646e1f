// The deck's top level, [run] and [decomposition] (read in io/Deck.cpp).
#include "spall/io/DeckKeys.hpp"

namespace spall::io::keys {

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
      {"run",
       "",
       "What is run, and for how long.",
       {
           {"title", "string", "\"\"", "", "", "Printed by `spall check` and kept in outputs."},
           {"dimension", "integer", "required", "", "1, 2 or 3", "The number of space dimensions."},
           {"geometry", "one of: cartesian, rz", "\"cartesian\"", "", "rz needs dimension 2",
            "rz: axisymmetric, x the radius and y the axis."},
           {"end_time", "float", "required", "s", "> 0", "Simulated time at which the run stops."},
           {"max_steps", "integer", "no limit", "", ">= 0",
            "The run stops after this many steps even before end_time."},
           {"resolution", "float", "1.0", "", "> 0",
            "Multiplies the particles per unit length of every body (spacing / resolution)."},
           {"seed", "integer", "1", "", ">= 0",
            "Seeds the random numbers (jitter, Weibull flaws)."},
       }},
      {"decomposition",
       "",
       "How particles are shared among MPI ranks; results are the same bits on any rank count.",
       {
           {"curve", "one of: hilbert, morton", "\"hilbert\"", "", "",
            "The space-filling curve that orders particles for the partition."},
           {"partitioner", "one of: sfc, metis", "\"sfc\"", "", "",
            "sfc: cut the curve into equal-cost pieces; metis: partition the neighbor graph."},
           {"rebalance_every", "integer", "20", "steps", ">= 0",
            "Steps between repartitions; 0: only when imbalance_threshold is crossed."},
           {"imbalance_threshold", "float", "1.1", "", ">= 1",
            "Max/mean cost over ranks that triggers a repartition at any step."},
           {"reproducible", "boolean", "true", "", "",
            "Neighbor sums in an order independent of the rank count (bit-for-bit results)."},
       }},
  };
}

} // namespace spall::io::keys
