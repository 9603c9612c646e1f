// Deck reading: typed values from valid decks, FILE:LINE:COLUMN and messages for each class of bad
// input (docs/reference.md, "Bad input"), --set overrides, and the resolved deck round trip.
#include "spall/io/Deck.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

namespace {

using spall::Deck;
using spall::DeckError;
using spall::loadDeck;

// Line numbers in the comments are the ones the tests below rely on.
const std::string kDeck1D = R"([run]
title = "rod"
dimension = 1
end_time = 12.8e-6

[solver]
kernel = "wendland_c2"
cfl = 0.3
artificial_viscosity = { alpha = 1.5, beta = 3.0, balsara = true }

[[material]]
name = "copper"
density = 8930.0
eos = { type = "mie_gruneisen", c0 = 3940.0, s = 1.49, gamma0 = 2.02 }

[[body]]
name = "striker"
material = "copper"
shape = { type = "box", min = [0.0], max = [0.010] }
spacing = 5.0e-5
velocity = [20.0]

[[body]]
name = "target"
material = "copper"
shape = { type = "box", min = [0.010], max = [0.030] }
spacing = 5.0e-5

[[boundary]]
type = "rigid_wall"
point = [0.0]
normal = [2.0]

[output]
directory = "out/rod"
every = 1.0e-7

[[probe]]
name = "mid"
position = [0.005]
fields = ["pressure"]
)";
// Lines of kDeck1D: 1 [run], 3 dimension, 4 end_time, 6 [solver], 7 kernel, 8 cfl, 9 viscosity,
// 11 [[material]], 13 density, 14 eos, 16 [[body]] striker, 18 material, 19 shape, 20 spacing,
// 21 velocity, 22 (blank), 23 [[body]] target, 24 its name, 29 [[boundary]], 30 type, 31 point,
// 32 normal, 33 (blank), 34 [output], 35 directory, 36 every, 38 [[probe]], 41 fields.

const std::string kDeck2D = R"([run]
dimension = 2
end_time = 1.0e-3
max_steps = 1e6
resolution = 2
seed = 7

[solver]
kernel = "wendland_c4"
density = "normalized_summation"
nodes_per_h = 1.2
h_max = inf

[decomposition]
curve = "morton"
partitioner = "metis"
rebalance_every = 5

[[material]]
name = "gas"
density = 1.0
eos = { type = "ideal_gas", gamma = 1.4 }
strength = { type = "none" }

[[material]]
name = "rock"
density = 2700
eos = { type = "tillotson", a = 0.5, b = 1.3, A = 1.8e10, B = 1.8e10, alpha = 5.0, beta = 5.0, e0 = 1.6e7, e_iv = 3.5e6, e_cv = 1.8e7 }

[[body]]
name = "ball"
material = "rock"
shape = { type = "sphere", center = [0.0, 0.0], radius = 0.1 }
spacing = 0.01
lattice = "hexagonal"
velocity = [1.0, -2.0]
initial_density = 2800.0
initial_pressure = 1.0e5
jitter = 0.1
lattice_transform = [[1.0, 0.5], [0.0, 1.0]]

[[body]]
name = "shell"
material = "gas"
shape = { type = "ring", center = [0.0, 0.0], inner_radius = 0.2, outer_radius = 0.3 }
spacing = 0.01
initial_specific_energy = 2.5
radial_velocity = { center = [0.0, 0.0], speed = -1.0 }
insert_time = 1e-4
allow_overlap = true

[[energy_source]]
center = [0.0, 0.0]
energy = 1.0

[[boundary]]
type = "periodic"
axis = 1
min = -1.0
max = 1.0

[[boundary]]
type = "rigid_wall"
point = [0.0, -1.0]
normal = [0.0, 3.0]

[output]
directory = "out/two"
every_steps = 10
fields = ["position", "density"]
history_every_steps = 5

[checkpoint]
every_steps = 100
every_wall_seconds = 60
keep = 3

[[probe]]
name = "center"
position = [0.0, 0.0]
track = "space"
fields = ["pressure", "velocity_x"]
)";

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

// `text` with its 1-based line `n` replaced (line numbers of the rest do not move).
std::string withLine(const std::string& text, std::size_t n, const std::string& replacement) {
  auto ls = lines(text);
  ls.at(n - 1) = replacement;
  std::string out;
  for (const auto& l : ls) out += l + "\n";
  return out;
}

std::string withLines(std::string text, std::size_t first, std::size_t last,
                      const std::string& replacement = "") {
  for (std::size_t n = first; n <= last; ++n) text = withLine(text, n, replacement);
  return text;
}

// 1-based column of `needle` on that line of the text.
int columnOf(const std::string& text, std::size_t line, const std::string& needle) {
  const std::size_t at = lines(text).at(line - 1).find(needle);
  EXPECT_NE(at, std::string::npos) << needle;
  return static_cast<int>(at) + 1;
}

class DeckTest : public ::testing::Test {
protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::temp_directory_path() /
           ("spall_test_deck_" + std::to_string(::getpid()) + "_" + info->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::string write(const std::string& text, const std::string& name = "deck.toml") {
    const std::string path = (dir_ / name).string();
    std::ofstream(path) << text;
    return path;
  }

  Deck load(const std::string& text, const std::vector<std::string>& overrides = {}) {
    return loadDeck(write(text), overrides);
  }

  // The DeckError loading `text` throws; `file` defaults to the deck path.
  DeckError error(const std::string& text, const std::vector<std::string>& overrides = {}) {
    const std::string path = write(text);
    try {
      loadDeck(path, overrides);
    } catch (const DeckError& e) {
      return e;
    }
    ADD_FAILURE() << "expected a DeckError";
    return DeckError({}, "");
  }

  void expectError(const std::string& text, int line, int column, const std::string& needle,
                   const std::vector<std::string>& overrides = {}) {
    const DeckError e = error(text, overrides);
    EXPECT_EQ(e.where().file, (dir_ / "deck.toml").string());
    EXPECT_EQ(e.where().line, line) << e.what();
    EXPECT_EQ(e.where().column, column) << e.what();
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos)
        << "'" << needle << "' not in: " << e.what();
  }

  // An error from an override: reported at the --set string, line 0.
  void expectOverrideError(const std::string& text, const std::string& override,
                           const std::string& needle) {
    const DeckError e = error(text, {override});
    EXPECT_EQ(e.where().file, "--set " + override);
    EXPECT_EQ(e.where().line, 0);
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos)
        << "'" << needle << "' not in: " << e.what();
  }

  std::filesystem::path dir_;
};

// ---- valid decks ----

TEST_F(DeckTest, Valid1DDeckHasTypedValues) {
  const Deck d = load(kDeck1D);
  EXPECT_EQ(d.run.title, "rod");
  EXPECT_EQ(d.run.dimension, 1);
  EXPECT_DOUBLE_EQ(d.run.end_time, 12.8e-6);
  EXPECT_EQ(d.run.seed, 1u);
  EXPECT_DOUBLE_EQ(d.run.resolution, 1.0);
  EXPECT_EQ(d.solver.method, spall::SolverMethod::Sph);
  EXPECT_EQ(d.solver.kernel, spall::KernelType::WendlandC2);
  EXPECT_EQ(d.solver.density, spall::DensityMethod::Continuity);
  EXPECT_DOUBLE_EQ(d.solver.cfl, 0.3);
  EXPECT_DOUBLE_EQ(d.solver.artificial_viscosity.alpha, 1.5);
  EXPECT_DOUBLE_EQ(d.solver.artificial_viscosity.beta, 3.0);
  EXPECT_TRUE(d.solver.artificial_viscosity.balsara);
  EXPECT_EQ(d.decomposition.curve, spall::CurveType::Hilbert);
  ASSERT_EQ(d.materials.size(), 1u);
  EXPECT_EQ(d.materials[0].name, "copper");
  EXPECT_DOUBLE_EQ(d.materials[0].density, 8930.0);
  const auto& mg = std::get<spall::materials::MieGruneisen>(d.materials[0].eos.model);
  EXPECT_DOUBLE_EQ(mg.C0, 3940.0);
  EXPECT_DOUBLE_EQ(mg.S, 1.49);
  EXPECT_DOUBLE_EQ(mg.Gamma0, 2.02);
  EXPECT_DOUBLE_EQ(mg.rho0, d.materials[0].density); // the material's density
  EXPECT_TRUE(d.materials[0].strength.none());
  ASSERT_EQ(d.bodies.size(), 2u);
  EXPECT_EQ(d.bodies[0].name, "striker");
  EXPECT_EQ(d.bodies[0].material_index, 0);
  EXPECT_EQ(d.bodies[0].shape.type, spall::ShapeType::Box);
  EXPECT_EQ(d.bodies[0].shape.max, std::vector<double>{0.010});
  EXPECT_EQ(d.bodies[0].velocity, std::vector<double>{20.0});
  EXPECT_EQ(d.bodies[1].velocity, std::vector<double>{0.0}); // default: at rest
  EXPECT_EQ(d.bodies[0].lattice, spall::Lattice::Cubic);
  EXPECT_FALSE(d.bodies[0].initial_density.has_value());
  EXPECT_EQ(d.bodies[0].where.line, 16);
  EXPECT_EQ(d.bodies[0].where.column, 1);
  EXPECT_EQ(d.bodies[0].shape.where.line, 19);
  ASSERT_EQ(d.boundaries.size(), 1u);
  EXPECT_EQ(d.boundaries[0].normal, std::vector<double>{1.0}); // normalised
  EXPECT_EQ(d.output.directory, "out/rod");
  EXPECT_DOUBLE_EQ(d.output.every, 1.0e-7);
  EXPECT_EQ(d.output.history_every_steps, 1);
  EXPECT_FALSE(d.checkpoint.has_value());
  ASSERT_EQ(d.probes.size(), 1u);
  EXPECT_EQ(d.probes[0].track, spall::ProbeTrack::Material);
  EXPECT_EQ(d.probes[0].fields, std::vector<std::string>{"pressure"});
  EXPECT_TRUE(d.energy_sources.empty());
}

TEST_F(DeckTest, Valid2DDeckHasTypedValues) {
  const Deck d = load(kDeck2D);
  EXPECT_EQ(d.run.dimension, 2);
  EXPECT_EQ(d.run.max_steps, 1000000);
  EXPECT_DOUBLE_EQ(d.run.resolution, 2.0);
  EXPECT_EQ(d.run.seed, 7u);
  EXPECT_EQ(d.solver.kernel, spall::KernelType::WendlandC4);
  EXPECT_EQ(d.solver.density, spall::DensityMethod::NormalizedSummation);
  EXPECT_DOUBLE_EQ(d.solver.nodes_per_h, 1.2);
  EXPECT_TRUE(std::isinf(d.solver.h_max));
  EXPECT_EQ(d.decomposition.curve, spall::CurveType::Morton);
  EXPECT_EQ(d.decomposition.partitioner, spall::Partitioner::Metis);
  EXPECT_EQ(d.decomposition.rebalance_every, 5);
  ASSERT_EQ(d.materials.size(), 2u);
  EXPECT_DOUBLE_EQ(std::get<spall::materials::IdealGas>(d.materials[0].eos.model).gamma, 1.4);
  EXPECT_DOUBLE_EQ(d.materials[1].density, 2700.0);
  const auto& tillotson = std::get<spall::materials::Tillotson>(d.materials[1].eos.model);
  EXPECT_DOUBLE_EQ(tillotson.A, 1.8e10);
  EXPECT_DOUBLE_EQ(tillotson.Ecv, 1.8e7);
  const auto& ball = d.bodies.at(0);
  EXPECT_EQ(ball.material_index, 1);
  EXPECT_EQ(ball.shape.center, (std::vector<double>{0.0, 0.0}));
  EXPECT_DOUBLE_EQ(ball.shape.radius, 0.1);
  EXPECT_EQ(ball.lattice, spall::Lattice::Hexagonal);
  EXPECT_EQ(ball.velocity, (std::vector<double>{1.0, -2.0}));
  EXPECT_DOUBLE_EQ(*ball.initial_density, 2800.0);
  EXPECT_DOUBLE_EQ(*ball.initial_pressure, 1.0e5);
  EXPECT_FALSE(ball.initial_specific_energy.has_value());
  EXPECT_DOUBLE_EQ(ball.jitter, 0.1);
  ASSERT_TRUE(ball.lattice_transform.has_value());
  EXPECT_DOUBLE_EQ((*ball.lattice_transform)[0][1], 0.5);
  const auto& shell = d.bodies.at(1);
  EXPECT_EQ(shell.material_index, 0);
  EXPECT_EQ(shell.shape.type, spall::ShapeType::Ring);
  EXPECT_DOUBLE_EQ(shell.shape.inner_radius, 0.2);
  EXPECT_DOUBLE_EQ(shell.shape.outer_radius, 0.3);
  EXPECT_DOUBLE_EQ(*shell.initial_specific_energy, 2.5);
  ASSERT_TRUE(shell.radial_velocity.has_value());
  EXPECT_DOUBLE_EQ(shell.radial_velocity->speed, -1.0);
  EXPECT_DOUBLE_EQ(shell.insert_time, 1e-4);
  EXPECT_TRUE(shell.allow_overlap);
  ASSERT_EQ(d.energy_sources.size(), 1u);
  EXPECT_DOUBLE_EQ(d.energy_sources[0].radius, 0.0);
  EXPECT_DOUBLE_EQ(d.energy_sources[0].energy, 1.0);
  ASSERT_EQ(d.boundaries.size(), 2u);
  EXPECT_EQ(d.boundaries[0].axis, 1);
  EXPECT_DOUBLE_EQ(d.boundaries[0].min, -1.0);
  EXPECT_EQ(d.boundaries[1].normal, (std::vector<double>{0.0, 1.0}));
  EXPECT_EQ(d.output.every_steps, 10);
  EXPECT_EQ(d.output.fields, (std::vector<std::string>{"position", "density"}));
  EXPECT_EQ(d.output.history_every_steps, 5);
  ASSERT_TRUE(d.checkpoint.has_value());
  EXPECT_EQ(d.checkpoint->keep, 3);
  EXPECT_DOUBLE_EQ(d.checkpoint->every_wall_seconds, 60.0);
  EXPECT_EQ(d.probes.at(0).track, spall::ProbeTrack::Space);
}

TEST_F(DeckTest, Valid3DCylinder) {
  const std::string deck = R"([run]
dimension = 3
end_time = 1
[[material]]
name = "al"
density = 2700
eos = { type = "linear", bulk_modulus = 7.6e10 }
[[body]]
name = "rod"
material = "al"
shape = { type = "cylinder", base = [0, 0, 0], axis = [0, 0, 2], radius = 0.01, length = 0.1 }
spacing = 1e-3
[output]
directory = "out"
)";
  const Deck d = load(deck);
  EXPECT_EQ(d.bodies[0].shape.axis, (std::vector<double>{0.0, 0.0, 2.0}));
  EXPECT_DOUBLE_EQ(d.bodies[0].shape.length, 0.1);
  EXPECT_DOUBLE_EQ(std::get<spall::materials::LinearEos>(d.materials[0].eos.model).K, 7.6e10);
  EXPECT_EQ(d.bodies[0].velocity, (std::vector<double>{0.0, 0.0, 0.0}));
}

TEST_F(DeckTest, IntegersAreAcceptedAsFloats) {
  const Deck d = load(withLine(kDeck1D, 4, "end_time = 2"));
  EXPECT_DOUBLE_EQ(d.run.end_time, 2.0);
}

// ---- syntax, files, structure ----

TEST_F(DeckTest, TomlSyntaxErrorHasItsPosition) {
  const DeckError e = error(withLine(kDeck1D, 13, "density = "));
  EXPECT_EQ(e.where().line, 13);
  EXPECT_GT(e.where().column, 0);
}

TEST_F(DeckTest, MissingFileIsADeckError) {
  EXPECT_THROW(loadDeck((dir_ / "nope.toml").string()), DeckError);
}

TEST_F(DeckTest, MissingRunTable) {
  expectError(withLines(kDeck1D, 1, 4), 1, 1, "[run]");
}

TEST_F(DeckTest, MissingOutputTable) {
  expectError(withLines(kDeck1D, 34, 36), 1, 1, "[output]");
}

TEST_F(DeckTest, MissingMaterials) {
  expectError(withLines(kDeck1D, 11, 14), 1, 1, "[[material]]");
}

TEST_F(DeckTest, MaterialWrittenAsSingleTable) {
  expectError(withLine(kDeck1D, 11, "[material]"), 11, 1, "'material' must be an array of tables");
}

// ---- unknown keys ----

TEST_F(DeckTest, UnknownBodyKeySuggestsTheKnownOne) {
  const std::string deck = withLine(kDeck1D, 21, "velocty = [20.0]");
  expectError(deck, 21, 1, "unknown key 'velocty' in body 'striker' (did you mean 'velocity'?)");
}

TEST_F(DeckTest, UnknownTopLevelTableSuggestsSingular) {
  expectError(withLine(kDeck1D, 23, "[[bodies]]"), 23, 3,
              "unknown top-level key 'bodies' (did you mean 'body'?)");
}

TEST_F(DeckTest, UnknownKeyInInlineTable) {
  const std::string deck =
      withLine(kDeck1D, 9, "artificial_viscosity = { alpah = 1.5, beta = 3.0, balsara = true }");
  expectError(deck, 9, 26,
              "unknown key 'alpah' in the artificial_viscosity of [solver] (did you "
              "mean 'alpha'?)");
}

TEST_F(DeckTest, UnknownKeyFarFromAllHasNoSuggestion) {
  const DeckError e = error(withLine(kDeck1D, 36, "zzzzzzzz = 1"));
  EXPECT_EQ(e.where().line, 36);
  EXPECT_NE(std::string(e.what()).find("unknown key 'zzzzzzzz' in [output]"), std::string::npos);
  EXPECT_EQ(std::string(e.what()).find("did you mean"), std::string::npos);
}

TEST_F(DeckTest, FirstUnknownKeyInDeckOrderIsReported) {
  // Keys are stored sorted; the report must still follow the deck.
  std::string deck = withLine(kDeck1D, 21, "zeta = 1");
  deck = withLine(deck, 22, "alpha_x = 2");
  expectError(deck, 21, 1, "'zeta'");
}

TEST_F(DeckTest, EosKeyOfAnotherTypeIsUnknown) {
  const std::string line = R"(eos = { type = "linear", bulk_modulus = 1.4e11, c0 = 3940.0 })";
  expectError(withLine(kDeck1D, 14, line), 14, columnOf(line + "\n", 1, "c0"),
              "unknown key 'c0' in the eos of material 'copper' (eos type 'linear' takes: "
              "bulk_modulus, min_pressure)");
}

// ---- damage and erosion ----

namespace {
const std::string kElastic = "strength = { type = \"elastic\", shear_modulus = 47.7e9 }\n";
const std::string kFlaws = "damage = { type = \"grady_kipp\", weibull_k = 1e35, weibull_m = 9.0 }";
} // namespace

TEST_F(DeckTest, DamageNeedsStrength) {
  expectError(withLine(kDeck1D, 15, kFlaws), 15, 10, "this material has none");
}

TEST_F(DeckTest, DamageTypesAndTheirKeys) {
  const auto at = [&](const std::string& text, const std::string& needle, const std::string& what) {
    expectError(text, 16, columnOf(text, 16, needle), what);
  };
  std::string t =
      withLine(kDeck1D, 15, kElastic + "damage = { type = \"grady_kipp\", weibull_m = 9.0 }");
  at(t, "{ type", "weibull_k");
  t = withLine(kDeck1D, 15,
               kElastic + "damage = { type = \"grady_kipp\", weibull_k = 1e35, "
                          "weibull_m = 9.0, mode = \"tensorial\" }");
  at(t, "\"tensorial\"", "tensor");
  t = withLine(kDeck1D, 15,
               kElastic + "damage = { type = \"johnson_cook\", D1 = 0.05, D2 = 3.44, "
                          "D3 = -2.12, D4 = 0.002, D5 = 0.61, reference_strain_rate = "
                          "1.0, room_temperature = 293.0, melt_temperature = 1793.0 }");
  at(t, "{ type", "use von_mises, johnson_cook or zerilli_armstrong");
  t = withLine(kDeck1D, 15,
               kElastic + "damage = { type = \"grady_kipp\", weibull_k = 1e35, "
                          "weibull_m = 9.0, crack_speed = 1.5 }");
  at(t, "1.5", "crack_speed");
}

TEST_F(DeckTest, JohnsonCookStrainRateIsPlasticOrTotal) {
  const std::string jc = "strength = { type = \"johnson_cook\", shear_modulus = 46e9, A = 90e6, "
                         "B = 292e6, n = 0.31, C = 0.025, m = 1.09, reference_strain_rate = 1.0, "
                         "room_temperature = 294.0, melt_temperature = 1356.0, specific_heat = "
                         "383.0, taylor_quinney = 0.9";
  const std::string bad = withLine(kDeck1D, 15, jc + ", strain_rate = \"elastic\" }");
  expectError(bad, 15, columnOf(bad, 15, "\"elastic\""), "plastic");
  const auto plasticRate = [&](const std::string& deck) {
    return std::get<spall::materials::JohnsonCook>(load(deck).materials[0].strength.model)
        .plasticRate;
  };
  EXPECT_TRUE(plasticRate(withLine(kDeck1D, 15, jc + " }")));
  EXPECT_FALSE(plasticRate(withLine(kDeck1D, 15, jc + ", strain_rate = \"total\" }")));
}

// Zerilli-Armstrong: the constants default to 0 (an fcc metal gives C0, C2, C3, C4), none
// negative, some stress to yield at; the temperature is absolute and required; Johnson-Cook's
// keys are not its keys.
TEST_F(DeckTest, ZerilliArmstrongConstants) {
  const std::string za = "strength = { type = \"zerilli_armstrong\", shear_modulus = 46e9, "
                         "room_temperature = 294.0, specific_heat = 383.0, taylor_quinney = 0.9";
  const Deck d =
      load(withLine(kDeck1D, 15, za + ", C0 = 65e6, C2 = 890e6, C3 = 0.0028, C4 = 0.000115 }"));
  EXPECT_TRUE(d.materials[0].strength.tracksTemperature());
  const auto& c = std::get<spall::materials::ZerilliArmstrong>(d.materials[0].strength.model);
  EXPECT_EQ(c.C0, 65e6);
  EXPECT_EQ(c.C1, 0.0);
  EXPECT_EQ(c.C2, 890e6);
  EXPECT_EQ(c.C4, 0.000115);
  EXPECT_EQ(c.C5, 0.0);
  EXPECT_EQ(c.n, 1.0);
  EXPECT_EQ(c.rate0, 1.0);
  std::string bad = withLine(kDeck1D, 15, za + ", C0 = 65e6, C2 = -890e6 }");
  expectError(bad, 15, columnOf(bad, 15, "-890e6"), "C2");
  bad = withLine(kDeck1D, 15, za + ", C0 = 65e6, C4 = 0.5 }");
  expectError(bad, 15, columnOf(bad, 15, "0.5"), "C4");
  bad = withLine(kDeck1D, 15, za + ", C0 = 65e6, n = 0 }");
  expectError(bad, 15, columnOf(bad, 15, "n = 0") + 4, "n");
  bad = withLine(kDeck1D, 15, za + ", C0 = 65e6, melt_temperature = 1356.0 }");
  expectError(bad, 15, columnOf(bad, 15, "melt_temperature"), "melt_temperature");
  bad = withLine(kDeck1D, 15, za + ", C3 = 0.0028 }");
  expectError(bad, 15, columnOf(bad, 15, "{ type"), "no stress to yield at");
  bad = withLine(kDeck1D, 15, za + ", C0 = 65e6, strain_rate = \"total\" }");
  expectError(bad, 15, columnOf(bad, 15, "strain_rate"), "strain_rate");
  bad = withLine(kDeck1D, 15,
                 "strength = { type = \"zerilli_armstrong\", shear_modulus = 46e9, C0 = 65e6, "
                 "specific_heat = 383.0, taylor_quinney = 0.9 }");
  expectError(bad, 15, columnOf(bad, 15, "{ type"), "room_temperature");
}

TEST_F(DeckTest, ErosionNeedsDamageAndAKnownOption) {
  expectError(withLine(kDeck1D, 15, kElastic + "erosion = \"no_tension\""), 16, 11,
              "has no damage");
  expectError(withLine(kDeck1D, 15, kElastic + kFlaws + "\nerosion = \"remove_mass\""), 17, 11,
              "zero_stress");
  const Deck d = load(withLine(kDeck1D, 15, kElastic + kFlaws + "\nerosion = \"zero_stress\""));
  const auto& flaws = std::get<spall::materials::GradyKipp>(d.materials[0].damage.model);
  EXPECT_EQ(flaws.k, 1e35);
  EXPECT_EQ(flaws.crackSpeed, 0.4);
  EXPECT_EQ(d.materials[0].erosion, spall::materials::Erosion::ZeroStress);
}

TEST_F(DeckTest, FragmentsLinkWithinTheKernelSupport) {
  const DeckError e = error(kDeck1D + "\n[fragments]\nlink_length = 4.0\n");
  EXPECT_NE(std::string(e.what()).find("link_length"), std::string::npos) << e.what();
  const Deck d = load(kDeck1D + "\n[fragments]\ndamage_threshold = 0.9\n");
  ASSERT_TRUE(d.fragments.has_value());
  EXPECT_EQ(d.fragments->link_length, 1.5);
  EXPECT_EQ(d.fragments->damage_threshold, 0.9);
}

// ---- types ----

TEST_F(DeckTest, WrongTypeNamesKeyAndTypes) {
  expectError(withLine(kDeck1D, 4, "end_time = \"soon\""), 4, 12,
              "'run.end_time' must be a number, got string");
}

TEST_F(DeckTest, FloatWhereIntegerExpected) {
  expectError(withLine(kDeck1D, 3, "dimension = 1.5"), 3, 13,
              "'run.dimension' must be an integer, got 1.5");
}

TEST_F(DeckTest, VectorNeedsOneEntryPerDimension) {
  expectError(withLine(kDeck1D, 21, "velocity = [1.0, 2.0]"), 21, 12,
              "'body.striker.velocity' must have 1 entry");
}

TEST_F(DeckTest, VectorEntryOfWrongTypeIsReportedAtTheEntry) {
  expectError(withLine(kDeck1D, 21, "velocity = [\"fast\"]"), 21, 13,
              "'body.striker.velocity' must be a number, got string");
}

TEST_F(DeckTest, LatticeTransformMustBeSquare) {
  expectError(withLine(kDeck1D, 22, "lattice_transform = [[1.0, 0.0]]"), 22, 22,
              "'body.striker.lattice_transform' must be a 1 x 1 array");
}

TEST_F(DeckTest, LatticeTransformMustBeInvertible) {
  expectError(withLine(kDeck1D, 22, "lattice_transform = [[0.0]]"), 22, 21,
              "'body.striker.lattice_transform' must be invertible");
}

// ---- missing keys ----

TEST_F(DeckTest, MissingBodyKeyIsReportedAtTheBody) {
  expectError(withLine(kDeck1D, 20, ""), 16, 1, "missing required key 'spacing' in body 'striker'");
}

TEST_F(DeckTest, MissingEosParameterIsReportedAtTheEos) {
  const std::string line = R"(eos = { type = "mie_gruneisen", s = 1.49, gamma0 = 2.02 })";
  expectError(withLine(kDeck1D, 14, line), 14, 7,
              "missing required key 'c0' in the eos of material 'copper'");
}

TEST_F(DeckTest, ProbeNeedsFields) {
  expectError(withLine(kDeck1D, 41, ""), 38, 1, "missing required key 'fields' in probe 'mid'");
}

// ---- enumerations ----

TEST_F(DeckTest, DimensionMustBeOneTwoOrThree) {
  expectError(withLine(kDeck1D, 3, "dimension = 4"), 3, 13,
              "'run.dimension' must be in [1, 3], got 4");
}

TEST_F(DeckTest, UnknownKernelSuggestsTheNearest) {
  expectError(withLine(kDeck1D, 7, "kernel = \"cubic_splin\""), 7, 10,
              "'solver.kernel' must be one of cubic_spline, wendland_c2, wendland_c4, got "
              "'cubic_splin' (did you mean 'cubic_spline'?)");
}

TEST_F(DeckTest, MpmTakesItsTableAndRefusesWhatItCannotDoYet) {
  // Lines 7-9 of kDeck1D are the solver's kernel, cfl and viscosity (ignored by MPM).
  const Deck d =
      load(withLine(kDeck1D, 7, "method = \"mpm\"\nmpm = { shape = \"linear\", flip = 0.5 }"));
  EXPECT_EQ(d.solver.method, spall::SolverMethod::Mpm);
  EXPECT_EQ(d.solver.mpm.shape, spall::MpmShape::Linear);
  EXPECT_EQ(d.solver.mpm.flip, 0.5);
  EXPECT_EQ(load(withLine(kDeck1D, 7, "method = \"mpm\"")).solver.mpm.shape,
            spall::MpmShape::CpGimp);
  expectError(withLine(kDeck1D, 7, "mpm = { flip = 0.5 }"), 7, 7, "set method = \"mpm\"");
  EXPECT_EQ(
      load(withLine(kDeck1D, 7, "method = \"mpm\"\nmpm = { shape = \"cpdi\" }")).solver.mpm.shape,
      spall::MpmShape::Cpdi);
  EXPECT_EQ(
      load(withLine(kDeck1D, 7, "method = \"mpm\"\nmpm = { shape = \"gimp\" }")).solver.mpm.shape,
      spall::MpmShape::Gimp);
  expectError(withLine(kDeck1D, 7, "method = \"mpm\"\nmpm = { shape = \"bspline\" }"), 8, 17,
              "linear, gimp, cpgimp, cpdi");
  expectError(withLine(kDeck1D, 7, "method = \"mpm\"\nmpm = { flip = 1.5 }"), 8, 16, "in [0, 1]");
  // The transfer: FLIP (the blend) by default, or APIC, which no flip blends (flip = 1 is
  // FLIP's default, harmless in a deck that switches to APIC with --set).
  EXPECT_EQ(load(withLine(kDeck1D, 7, "method = \"mpm\"")).solver.mpm.transfer,
            spall::MpmTransfer::Flip);
  EXPECT_EQ(
      load(withLine(kDeck1D, 7, "method = \"mpm\"\nmpm = { transfer = \"apic\", flip = 1.0 }"))
          .solver.mpm.transfer,
      spall::MpmTransfer::Apic);
  expectError(withLine(kDeck1D, 7, "method = \"mpm\"\nmpm = { transfer = \"apic\", flip = 0.9 }"),
              8, 35, "transfer = \"apic\" is neither");
  expectError(withLine(kDeck1D, 7, "method = \"mpm\"\nmpm = { transfer = \"pic\" }"), 8, 20,
              "flip, apic");
  {
    const auto q = load(withLine(kDeck1D, 7,
                                 "method = \"mpm\"\nmpm = { viscosity = { linear = 0.2, "
                                 "quadratic = 2.0 } }"))
                       .solver.mpm;
    EXPECT_EQ(q.viscosity_linear, 0.2);
    EXPECT_EQ(q.viscosity_quadratic, 2.0);
    EXPECT_TRUE(q.viscous());
    EXPECT_FALSE(load(withLine(kDeck1D, 7, "method = \"mpm\"")).solver.mpm.viscous());
  }
  expectError(withLine(kDeck1D, 7, "method = \"mpm\"\nmpm = { viscosity = { linear = -0.1 } }"), 8,
              32, ">= 0");
  expectError(withLine(kDeck1D, 7, "method = \"mpm\"\nmpm = { viscosity = { cubic = 1.0 } }"), 8,
              23, "cubic");
  expectError(withLine(kDeck1D, 7, "method = \"mpm\"\nmpm = { cell_size = -1.0 }"), 8, 21, ">= 0");
  // Contact: one velocity field per body (frictionless) is MPM's too.
  EXPECT_EQ(
      load(withLine(kDeck1D, 7, "method = \"mpm\"\ncontact = \"frictionless\"")).solver.contact,
      spall::Contact::Frictionless);
  // ... and Coulomb friction between the fields, MPM's only, with its coefficient and only then.
  const auto friction =
      load(withLine(kDeck1D, 7,
                    "method = \"mpm\"\ncontact = \"friction\"\nmpm = { friction = 0.3 }"))
          .solver;
  EXPECT_EQ(friction.contact, spall::Contact::Friction);
  EXPECT_EQ(friction.mpm.friction, 0.3);
  expectError(withLine(kDeck1D, 7, "contact = \"friction\""), 7, 11, "material point method's");
  expectError(withLine(kDeck1D, 7, "method = \"mpm\"\ncontact = \"friction\""), 8, 11,
              "set [solver.mpm] friction");
  expectError(withLine(kDeck1D, 7,
                       "method = \"mpm\"\ncontact = \"frictionless\"\nmpm = { friction = 0.3 }"),
              9, 20, "set solver.contact = \"friction\"");
  expectError(
      withLine(kDeck1D, 7, "method = \"mpm\"\ncontact = \"friction\"\nmpm = { friction = -0.1 }"),
      9, 20, ">= 0");
  // ... and a rigid wall's friction, MPM's only (SPH's wall is a mirror).
  const std::string rubbing = withLine(kDeck1D, 32, "normal = [2.0]\nfriction = 0.2");
  EXPECT_EQ(load(withLine(rubbing, 7, "method = \"mpm\"")).boundaries[0].friction, 0.2);
  expectError(rubbing, 33, 12, "material point method's");
  // ... and fixed bodies (their grid nodes move at their velocity).
  EXPECT_TRUE(
      load(withLine(withLine(kDeck1D, 7, "method = \"mpm\""), 22, "fixed = true")).bodies[0].fixed);
}

TEST_F(DeckTest, StrengthModelsNeedTheirParameters) {
  expectError(withLine(kDeck1D, 15, "strength = { type = \"cap\", shear_modulus = 1.0e10 }"), 15,
              12, "missing required key 'bulk_modulus'");
  // A cap material computes its whole stress: the material's eos (line 14) is an error.
  expectError(withLine(kDeck1D, 15,
                       "strength = { type = \"cap\", bulk_modulus = 1e10, shear_modulus = 1e10, "
                       "peak_i1 = 1e6, f_slope = 0.4, cap_ratio = 5.0, crush_p0 = -1e7, "
                       "crush_p1 = 1e-10, crush_p3 = 0.1 }"),
              14, 7, "remove 'eos'");
  expectError(withLine(kDeck1D, 15,
                       "strength = { type = \"cap\", bulk_modulus = 1e10, shear_modulus = 1e10, "
                       "peak_i1 = 1e6, f_slope = 0.4, cap_ratio = 5.0, crush_p0 = 1e7, "
                       "crush_p1 = 1e-10, crush_p3 = 0.1 }"),
              15, 129, "'material.copper.strength.crush_p0' must be < 0");
  expectError(withLine(kDeck1D, 15,
                       "strength = { type = \"von_mises\", shear_modulus = 4.5e10, "
                       "yield_stress = -1.0 }"),
              15, 73, "yield_stress");
  expectError(withLine(kDeck1D, 15,
                       "strength = { type = \"elastic\", shear_modulus = 4.5e10, yield = 1.0 }"),
              15, 56, "unknown key 'yield'");
}

TEST_F(DeckTest, PorosityIsCheckedAtItsKeys) {
  const std::string ok = "porosity = { type = \"p_alpha\", alpha0 = 1.5, elastic_pressure = 1e6, "
                         "solid_pressure = 1e9";
  const Deck deck = load(withLine(kDeck1D, 15, ok + " }"));
  EXPECT_EQ(deck.materials[0].porosity.type, spall::PorosityType::PAlpha);
  EXPECT_EQ(deck.materials[0].porosity.exponent, 2.0); // the default
  expectError(withLine(kDeck1D, 15,
                       "porosity = { type = \"p_alpha\", alpha0 = 0.5, elastic_pressure = 1e6, "
                       "solid_pressure = 1e9 }"),
              15, 41, "'material.copper.porosity.alpha0' must be >= 1");
  expectError(withLine(kDeck1D, 15, ok + ", transition_pressure = 1e8 }"), 15, 114,
              "'alpha_transition' is missing");
  expectError(withLine(kDeck1D, 15,
                       ok + ", transition_pressure = 1e8, alpha_transition = 1.5, "
                            "exponent_transition = 1.0 }"),
              15, 138, "alpha_transition");
  EXPECT_EQ(load(withLine(kDeck1D, 15, ok + ", elastic_sound_speed = 1500.0 }"))
                .materials[0]
                .porosity.elastic_sound_speed,
            1500.0);
  expectError(withLine(kDeck1D, 15, ok + ", elastic_sound_speed = -1500.0 }"), 15, 114,
              "'material.copper.porosity.elastic_sound_speed' must be > 0");
  expectError(withLine(kDeck1D, 15,
                       "porosity = { type = \"p_alpha\", alpha0 = 1.0, elastic_pressure = 1e6, "
                       "solid_pressure = 1e9, elastic_sound_speed = 1500.0 }"),
              15, 114, "alpha0 = 1 is not porous");
  // A cap material has its own porosity (checked after its eos: line 14 goes).
  expectError(withLine(withLine(kDeck1D, 14, ok + " }"), 15,
                       "strength = { type = \"cap\", bulk_modulus = 1e10, shear_modulus = 1e10, "
                       "peak_i1 = 1e6, f_slope = 0.4, cap_ratio = 5.0, crush_p0 = -1e7, "
                       "crush_p1 = 1e-10, crush_p3 = 0.1 }"),
              14, 12, "carries its own porosity");
  expectError(withLine(kDeck1D, 15, "porosity = 2.0"), 15, 12,
              "'material.copper.porosity' must be a table");
}

TEST_F(DeckTest, CylinderIs3DOnlyAndRingIs2DOnly) {
  std::string line =
      R"(shape = { type = "cylinder", base = [0.0], axis = [1.0], radius = 1.0, length = 1.0 })";
  expectError(withLine(kDeck1D, 19, line), 19, 18, "shape 'cylinder' is 3D only");
  line = R"(shape = { type = "ring", center = [0.0], inner_radius = 0.1, outer_radius = 0.2 })";
  expectError(withLine(kDeck1D, 19, line), 19, 18, "shape 'ring' is 2D only");
}

// ---- physically impossible values ----

TEST_F(DeckTest, NonPositiveEndTime) {
  expectError(withLine(kDeck1D, 4, "end_time = 0"), 4, 12, "'run.end_time' must be > 0 (s), got 0");
}

TEST_F(DeckTest, NonPositiveMaterialDensity) {
  expectError(withLine(kDeck1D, 13, "density = -8930.0"), 13, 11,
              "'material.copper.density' must be > 0 (kg/m^3), got -8930");
}

TEST_F(DeckTest, NonPositiveSpacing) {
  expectError(withLine(kDeck1D, 27, "spacing = 0.0"), 27, 11, "'body.target.spacing' must be > 0");
}

TEST_F(DeckTest, CflOutsideZeroOne) {
  expectError(withLine(kDeck1D, 8, "cfl = 0.0"), 8, 7, "'solver.cfl' must be > 0, got 0");
  expectError(withLine(kDeck1D, 8, "cfl = 1.5"), 8, 7, "'solver.cfl' must be in (0, 1] (above 1");
  EXPECT_DOUBLE_EQ(load(withLine(kDeck1D, 8, "cfl = 1")).solver.cfl, 1.0);
  // A stability test asks for an unstable cfl explicitly; 10 is still the limit.
  EXPECT_DOUBLE_EQ(load(withLine(kDeck1D, 8, "cfl = 5\nallow_unstable_cfl = true")).solver.cfl,
                   5.0);
  expectError(withLine(kDeck1D, 8, "allow_unstable_cfl = true\ncfl = 50"), 9, 7,
              "'solver.cfl' must be in (0, 10]");
}

TEST_F(DeckTest, IdealGasGammaAboveOne) {
  const std::string line = R"(eos = { type = "ideal_gas", gamma = 1.0 })";
  expectError(withLine(kDeck1D, 14, line), 14, columnOf(line + "\n", 1, "1.0"),
              "'material.copper.eos.gamma' must be > 1");
}

TEST_F(DeckTest, BoxMinMustBeBelowMax) {
  const std::string line = R"(shape = { type = "box", min = [0.0], max = [0.0] })";
  expectError(withLine(kDeck1D, 19, line), 19, columnOf(line + "\n", 1, "[0.0] }"),
              "'body.striker.shape.max' must exceed min on every axis");
}

TEST_F(DeckTest, RingInnerRadiusBelowOuter) {
  // kDeck2D line 45 is the shell's shape.
  const std::string line =
      R"(shape = { type = "ring", center = [0.0, 0.0], inner_radius = 0.3, outer_radius = 0.3 })";
  ASSERT_NE(lines(kDeck2D).at(44).find("ring"), std::string::npos);
  expectError(withLine(kDeck2D, 45, line), 45, columnOf(line + "\n", 1, "0.3 }"),
              "'body.shell.shape.outer_radius' must be > inner_radius, inner_radius = 0.3 (m)");
}

TEST_F(DeckTest, ZeroWallNormal) {
  expectError(withLine(kDeck1D, 32, "normal = [0.0]"), 32, 10,
              "'boundary.1.normal' must not be the zero vector");
}

TEST_F(DeckTest, PeriodicAxisAndRange) {
  std::string deck = withLine(kDeck1D, 30, "type = \"periodic\"");
  deck = withLine(deck, 31, "axis = 1");
  deck = withLine(deck, 32, "min = 0.0");
  deck = withLine(deck, 33, "max = 1.0");
  expectError(deck, 31, 8, "'boundary.1.axis' must be in [0, dimension - 1], dimension - 1 = 0");
  deck = withLine(deck, 31, "axis = 0");
  deck = withLine(deck, 33, "max = 0.0");
  expectError(deck, 33, 7, "'boundary.1.max' must be > min, min = 0 (m)");
}

TEST_F(DeckTest, JitterBelowHalf) {
  expectError(withLine(kDeck1D, 22, "jitter = 0.5"), 22, 10,
              "'body.striker.jitter' must be in [0, 0.5)");
}

TEST_F(DeckTest, InitialEnergyWithInitialPressureIsAmbiguous) {
  std::string deck = withLine(kDeck1D, 21, "initial_specific_energy = 1.0");
  deck = withLine(deck, 22, "initial_pressure = 1.0e5");
  expectError(deck, 22, 20, "cannot be combined with initial_specific_energy");
  // initial_density with initial_pressure is fine.
  deck = withLine(deck, 21, "initial_density = 9000.0");
  EXPECT_DOUBLE_EQ(*load(deck).bodies[0].initial_pressure, 1.0e5);
}

TEST_F(DeckTest, NegativeEnergySource) {
  const std::string deck = kDeck1D + "[[energy_source]]\ncenter = [0.0]\nenergy = -1.0\n";
  expectError(deck, 44, 10, "'energy_source.1.energy' must be >= 0");
}

TEST_F(DeckTest, CheckpointKeepAtLeastOne) {
  const std::string deck = kDeck1D + "[checkpoint]\nkeep = 0\n";
  expectError(deck, 43, 8, "'checkpoint.keep' must be >= 1");
}

TEST_F(DeckTest, NegativeOutputInterval) {
  expectError(withLine(kDeck1D, 36, "every = -1.0"), 36, 9, "'output.every' must be >= 0");
}

TEST_F(DeckTest, BodyWithUnknownMaterial) {
  expectError(withLine(kDeck1D, 18, "material = \"coper\""), 18, 12,
              "names no [[material]]: 'coper' (did you mean 'copper'?)");
}

TEST_F(DeckTest, DuplicateBodyName) {
  expectError(withLine(kDeck1D, 24, "name = \"striker\""), 24, 8,
              "duplicate body name 'striker' (first at line 17)");
}

// ---- overrides ----

TEST_F(DeckTest, OverrideScalar) {
  const Deck d = load(kDeck1D, {"run.end_time=2e-6"});
  EXPECT_DOUBLE_EQ(d.run.end_time, 2e-6);
}

TEST_F(DeckTest, OverrideArrayOfNamedBody) {
  const Deck d = load(kDeck1D, {"body.striker.velocity=[30.0]", "body.target.spacing = 1e-4"});
  EXPECT_EQ(d.bodies[0].velocity, std::vector<double>{30.0});
  EXPECT_DOUBLE_EQ(d.bodies[1].spacing, 1e-4);
}

TEST_F(DeckTest, OverrideNestedInNamedMaterial) {
  const Deck d = load(kDeck1D, {"material.copper.eos.c0=4000"});
  EXPECT_DOUBLE_EQ(std::get<spall::materials::MieGruneisen>(d.materials[0].eos.model).C0, 4000.0);
}

TEST_F(DeckTest, OverrideUnnamedEntryByIndex) {
  const Deck d = load(kDeck1D, {"boundary.1.normal=[-3.0]"});
  EXPECT_EQ(d.boundaries[0].normal, std::vector<double>{-1.0});
}

TEST_F(DeckTest, OverrideCreatesMissingOptionalTablesAndKeys) {
  const std::string deck = withLines(kDeck1D, 6, 9); // no [solver]
  const Deck d = load(deck, {"solver.artificial_viscosity.alpha=2", "checkpoint.keep=4",
                             "body.striker.jitter=0.25"});
  EXPECT_DOUBLE_EQ(d.solver.artificial_viscosity.alpha, 2.0);
  EXPECT_DOUBLE_EQ(d.solver.artificial_viscosity.beta, 2.0); // default kept
  ASSERT_TRUE(d.checkpoint.has_value());
  EXPECT_EQ(d.checkpoint->keep, 4);
  EXPECT_DOUBLE_EQ(d.bodies[0].jitter, 0.25);
}

TEST_F(DeckTest, OverrideBareString) {
  const Deck d = load(kDeck1D, {"output.directory=out/other run", "run.title=a \"quoted\" title"});
  EXPECT_EQ(d.output.directory, "out/other run");
  EXPECT_EQ(d.run.title, "a \"quoted\" title");
  expectOverrideError(kDeck1D, "solver.method=fem", "must be one of");
  EXPECT_EQ(load(kDeck1D, {"solver.method=asph"}).solver.method, spall::SolverMethod::Asph);
}

TEST_F(DeckTest, OverrideUnknownKeySuggests) {
  expectOverrideError(kDeck1D, "body.striker.velocty=[1.0]",
                      "unknown key 'velocty' in body 'striker' (did you mean 'velocity'?)");
  expectOverrideError(kDeck1D, "rnu.end_time=1",
                      "unknown top-level key 'rnu' (did you mean 'run'?)");
}

TEST_F(DeckTest, OverrideUnknownEntryNamesTheAvailableOnes) {
  expectOverrideError(kDeck1D, "body.strikr.velocity=[1.0]",
                      "no body named 'strikr' (did you mean 'striker'?) (body names: striker, "
                      "target)");
}

TEST_F(DeckTest, OverrideWrongType) {
  expectOverrideError(kDeck1D, "run.end_time=abc", "'run.end_time' must be a number, got string");
  expectOverrideError(kDeck1D, "run.dimension=true",
                      "'run.dimension' must be an integer, got boolean");
  expectOverrideError(kDeck1D, "body.striker.velocity=[1.0, 2.0]", "must have 1 entry");
}

TEST_F(DeckTest, OverrideInlineTableIsCheckedLikeTheDeck) {
  expectOverrideError(kDeck1D, "body.striker.shape={ type = \"box\", min = [0.0], mx = [1.0] }",
                      "unknown key 'mx' in the shape of body 'striker' (did you mean 'max'?)");
}

TEST_F(DeckTest, MalformedOverride) {
  expectOverrideError(kDeck1D, "run.end_time", "expected --set KEY=VALUE");
  expectOverrideError(kDeck1D, "body.striker=1", "must name a key of one [[body]] entry");
}

// ---- resolved deck ----

TEST_F(DeckTest, ResolvedTomlRoundTrips) {
  for (const std::string* source : {&kDeck1D, &kDeck2D}) {
    const std::vector<std::string> overrides =
        source == &kDeck1D ? std::vector<std::string>{"run.end_time=2e-6", "solver.method=sph",
                                                      "body.striker.velocity=[30.0]"}
                           : std::vector<std::string>{};
    const Deck a = load(*source, overrides);
    EXPECT_EQ(a.resolved_toml.rfind("# resolved deck of " + a.path, 0), 0u) << a.resolved_toml;
    if (!overrides.empty()) {
      EXPECT_NE(a.resolved_toml.find("--set run.end_time=2e-6"), std::string::npos);
    }
    const Deck b = loadDeck(write(a.resolved_toml, "resolved.toml"));
    EXPECT_EQ(b.run.dimension, a.run.dimension);
    EXPECT_EQ(b.run.end_time, a.run.end_time);
    EXPECT_EQ(b.run.max_steps, a.run.max_steps);
    EXPECT_EQ(b.solver.kernel, a.solver.kernel);
    EXPECT_EQ(b.solver.h_max, a.solver.h_max);
    EXPECT_EQ(b.materials.size(), a.materials.size());
    EXPECT_EQ(spall::eosTypeName(b.materials.back().eos),
              spall::eosTypeName(a.materials.back().eos));
    EXPECT_EQ(b.materials.back().eos.min_pressure, a.materials.back().eos.min_pressure);
    ASSERT_EQ(b.bodies.size(), a.bodies.size());
    for (std::size_t i = 0; i < a.bodies.size(); ++i) {
      EXPECT_EQ(b.bodies[i].name, a.bodies[i].name);
      EXPECT_EQ(b.bodies[i].velocity, a.bodies[i].velocity);
      EXPECT_EQ(b.bodies[i].spacing, a.bodies[i].spacing);
      EXPECT_EQ(b.bodies[i].shape.min, a.bodies[i].shape.min);
      EXPECT_EQ(b.bodies[i].initial_pressure, a.bodies[i].initial_pressure);
      EXPECT_EQ(b.bodies[i].lattice_transform, a.bodies[i].lattice_transform);
    }
    EXPECT_EQ(b.boundaries.size(), a.boundaries.size());
    EXPECT_EQ(b.output.directory, a.output.directory);
    EXPECT_EQ(b.output.fields, a.output.fields);
    EXPECT_EQ(b.checkpoint.has_value(), a.checkpoint.has_value());
    EXPECT_EQ(b.probes.at(0).fields, a.probes.at(0).fields);
  }
}

} // namespace

// ---- solid-mechanics solver options and structure body keys ----

TEST_F(DeckTest, SolidSolverOptions) {
  const std::string path = write(kDeck1D);
  const Deck d =
      loadDeck(path, {"solver.artificial_stress.epsilon=0.2", "solver.contact=frictionless",
                      "solver.velocity_gradient=corrected"});
  EXPECT_TRUE(d.solver.artificial_stress.enabled);
  EXPECT_EQ(d.solver.artificial_stress.epsilon, 0.2);
  EXPECT_EQ(d.solver.artificial_stress.exponent, 4);
  EXPECT_EQ(d.solver.contact, spall::Contact::Frictionless);
  EXPECT_EQ(d.solver.velocity_gradient, spall::VelocityGradient::Corrected);
  const Deck off = loadDeck(path, {"solver.artificial_stress.epsilon=0"});
  EXPECT_FALSE(off.solver.artificial_stress.enabled);
  // The defaults (decks/topics/safe-defaults.md): artificial stress where a material has
  // strength (none here), contact "auto".
  const Deck plain = loadDeck(path);
  EXPECT_FALSE(plain.solver.artificial_stress.enabled);
  EXPECT_EQ(plain.solver.contact, spall::Contact::Auto);
  EXPECT_EQ(plain.solver.stress_form, spall::StressForm::RhoProduct);
  // A deck without a [solver] table has the same defaults (it once had welded contact).
  const Deck bare = load(withLines(kDeck1D, 6, 9, ""));
  EXPECT_EQ(bare.solver.contact, spall::Contact::Auto);
  EXPECT_EQ(bare.solver.neighbor_skin, 0.1);
  EXPECT_EQ(bare.solver.shape_interval, 4);
  EXPECT_EQ(loadDeck(path, {"solver.shape_interval=1"}).solver.shape_interval, 1);
  const Deck solid =
      load(withLine(kDeck1D, 14,
                    R"(eos = { type = "mie_gruneisen", c0 = 3940.0, s = 1.49, gamma0 = 2.02 }
strength = { type = "von_mises", shear_modulus = 4.6e10, yield_stress = 1.2e8 })"));
  EXPECT_TRUE(solid.solver.artificial_stress.enabled);
  EXPECT_EQ(solid.solver.artificial_stress.epsilon, 0.3);
  // Only epsilon turns the stress on: a table with only the exponent keeps the default (off for
  // this fluid, where "on" is refused as acting on no material).
  const std::string fluid = write(kDeck1D, "fluid.toml"); // load() above rewrote `path`
  const Deck exponentOnly = loadDeck(fluid, {"solver.artificial_stress.exponent=2"});
  EXPECT_FALSE(exponentOnly.solver.artificial_stress.enabled);
  EXPECT_EQ(exponentOnly.solver.artificial_stress.exponent, 2);
  // ASPH's keys with method "sph" are listed for the run's warning; with "asph" they act.
  const std::vector<std::string> asphKeys{"max_aspect_ratio", "shape_interval"};
  EXPECT_EQ(
      loadDeck(fluid, {"solver.max_aspect_ratio=3", "solver.shape_interval=2"}).solver.asphOnlyKeys,
      asphKeys);
  EXPECT_TRUE(loadDeck(fluid, {"solver.method=asph", "solver.max_aspect_ratio=3"})
                  .solver.asphOnlyKeys.empty());
}

TEST_F(DeckTest, SolidSolverOptionsAreValidated) {
  expectOverrideError(kDeck1D, "solver.artificial_stress.epsilon=1.5", "in [0, 1]");
  expectOverrideError(kDeck1D, "solver.artificial_stress.exponent=0", "[1, 8]");
  expectOverrideError(kDeck1D, "solver.contact=sticky", "frictionless");
  expectOverrideError(kDeck1D, "solver.shape_interval=0", "[1, 64]");
  expectOverrideError(kDeck1D, "solver.shape_interval=2.5", "shape_interval");
}

TEST_F(DeckTest, FixedBodyMovesRigidly) {
  // The striker has velocity = [20.0]: fixed, it is a piston at that speed.
  const Deck piston = loadDeck(write(kDeck1D), {"body.striker.fixed=true"});
  EXPECT_TRUE(piston.bodies[0].fixed);
  EXPECT_DOUBLE_EQ(piston.bodies[0].velocity[0], 20.0);
  const Deck d = loadDeck(write(kDeck1D), {"body.target.fixed=true"});
  EXPECT_TRUE(d.bodies[1].fixed);
  EXPECT_FALSE(d.bodies[0].fixed);
}

TEST_F(DeckTest, CantileverVelocityNeedsATransverseAxis) {
  expectOverrideError(kDeck1D,
                      "body.target.cantilever_velocity={root=[0.0], length=0.02, tip_speed=1.0}",
                      "run.dimension 2 or 3");
}

TEST_F(DeckTest, LinearVelocityTakesADimByDimGradient) {
  const Deck d = loadDeck(write(kDeck1D),
                          {"body.target.linear_velocity={center=[0.01], gradient=[[-3.0e3]]}"});
  ASSERT_TRUE(d.bodies[1].linear_velocity);
  EXPECT_DOUBLE_EQ(d.bodies[1].linear_velocity->center[0], 0.01);
  EXPECT_DOUBLE_EQ(d.bodies[1].linear_velocity->gradient[0][0], -3.0e3);
  // 1D deck: a 2x2 gradient is the wrong shape; and a fixed body cannot be given one.
  expectOverrideError(
      kDeck1D, "body.target.linear_velocity={center=[0.0], gradient=[[1.0, 0.0], [0.0, 1.0]]}",
      "gradient");
  const DeckError e =
      error(kDeck1D, {"body.target.linear_velocity={center=[0.0], gradient=[[1.0]]}",
                      "body.target.fixed=true"});
  EXPECT_NE(std::string(e.what()).find("velocity field"), std::string::npos) << e.what();
}

// material.library (decks/materials): the file's keys fill what the entry leaves out, the entry's
// win (an eos table of the same type merges key by key), errors point at the name or into the file.
namespace {
std::string withLibrary(const std::string& materialLines) {
  std::string deck = kDeck1D;
  const std::string own =
      "density = 8930.0\n"
      "eos = { type = \"mie_gruneisen\", c0 = 3940.0, s = 1.49, gamma0 = 2.02 }\n";
  deck.replace(deck.find(own), own.size(), materialLines);
  return deck;
}
} // namespace

TEST_F(DeckTest, MaterialLibraryFillsWhatTheEntryLeavesOut) {
  // The shipped decks/materials/copper.toml, found through the built-in path.
  const Deck d = load(withLibrary("library = \"copper\"\n"));
  EXPECT_DOUBLE_EQ(d.materials[0].density, 8930.0);
  const auto& mg = std::get<spall::materials::MieGruneisen>(d.materials[0].eos.model);
  EXPECT_DOUBLE_EQ(mg.C0, 3940.0);
  EXPECT_DOUBLE_EQ(mg.Gamma0, 2.02);
  EXPECT_NE(d.resolved_toml.find("# material library: copper ("), std::string::npos);
  EXPECT_EQ(d.resolved_toml.find("library ="), std::string::npos); // inlined: the deck as run
                                                                   // needs no library
  // The entry's keys win; an eos of the same type takes the rest from the file.
  const Deck e =
      load(withLibrary("library = \"copper\"\ndensity = 9000.0\neos = { min_pressure = -1e9 }\n"));
  EXPECT_DOUBLE_EQ(e.materials[0].density, 9000.0);
  EXPECT_DOUBLE_EQ(std::get<spall::materials::MieGruneisen>(e.materials[0].eos.model).C0, 3940.0);
  EXPECT_DOUBLE_EQ(e.materials[0].eos.min_pressure, -1e9);
  // Another type is the entry's own model, whole.
  const Deck f = load(
      withLibrary("library = \"copper\"\neos = { type = \"linear\", bulk_modulus = 1.4e11 }\n"));
  EXPECT_DOUBLE_EQ(std::get<spall::materials::LinearEos>(f.materials[0].eos.model).K, 1.4e11);
}

TEST_F(DeckTest, MaterialLibraryBesideTheDeckComesFirstAndErrorsPointIntoIt) {
  std::filesystem::create_directories(dir_ / "materials");
  write("# a local set\ndensity = 1234.0\neos = { type = \"linear\", bulk_modulus = 1e10 }\n",
        "materials/copper.toml");
  EXPECT_DOUBLE_EQ(load(withLibrary("library = \"copper\"\n")).materials[0].density, 1234.0);
  // A bad value in the file is reported at its line in the file.
  write("density = 8000.0\neos = { type = \"linear\", bulk_modulus = -1.0 }\n",
        "materials/bad.toml");
  const DeckError bad = error(withLibrary("library = \"bad\"\n"));
  EXPECT_EQ(bad.where().file, (dir_ / "materials" / "bad.toml").string()) << bad.what();
  EXPECT_EQ(bad.where().line, 2) << bad.what();
  write("name = \"x\"\ndensity = 8000.0\n", "materials/named.toml");
  EXPECT_NE(std::string(error(withLibrary("library = \"named\"\n")).what()).find("'name'"),
            std::string::npos);
  // An unknown name: at the entry's value, with the near miss and what the library holds.
  expectError(withLibrary("library = \"coper\"\n"), 13, 11, "did you mean 'copper'?");
  expectError(withLibrary("library = \"../deck\"\n"), 13, 11, "letters, digits");
}
