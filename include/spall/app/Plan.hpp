#pragma once
// `spall plan`: a deck's particles and decomposition for N virtual ranks on one process, no
// physics: per rank the owned particles, ghosts, neighbor ranks, bytes sent a step and memory,
// and the strong-scaling efficiency predicted from costs measured on a machine. The counts are
// those a run makes at step 0 (parallel/VirtualRanks.hpp); the times are a model (below).
//
// The model, per rank r and step (one force evaluation):
//   t_r = s c (N_r + gamma G_r) / (T e_T) + k_x m_r lambda + b_r / beta + k_c lambda ceil(log2 R)
// N_r owned particles, G_r ghosts; c seconds per particle-step on one core (1 / the measured
// rate), s its slowdown when every core works (shared memory bandwidth and clocks; 1 on one
// rank), gamma a ghost's cost relative to an owned particle's (its pairs with the owned ones are
// evaluated on both sides, and it is packed, sent and searched), T threads at efficiency e_T;
// m_r messages of an exchange (ranks sent to and received from), b_r bytes sent by an exchange,
// k_x exchanges a step, lambda the latency of a message, beta the bandwidth; k_c collectives a
// step. A step of R ranks on C cores takes max(max_r t_r, sum_r t_r / C); the efficiency is
// t(1 rank) / (R t(R ranks)).
#include "spall/io/Deck.hpp"
#include "spall/parallel/Mpi.hpp"

#include <string>
#include <vector>

namespace spall::app {

struct PlanCosts {
  double rate = 0.0;        // particle-steps/s per core (one thread); 0: the method's default
  double ghost = 0.0;       // gamma; 0: the default
  double slowdown = 0.0;    // s, a core's compute when every core works; 0: the default
  double latency = 2.0e-6;  // s per message (lambda)
  double bandwidth = 5.0e9; // B/s (beta)
};

struct PlanOptions {
  std::string deckPath; // for the report (the caller loads the deck)
  std::vector<int> ranks;
  int threads = 1;
  int cores = 0;        // cores the ranks share; 0: as many as ranks (a cluster)
  std::string measured; // a run's output directory: its rate and bytes per particle
  PlanCosts costs;
  bool perRank = false; // the per-rank table for every rank count (default: up to 16 ranks)
  std::string json;     // also write the plan as JSON here
};

// Prints the plan (one process; UsageError on more ranks, for an MPM deck, or for bad options).
void runPlan(const Deck& deck, const PlanOptions& options, const parallel::MpiContext& mpi);

} // namespace spall::app
