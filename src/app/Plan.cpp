#include "spall/app/Plan.hpp"

#include "spall/app/BodyGenerator.hpp"
#include "spall/app/Setup.hpp"
#include "spall/core/Error.hpp"
#include "spall/methods/ParticleMethod.hpp"
#include "spall/parallel/VirtualRanks.hpp"
#include "spall/solvers/SphSolver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>

// `spall plan` (Plan.hpp): the deck's particles at t = 0 on one process, cut for each rank
// count as a run would cut them, and the model's step times.
namespace spall::app {

namespace {

// Costs measured on the development machine (2-core x86-64, one thread, Release -O3) with
// tools/plan_check: particle-steps/s per core over steps 20-200 of one rank (Sedov and the Taylor
// bar in 3D at resolution 0.6 and 0.7, noh_2d, rock_impact_2d, sod_1d, spall_plate_1d, ASPH the
// same decks with method "asph" and stretching_rod_2d). The ghost cost gamma and the slowdown s of
// a core when both work, fitted to the 2- and 4-rank steps of Sedov, the Taylor bar, noh_2d and
// rock_impact_2d: gamma 0.08, 0.21, 0.14, 0.99 and s 1.13, 1.07, 1.30, 1.04; the medians are
// taken. A ghost is cheap because a row sums its own neighbors (gather): a ghost is searched,
// packed and sent, but its pairs are not evaluated for it. A run of the deck itself (--measured,
// --rate) replaces the rate.
struct DefaultCosts {
  double rate, ghost, slowdown;
};
DefaultCosts defaultCosts(bool asph, int dim, bool solid) {
  // [dimension 1, 2 (rz too), 3][hydro, solid]
  static constexpr double sph[3][2] = {{3.1e6, 2.0e6}, {1.1e6, 5.5e5}, {3.5e5, 1.85e5}};
  static constexpr double asphRate[3][2] = {{2.0e6, 1.6e6}, {6.6e5, 5.4e5}, {9.9e4, 9.8e4}};
  const auto d = static_cast<std::size_t>(dim - 1);
  const auto s = static_cast<std::size_t>(solid ? 1 : 0);
  return {asph ? asphRate[d][s] : sph[d][s], 0.2, 1.1};
}
// Two threads on this machine's Taylor bar (resolution 0.7, steps 20-200): 1.86x one thread.
constexpr double kThreadEfficiency = 0.93;
// Collectives of an SPH step (the time step, the skin's check, the balance's cost, the
// history's sums and the finiteness check).
constexpr int kCollectives = 6;

struct Measured {
  double rate = 0.0, bytesOwned = 0.0;
  std::string source;
};

// A run's steady rate from its history.csv: particle-steps (substeps with time bins) per second
// over the second half of its rows, the start-up, the first searches and cuts left out. 0 when
// it has fewer than 10 rows.
double steadyRate(const std::filesystem::path& history) {
  std::ifstream in(history);
  std::string line;
  if (!std::getline(in, line)) return 0.0;
  std::vector<std::string> head;
  for (std::size_t a = 0, b; a <= line.size(); a = b + 1) {
    b = std::min(line.find(',', a), line.size());
    head.push_back(line.substr(a, b - a));
  }
  const auto column = [&](const char* name) {
    return static_cast<int>(std::find(head.begin(), head.end(), name) - head.begin());
  };
  const int step = column("step"), wall = column("wall_seconds"), n = column("particles"),
            sub = column("substeps"), cols = static_cast<int>(head.size());
  if (step == cols || wall == cols || n == cols) return 0.0;
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    std::vector<double> r;
    std::istringstream s(line);
    for (std::string cell; std::getline(s, cell, ',');) r.push_back(std::atof(cell.c_str()));
    if (static_cast<int>(r.size()) == cols) rows.push_back(std::move(r));
  }
  if (rows.size() < 10) return 0.0;
  const std::size_t mid = rows.size() / 2;
  double substeps = 0.0;
  for (std::size_t k = mid + 1; k < rows.size(); ++k) substeps += sub < cols ? rows[k][sub] : 1.0;
  substeps /= static_cast<double>(rows.size() - mid - 1);
  const double seconds = rows.back()[wall] - rows[mid][wall];
  const double steps = rows.back()[step] - rows[mid][step];
  return seconds > 0.0 ? rows.back()[n] * steps * substeps / seconds : 0.0;
}

Measured readMeasured(const std::string& dir, int dimension) {
  Measured m;
  if (dir.empty()) return m;
  const std::filesystem::path path = std::filesystem::path(dir) / "summary.json";
  std::ifstream in(path);
  if (!in) throw UsageError(fmt::format("--measured: cannot read {}", path.string()));
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const std::exception& e) {
    throw UsageError(fmt::format("--measured: {} is not JSON: {}", path.string(), e.what()));
  }
  if (j.value("dimension", 0) != dimension)
    throw UsageError(fmt::format("--measured: {} is a {}D run; the deck is {}D", path.string(),
                                 j.value("dimension", 0), dimension));
  if (j.value("ranks", 0) != 1 || j.value("threads_per_rank", 0) != 1)
    throw UsageError(fmt::format("--measured: {} is a run of {} rank(s) x {} thread(s); the "
                                 "model's rate is one rank's, one thread",
                                 path.string(), j.value("ranks", 0),
                                 j.value("threads_per_rank", 0)));
  m.rate = steadyRate(std::filesystem::path(dir) / "history.csv");
  m.source = fmt::format("{}, steps of the second half", dir);
  if (!(m.rate > 0.0)) {
    m.rate = j.value("particle_steps_per_second_per_core", 0.0);
    m.source = fmt::format("{}, the whole run with its start-up: run 10 steps or more", dir);
  }
  if (!(m.rate > 0.0)) throw UsageError(fmt::format("--measured: {} holds no rate", path.string()));
  if (j.contains("memory_parts")) {
    const auto& p = j["memory_parts"];
    m.bytesOwned = p.value("accounted", 0.0) - p.value("particle_fields", 0.0);
  }
  return m;
}

struct Schema {
  double fieldBytes = 0.0; // every column, a row (owned or ghost)
  double haloBytes = 0.0;  // what a ghost receives an exchange
  int exchanges = 1;       // halo exchanges a step
  double support = 2.0;    // in h, widened by the skin
  bool solid = false;      // some material has strength
};

template <int Dim> Schema schemaOf(const Deck& deck) {
  ParticleStore s;
  ParticleFields<Dim> f;
  auto modules = buildModules<Dim>(deck);
  for (const auto& m : modules) m->registerFields(s, f);
  s.add<std::int32_t>("cost", kCheckpoint);
  const methods::MethodSetup setup = methodSetup(deck);
  materials::MaterialUpdate update(buildMaterials(deck), deck.run.seed);
  std::vector<bool> solid, failedNoTension;
  for (const auto& m : update.materials()) {
    solid.push_back(m.solid());
    failedNoTension.push_back(m.failedCarriesNoTension());
  }
  if (!update.anyDamage()) failedNoTension.clear();
  Schema out;
  out.solid = std::find(solid.begin(), solid.end(), true) != solid.end();
  const auto solver = solvers::makeSolver<Dim>({setup.solver, solid, failedNoTension}, s, f);
  out.fieldBytes = static_cast<double>(s.bytesPerParticle());
  double halo = 0.0, refresh = 0.0;
  for (const auto& c : s.columns()) {
    if (c->info().flags & kHalo) halo += static_cast<double>(c->bytesPerParticle());
    if (c->info().flags & kRefresh) refresh += static_cast<double>(c->bytesPerParticle());
  }
  out.haloBytes = halo;
  if (solver->usesSummationDensity()) out.haloBytes += refresh, ++out.exchanges;
  if (f.B.valid()) out.haloBytes += sizeof(Tensor<3>), ++out.exchanges;
  out.support = solver->support() * (1.0 + setup.solver.neighbor_skin);
  return out;
}

// The model's costs, resolved from the options, a measured run and the defaults.
struct Costs {
  double rate = 0.0, c = 0.0, gamma = 0.0, slowdown = 1.0, eT = 1.0, bytesOwned = 0.0;
  std::string rateFrom;
  bool measuredBytes = false;
};

Costs resolveCosts(const PlanOptions& o, const Schema& schema, bool asph, int dim,
                   double nodesPerH) {
  const Measured measured = readMeasured(o.measured, dim);
  const DefaultCosts defaults = defaultCosts(asph, dim, schema.solid);
  Costs k;
  k.rate = o.costs.rate > 0.0 ? o.costs.rate : measured.rate > 0.0 ? measured.rate : defaults.rate;
  k.rateFrom = o.costs.rate > 0.0 ? "--rate"
               : measured.rate > 0.0
                   ? measured.source
                   : fmt::format("the development machine's, {} {}D {}", asph ? "asph" : "sph", dim,
                                 schema.solid ? "solid" : "hydro");
  k.gamma = o.costs.ghost > 0.0 ? o.costs.ghost : defaults.ghost;
  k.slowdown = o.costs.slowdown > 0.0 ? o.costs.slowdown : defaults.slowdown;
  k.eT = kThreadEfficiency;
  k.c = 1.0 / (k.rate * (o.threads > 1 ? o.threads * k.eT : 1.0));
  // Bytes an owned particle holds beyond its fields: measured, or its neighbor list estimated
  // from the lattice (the wide list's pairs within the widened support of h, 4 B each).
  const double ball = dim == 1 ? 2.0 : dim == 2 ? std::numbers::pi : 4.0 / 3.0 * std::numbers::pi;
  k.measuredBytes = measured.bytesOwned > 0.0;
  k.bytesOwned = k.measuredBytes ? measured.bytesOwned
                                 : 4.0 * ball * std::pow(schema.support * nodesPerH, dim);
  return k;
}

// The particles a run makes at t = 0 (only the fields the generator fills) and how far each
// reaches, as SphMethod::exchangeHalo has it at the first evaluation: the widened support times
// h; ASPH's bounding box of H = I/h (SmoothingTensor) computed the same way.
template <int Dim> struct AtStart {
  std::vector<Vec<Dim>> x, reach;
  std::vector<ParticleId> id;
  std::vector<double> radius;
};

template <int Dim> AtStart<Dim> particlesAtStart(const Deck& deck, double support, bool asph) {
  ParticleStore store;
  ParticleFields<Dim> f;
  f.id = store.add<ParticleId>("id", 0);
  f.x = store.add<Vec<Dim>>("position", 0);
  f.v = store.add<Vec<Dim>>("velocity", 0);
  f.m = store.add<double>("mass", 0);
  f.rho = store.add<double>("density", 0);
  f.e = store.add<double>("specific_internal_energy", 0);
  f.h = store.add<double>("smoothing_length", 0);
  f.material = store.add<std::int32_t>("material", 0);
  f.body = store.add<std::int32_t>("body", 0);
  generateBodies<Dim>(deck, buildMaterials(deck), store, f);
  applyEnergySources<Dim>(deck, store, f); // moves nothing, but refuses what a run refuses
  const std::size_t n = store.localCount();
  if (n == 0) throw UsageError("the deck has no particle at t = 0");
  AtStart<Dim> a;
  a.x.assign(store[f.x].begin(), store[f.x].begin() + static_cast<std::ptrdiff_t>(n));
  a.id.assign(store[f.id].begin(), store[f.id].begin() + static_cast<std::ptrdiff_t>(n));
  a.radius.resize(n);
  a.reach.resize(n);
  const auto h = store[f.h];
  for (std::size_t i = 0; i < n; ++i) {
    a.radius[i] = support * h[i];
    if (asph) {
      const Tensor<Dim> H = Tensor<Dim>::Identity() / h[i];
      a.reach[i] = support * H.inverse().rowwise().norm();
    } else {
      a.reach[i] = Vec<Dim>::Constant(a.radius[i]);
    }
  }
  return a;
}

struct RankModel {
  parallel::VirtualRank r;
  double seconds = 0.0, bytesSent = 0.0, memory = 0.0;
};

struct CountPlan {
  int ranks = 0;
  std::vector<RankModel> per;
  double step = 0.0, efficiency = 1.0;
  std::uint64_t ghosts = 0;
  double cutSeconds = 0.0;
};

// Plan.hpp's model on one cut.
CountPlan modelOf(const std::vector<parallel::VirtualRank>& ranks, const Schema& schema,
                  const Costs& k, const PlanOptions& o) {
  CountPlan p;
  const int R = static_cast<int>(ranks.size());
  p.ranks = R;
  const double collectives =
      R > 1 ? kCollectives * o.costs.latency * std::ceil(std::log2(static_cast<double>(R))) : 0.0;
  double most = 0.0, sum = 0.0;
  for (const auto& r : ranks) {
    RankModel m;
    m.r = r;
    m.bytesSent = static_cast<double>(r.sent) * schema.haloBytes;
    const double messages = static_cast<double>(r.sendsTo + r.receivesFrom);
    m.seconds = (R > 1 ? k.slowdown : 1.0) * k.c *
                    (static_cast<double>(r.owned) + k.gamma * static_cast<double>(r.ghosts)) +
                schema.exchanges * messages * o.costs.latency + m.bytesSent / o.costs.bandwidth +
                collectives;
    m.memory = static_cast<double>(r.owned + r.ghosts) * schema.fieldBytes +
               static_cast<double>(r.owned) * k.bytesOwned;
    most = std::max(most, m.seconds);
    sum += m.seconds;
    p.ghosts += r.ghosts;
    p.per.push_back(m);
  }
  // R ranks on fewer cores share them (oversubscribed ranks yield when they wait).
  const int cores = o.cores > 0 ? std::min(o.cores, R) : R;
  p.step = std::max(most, sum / cores);
  return p;
}

std::string human(double bytes) {
  if (bytes >= 1e9) return fmt::format("{:.2f} GB", bytes / 1e9);
  if (bytes >= 1e6) return fmt::format("{:.1f} MB", bytes / 1e6);
  if (bytes >= 1e3) return fmt::format("{:.1f} kB", bytes / 1e3);
  return fmt::format("{:.0f} B", bytes);
}

void printTables(const std::vector<CountPlan>& plans, std::size_t n, bool perRank) {
  fmt::print("{:>6} {:>11} {:>11} {:>9} {:>8} {:>9} {:>11} {:>11} {:>11} {:>6}\n", "ranks",
             "owned/rank", "ghosts", "g/o max", "nbrs max", "ranks g>o", "sent/step", "memory max",
             "step (s)", "eff");
  for (const auto& p : plans) {
    double goMax = 0.0, sentMax = 0.0, memMax = 0.0;
    std::uint32_t nbMax = 0;
    int over = 0;
    for (const auto& m : p.per) {
      const double go = m.r.owned ? static_cast<double>(m.r.ghosts) / m.r.owned : 0.0;
      goMax = std::max(goMax, go);
      over += m.r.ghosts > m.r.owned;
      sentMax = std::max(sentMax, m.bytesSent);
      memMax = std::max(memMax, m.memory);
      nbMax = std::max(nbMax, m.r.neighbors);
    }
    fmt::print("{:>6} {:>11.0f} {:>11} {:>9.3f} {:>8} {:>9} {:>11} {:>11} {:>11.4g} {:>6.3f}\n",
               p.ranks, static_cast<double>(n) / p.ranks, p.ghosts, goMax, nbMax, over,
               human(sentMax), human(memMax), p.step, p.efficiency);
  }
  // The two thresholds a user sizes a run by, among the rank counts asked for.
  const CountPlan* belowEfficiency = nullptr;
  const CountPlan* ghostsOver = nullptr;
  for (const auto& p : plans) {
    if (!belowEfficiency && p.efficiency < 0.8) belowEfficiency = &p;
    for (const auto& m : p.per)
      if (!ghostsOver && m.r.ghosts > m.r.owned) ghostsOver = &p;
  }
  fmt::print("\nefficiency below 0.8: {}\nghosts more than a rank's own particles: {}\n",
             belowEfficiency
                 ? fmt::format("from {} ranks ({:.0f} particles a rank)", belowEfficiency->ranks,
                               static_cast<double>(n) / belowEfficiency->ranks)
                 : "at none of these rank counts",
             ghostsOver ? fmt::format("from {} ranks ({:.0f} particles a rank)", ghostsOver->ranks,
                                      static_cast<double>(n) / ghostsOver->ranks)
                        : "at none of these rank counts");
  for (const auto& p : plans) {
    if (!(perRank || p.ranks <= 16)) continue;
    fmt::print("\n{} rank{}:\n{:>6} {:>11} {:>9} {:>8} {:>8} {:>8} {:>11} {:>11} {:>11}\n", p.ranks,
               p.ranks > 1 ? "s" : "", "rank", "owned", "ghosts", "sends", "receives", "nbrs",
               "sent/step", "memory", "step (s)");
    for (std::size_t r = 0; r < p.per.size(); ++r) {
      const auto& m = p.per[r];
      fmt::print("{:>6} {:>11} {:>9} {:>8} {:>8} {:>8} {:>11} {:>11} {:>11.4g}\n", r, m.r.owned,
                 m.r.ghosts, m.r.sendsTo, m.r.receivesFrom, m.r.neighbors, human(m.bytesSent),
                 human(m.memory), m.seconds);
    }
  }
}

void writeJson(const std::string& path, nlohmann::json j, const std::vector<CountPlan>& plans) {
  for (const auto& p : plans) {
    nlohmann::json q;
    q["ranks"] = p.ranks;
    q["ghosts"] = p.ghosts;
    q["step_seconds"] = p.step;
    q["efficiency"] = p.efficiency;
    q["cut_seconds"] = p.cutSeconds;
    for (const auto& m : p.per)
      q["per_rank"].push_back({{"owned", m.r.owned},
                               {"ghosts", m.r.ghosts},
                               {"sent", m.r.sent},
                               {"sends_to", m.r.sendsTo},
                               {"receives_from", m.r.receivesFrom},
                               {"neighbors", m.r.neighbors},
                               {"bytes_sent_per_step", m.bytesSent},
                               {"memory_bytes", m.memory},
                               {"step_seconds", m.seconds}});
    j["plans"].push_back(q);
  }
  std::ofstream out(path);
  if (!out) throw UsageError(fmt::format("cannot write {}", path));
  out << j.dump(1) << "\n";
}

template <int Dim> void planDim(const Deck& deck, const PlanOptions& o) {
  if (deck.solver.method == SolverMethod::Mpm)
    throw UsageError("spall plan covers SPH and ASPH decks: MPM's ghosts follow its grid cells "
                     "and its points' domains, which the plan does not model yet");
  const auto t0 = std::chrono::steady_clock::now();
  const Schema schema = schemaOf<Dim>(deck);
  const bool asph = deck.solver.method == SolverMethod::Asph;
  const Costs k = resolveCosts(o, schema, asph, Dim, deck.solver.nodes_per_h);
  const AtStart<Dim> start = particlesAtStart<Dim>(deck, schema.support, asph);
  const std::size_t n = start.x.size();
  parallel::VirtualParticles<Dim> vp;
  vp.x = start.x, vp.id = start.id, vp.reach = start.reach, vp.radius = start.radius;
  vp.round = !asph;
  vp.periodic = methods::sharedSetup(methodSetup(deck)).periodic;
  const bool morton = deck.decomposition.curve == CurveType::Morton;
  vp.curve = morton ? parallel::Curve::Morton : parallel::Curve::Hilbert;
  const parallel::VirtualRanks<Dim> virtualRanks(std::move(vp));
  const double setupSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  // The reference: one rank (with its own periodic images, if any).
  const double serial = modelOf(virtualRanks.cut(1), schema, k, o).step;
  std::vector<CountPlan> plans;
  for (const int R : o.ranks) {
    const auto tc = std::chrono::steady_clock::now();
    const auto ranks = virtualRanks.cut(R);
    const double cut = std::chrono::duration<double>(std::chrono::steady_clock::now() - tc).count();
    plans.push_back(modelOf(ranks, schema, k, o));
    plans.back().cutSeconds = cut;
    plans.back().efficiency = serial / (R * plans.back().step);
  }

  fmt::print("plan: {} | {}D{} | {} | {} curve | {} particles at t = 0\n", o.deckPath, Dim,
             deck.run.geometry == Geometry::RZ ? " rz" : "", methodSummary(deck),
             morton ? "morton" : "hilbert", n);
  fmt::print("reach: {:.3g} h (support x (1 + skin)); fields {:.0f} B a row, a ghost receives "
             "{:.0f} B in {} exchange{} a step\n",
             schema.support, schema.fieldBytes, schema.haloBytes, schema.exchanges,
             schema.exchanges > 1 ? "s" : "");
  fmt::print("costs: {:.3g} particle-steps/s per core ({}), x {:.2f} when every core works, a "
             "ghost {:.2f} of a particle, {:.2g} s a message, {:.3g} B/s, {} collectives a "
             "step{}\n",
             k.rate, k.rateFrom, k.slowdown, k.gamma, o.costs.latency, o.costs.bandwidth,
             kCollectives,
             o.threads > 1 ? fmt::format(", {} threads at {:.2f}", o.threads, k.eT) : "");
  fmt::print("memory: fields x (owned + ghosts) + {:.0f} B an owned particle ({})\n", k.bytesOwned,
             k.measuredBytes ? "measured" : "its neighbor list, estimated");
  fmt::print("built in {:.2f} s\n\n", setupSeconds);
  printTables(plans, n, o.perRank);

  if (o.json.empty()) return;
  nlohmann::json j;
  j["deck"] = o.deckPath;
  j["dimension"] = Dim;
  j["method"] = asph ? "asph" : "sph";
  j["particles"] = n;
  j["reach_in_h"] = schema.support;
  j["field_bytes"] = schema.fieldBytes;
  j["halo_bytes"] = schema.haloBytes;
  j["exchanges_per_step"] = schema.exchanges;
  j["costs"] = {{"rate", k.rate},
                {"rate_from", k.rateFrom},
                {"ghost", k.gamma},
                {"slowdown", k.slowdown},
                {"latency", o.costs.latency},
                {"bandwidth", o.costs.bandwidth},
                {"collectives_per_step", kCollectives},
                {"threads", o.threads},
                {"thread_efficiency", k.eT},
                {"bytes_per_owned_particle", k.bytesOwned}};
  writeJson(o.json, std::move(j), plans);
}

} // namespace

void runPlan(const Deck& deck, const PlanOptions& options, const parallel::MpiContext& mpi) {
  if (mpi.size() > 1) throw UsageError("spall plan runs on one process (its ranks are virtual)");
  if (options.ranks.empty()) throw UsageError("--ranks: give at least one rank count");
  for (int r : options.ranks)
    // 128 boxes of 80 B per rank: 2^16 ranks hold 0.7 GB of them.
    if (r < 1 || r > 1 << 16) throw UsageError(fmt::format("--ranks: {} is not in [1, 65536]", r));
  if (options.threads < 1) throw UsageError("--threads: at least 1");
  if (!(options.costs.latency >= 0.0) || !(options.costs.bandwidth > 0.0) ||
      !(options.costs.rate >= 0.0) || !(options.costs.ghost >= 0.0) ||
      !(options.costs.slowdown >= 0.0))
    throw UsageError(
        "--rate, --ghost-cost, --all-cores-slowdown, --latency and --bandwidth must be positive");
  switch (deck.run.dimension) {
  case 1:
    return planDim<1>(deck, options);
  case 2:
    return planDim<2>(deck, options);
  default:
    return planDim<3>(deck, options);
  }
}

} // namespace spall::app
