// Shapes beyond the primitives: cones, ogives, polygons, unions, differences and particles read
// from a file. Each body's mass against the shape's exact volume (rz: Pappus' theorem), the
// lattice of a union built on a box against the box's own, and the file readers' exact copies.
#include "spall/app/BodyGenerator.hpp"
#include "spall/io/ParticleFile.hpp"

#include "unit/app/GeneratedBodies.hpp"

#include <hdf5.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <iomanip>
#include <numbers>
#include <set>

using namespace spall;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kRho = 2.0; // the fixture material's density

std::filesystem::path tempPath(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("spall_shapes_" + name);
}

Deck shapeDeck(const std::string& name, int dim, const std::string& bodies, bool rz = false) {
  const auto path = tempPath(name + ".toml");
  std::ofstream(path) << "[run]\ndimension = " << dim << "\nend_time = 1.0\n"
                      << (rz ? "geometry = \"rz\"\n" : "")
                      << "[[material]]\nname = \"m\"\ndensity = 2.0\n"
                         "eos = { type = \"ideal_gas\", gamma = 1.4 }\n"
                      << bodies << "[output]\ndirectory = \"unused\"\n";
  return loadDeck(path.string());
}

std::string body(const std::string& name, const std::string& shape, double spacing) {
  return "[[body]]\nname = \"" + name + "\"\nmaterial = \"m\"\nshape = " + shape +
         "\nspacing = " + std::to_string(spacing) + "\n";
}

template <int Dim> using Generated = fixtures::GeneratedBodies<Dim>;

// The tangent ogive's volume, pi int_0^L y(t)^2 dt with y = R - rho + sqrt(rho^2 - t^2), by
// Simpson's rule on 20,000 intervals (error ~1e-15 of it: the profile is smooth on [0, L]).
double ogiveVolume(double R, double L) {
  const double rho = (R * R + L * L) / (2.0 * R);
  const int n = 20000;
  double s = 0.0;
  for (int k = 0; k <= n; ++k) {
    const double t = L * k / n;
    const double y = R - rho + std::sqrt(std::max(0.0, rho * rho - t * t));
    s += (k == 0 || k == n ? 1.0 : (k % 2 ? 4.0 : 2.0)) * y * y;
  }
  return kPi * s * L / (3.0 * n);
}

} // namespace

// A lattice clipped by a surface holds the volume to first order in dx/size, the sign and size
// of the error depending on how the surface meets the lattice: the oblique frustum below,
// measured at spacings 0.0125-0.04, is off by at most 0.45 dx/R (+1.8% at 0.04, +1.1% here at
// 0.025, -0.5% at 0.0125). Each tolerance is that bound at the test's spacing.
TEST(CompositeShapes, ConesAndOgivesHoldTheirVolume) {
  // 3D: a frustum along an oblique axis, a pointed cone, a 2.5-caliber tangent ogive.
  const Generated<3> frustum(shapeDeck(
      "frustum", 3,
      body("f",
           "{ type = \"cone\", base = [0.1, 0.2, 0.3], axis = [1.0, 1.0, 1.0], radius = 0.5, "
           "length = 1.0, tip_radius = 0.25 }",
           0.025)));
  EXPECT_NEAR(frustum.bodies[0].mass / (kRho * kPi * (0.25 + 0.125 + 0.0625) / 3.0), 1.0, 2.3e-2);
  const Generated<3> cone(shapeDeck(
      "cone", 3,
      body("c",
           "{ type = \"cone\", base = [0.0, 0.0, 0.0], axis = [0.0, 0.0, 2.0], radius = 0.5, "
           "length = 1.5 }",
           0.025)));
  EXPECT_NEAR(cone.bodies[0].mass / (kRho * kPi * 0.25 * 1.5 / 3.0), 1.0, 1e-2);
  const Generated<3> ogive(shapeDeck(
      "ogive", 3,
      body("o",
           "{ type = \"ogive\", base = [0.0, 0.0, 0.0], axis = [0.0, 1.0, 0.0], radius = 0.5, "
           "length = 1.25 }",
           0.025)));
  EXPECT_NEAR(ogive.bodies[0].mass / (kRho * ogiveVolume(0.5, 1.25)), 1.0, 1e-2);
  // An ogive as long as its radius is a hemisphere: 2/3 pi R^3.
  EXPECT_NEAR(ogiveVolume(0.5, 0.5) / (2.0 / 3.0 * kPi * 0.125), 1.0, 1e-12);
  // 2D: the sections, a trapezoid of area L (R + r) and the ogive's 2 int y dt.
  const Generated<2> trapezoid(
      shapeDeck("trapezoid", 2,
                body("t",
                     "{ type = \"cone\", base = [0.0, 0.0], axis = [0.0, -1.0], radius = 0.5, "
                     "length = 1.0, tip_radius = 0.2 }",
                     0.02)));
  EXPECT_NEAR(trapezoid.bodies[0].mass / (kRho * 1.0 * 0.7), 1.0, 5e-3);
}

TEST(CompositeShapes, RzBodiesOfRevolutionHoldPappusVolume) {
  // rz: each ring's mass is rho A 2 pi r, so a section's mass is rho 2 pi (A r_c) = rho V
  // (Pappus). A cone of R 0.5, L 1.5 about the axis; an ogive; a polygon (a washer with a bevel).
  // The cone is commensurate with its lattice (R = 25 dx, L = 75 dx): every third layer's radius
  // falls half-way between two rings and keeps the inner one, a bias of -dx/(2 rho) on a third
  // of the layers: -1.45% (the same sum done by hand), inside 0.45 dx/R = 1.8%.
  const Generated<2> cone(shapeDeck(
      "rz_cone", 2,
      body("c",
           "{ type = \"cone\", base = [0.0, 1.0], axis = [0.0, -1.0], radius = 0.5, length = 1.5 }",
           0.02),
      true));
  EXPECT_NEAR(cone.bodies[0].mass / (kRho * kPi * 0.25 * 1.5 / 3.0), 1.0, 1.8e-2);
  const Generated<2> ogive(shapeDeck(
      "rz_ogive", 2,
      body("o",
           "{ type = \"ogive\", base = [0.0, 0.0], axis = [0.0, 1.0], radius = 0.5, length = 1.0 }",
           0.02),
      true));
  EXPECT_NEAR(ogive.bodies[0].mass / (kRho * ogiveVolume(0.5, 1.0)), 1.0, 1e-2);
  // The section: (0.2, 0) (1, 0) (1, 0.5) (0.6, 0.9) (0.2, 0.9). Area 0.8 * 0.9 - 0.4^2 / 2 =
  // 0.64; its first moment about the axis int r dA = 0.9 (1 - 0.04)/2 - (the bevel's triangle,
  // legs 0.4, centroid at r = 1 - 0.4/3) 0.08 (1 - 0.4/3).
  const Generated<2> washer(shapeDeck(
      "rz_polygon", 2,
      body("w",
           "{ type = \"polygon\", points = [[0.2, 0.0], [1.0, 0.0], [1.0, 0.5], [0.6, 0.9], "
           "[0.2, 0.9]] }",
           0.01),
      true));
  const double moment = 0.9 * (1.0 - 0.04) / 2.0 - 0.08 * (1.0 - 0.4 / 3.0);
  // The bevel alone is clipped (the other edges lie half a spacing from the sites): 0.45 dx over
  // the section's size, 0.8.
  EXPECT_NEAR(washer.bodies[0].mass / (kRho * 2.0 * kPi * moment), 1.0, 0.45 * 0.01 / 0.8 + 1e-4);
}

TEST(CompositeShapes, PolygonHoldsItsAreaEitherWayRound) {
  // An L: area 1 - 0.25. Its vertices clockwise and anticlockwise give the same particles.
  const std::string ccw = "[[0.0, 0.0], [1.0, 0.0], [1.0, 0.5], [0.5, 0.5], [0.5, 1.0], "
                          "[0.0, 1.0]]";
  const std::string cw = "[[0.0, 1.0], [0.5, 1.0], [0.5, 0.5], [1.0, 0.5], [1.0, 0.0], "
                         "[0.0, 0.0]]";
  const Generated<2> a(
      shapeDeck("poly_ccw", 2, body("l", "{ type = \"polygon\", points = " + ccw + " }", 0.05)));
  const Generated<2> b(
      shapeDeck("poly_cw", 2, body("l", "{ type = \"polygon\", points = " + cw + " }", 0.05)));
  // The edges lie on lattice lines half a spacing from the sites: exact.
  EXPECT_NEAR(a.bodies[0].mass, kRho * 0.75, 1e-12);
  ASSERT_EQ(a.store.localCount(), b.store.localCount());
  for (std::size_t i = 0; i < a.store.localCount(); ++i)
    EXPECT_EQ(a.store[a.f.x][i], b.store[b.f.x][i]);
}

TEST(CompositeShapes, UnionOnABoxKeepsTheBoxsLattice) {
  // A rod with a hemispherical nose in rz, as one body (two bodies overlap where they join):
  // the rod's particles are the box's own exact lattice, bit for bit, and the nose continues
  // it; the mass is the cylinder's and the hemisphere's (Pappus), rho (pi R^2 L + 2/3 pi R^3).
  const double R = 0.1, L = 1.0, dx = 0.004;
  const std::string box = "{ type = \"box\", min = [0.0, 0.0], max = [0.1, 1.0] }";
  const Generated<2> rod(shapeDeck("rod", 2, body("rod", box, dx), true));
  const Generated<2> nosed(
      shapeDeck("rod_nose", 2,
                body("rod",
                     "{ type = \"union\", shapes = [" + box +
                         ", { type = \"sphere\", center = [0.0, 0.0], radius = 0.1 }] }",
                     dx),
                true));
  std::set<std::pair<double, double>> inRod;
  for (const auto& x : rod.store[rod.f.x]) inRod.insert({x[0], x[1]});
  std::size_t shared = 0;
  for (const auto& x : nosed.store[nosed.f.x]) shared += inRod.count({x[0], x[1]});
  EXPECT_EQ(shared, rod.store.localCount()); // every rod site, at the same bits
  const double exact = kRho * kPi * (R * R * L + 2.0 / 3.0 * R * R * R);
  EXPECT_NEAR(nosed.bodies[0].mass / exact, 1.0, 3e-3);
  // Every particle of the nose carries the box's cell (the exact fill's step).
  for (const auto m : nosed.store[nosed.f.h]) EXPECT_NEAR(m, 1.5 * dx, 1e-15);
}

TEST(CompositeShapes, DifferenceCutsItsPartsOut) {
  // A plate with a round hole and a square notch (2D); a hollow ball (3D, with a ball cut from a
  // ball: a shell) against 4/3 pi (R^3 - r^3).
  const Generated<2> plate(shapeDeck(
      "plate", 2,
      body("p",
           "{ type = \"difference\", from = { type = \"box\", min = [0.0, 0.0], max = [2.0, "
           "1.0] }, minus = [{ type = \"sphere\", center = [0.7, 0.5], radius = 0.3 }, { type = "
           "\"box\", min = [1.5, 0.0], max = [2.0, 0.5] }] }",
           0.01)));
  EXPECT_NEAR(plate.bodies[0].mass / (kRho * (2.0 - kPi * 0.09 - 0.25)), 1.0, 2e-3);
  for (const auto& x : plate.store[plate.f.x]) {
    EXPECT_GE((x - Vec<2>(0.7, 0.5)).norm(), 0.3);
    EXPECT_FALSE(x[0] >= 1.5 && x[1] < 0.5);
  }
  const Generated<3> shell(shapeDeck(
      "shell", 3,
      body("s",
           "{ type = \"difference\", from = { type = \"sphere\", center = [0.0, 0.0, 0.0], "
           "radius = 0.5 }, minus = [{ type = \"sphere\", center = [0.0, 0.0, 0.0], radius = "
           "0.3 }] }",
           0.02)));
  EXPECT_NEAR(shell.bodies[0].mass / (kRho * 4.0 / 3.0 * kPi * (0.125 - 0.027)), 1.0, 1e-2);
}

TEST(CompositeShapes, NestedShapesAreAddressedByIndex) {
  // --set reaches into a union's shapes by 1-based index, and the key is checked there.
  const auto path = tempPath("nested.toml");
  std::ofstream(path) << "[run]\ndimension = 2\ngeometry = \"rz\"\nend_time = 1.0\n"
                         "[[material]]\nname = \"m\"\ndensity = 2.0\n"
                         "eos = { type = \"ideal_gas\", gamma = 1.4 }\n"
                      << body("rod",
                              "{ type = \"union\", shapes = [{ type = \"box\", min = [0.0, 0.0], "
                              "max = [0.1, 1.0] }, { type = \"ogive\", base = [0.0, 0.0], axis = "
                              "[0.0, -1.0], radius = 0.1, length = 0.2 }] }",
                              0.01)
                      << "[output]\ndirectory = \"unused\"\n";
  const Deck deck = loadDeck(path.string(), {"body.rod.shape.shapes.2.length=0.3"});
  EXPECT_EQ(deck.bodies[0].shape.parts.at(1).length, 0.3);
  try {
    loadDeck(path.string(), {"body.rod.shape.shapes.2.length=0.05"});
    FAIL() << "an ogive shorter than its radius was accepted";
  } catch (const DeckError& e) {
    EXPECT_NE(std::string(e.what()).find("body.rod.shape.shapes.2.length"), std::string::npos)
        << e.what();
  }
}

namespace {

// A small 3D cloud, irregular volumes: a 4 x 3 x 2 block of cells with the volumes of its
// cells, written as CSV (extra columns in any order) and as HDF5.
struct Cloud {
  std::vector<double> x, V;
  Cloud() {
    for (int k = 0; k < 2; ++k)
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 4; ++i) {
          const double s = 0.01 * (1.0 + 0.1 * i); // cells widen along x
          x.insert(x.end(), {0.05 * i, 0.012 * j, 0.012 * k});
          V.push_back(s * 0.012 * 0.012);
        }
  }
};

void writeCsv(const std::filesystem::path& p, const Cloud& c) {
  std::ofstream o(p);
  o << std::setprecision(17) << "# a mesher's output\nid, volume, z, y, x\n";
  for (std::size_t i = 0; i < c.V.size(); ++i)
    o << i << ", " << c.V[i] << ", " << c.x[3 * i + 2] << ", " << c.x[3 * i + 1] << ", "
      << c.x[3 * i] << "\n";
}

void writeH5(const std::filesystem::path& p, const Cloud& c) {
  const hid_t f = H5Fcreate(p.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  const hsize_t n = c.V.size(), dims[2] = {n, 3};
  const hid_t s2 = H5Screate_simple(2, dims, nullptr), s1 = H5Screate_simple(1, &n, nullptr);
  const hid_t d2 =
      H5Dcreate2(f, "position", H5T_NATIVE_DOUBLE, s2, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  const hid_t d1 =
      H5Dcreate2(f, "volume", H5T_NATIVE_DOUBLE, s1, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  H5Dwrite(d2, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, c.x.data());
  H5Dwrite(d1, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, c.V.data());
  H5Dclose(d1), H5Dclose(d2), H5Sclose(s1), H5Sclose(s2), H5Fclose(f);
}

} // namespace

TEST(CompositeShapes, ParticlesFromAFileAreTheFilesOwn) {
  const Cloud c;
  writeCsv(tempPath("cloud.csv"), c);
  writeH5(tempPath("cloud.h5"), c);
  for (const std::string file : {"spall_shapes_cloud.csv", "spall_shapes_cloud.h5"}) {
    // Relative to the deck; run.resolution does not rescale a mesher's particles.
    const Deck deck = shapeDeck("cloud", 3,
                                "[[body]]\nname = \"c\"\nmaterial = \"m\"\nshape = { type = "
                                "\"particles\", file = \"" +
                                    file + "\" }\n");
    const Deck coarse = loadDeck(deck.path, {"run.resolution=0.5"});
    for (const Deck* d : {&deck, &coarse}) {
      const Generated<3> g(*d);
      ASSERT_EQ(g.store.localCount(), c.V.size()) << file;
      for (std::size_t i = 0; i < c.V.size(); ++i) {
        EXPECT_EQ(g.store[g.f.x][i], Vec<3>(c.x[3 * i], c.x[3 * i + 1], c.x[3 * i + 2]));
        EXPECT_EQ(g.store[g.f.m][i], kRho * c.V[i]); // written with 17 digits: the same double
        EXPECT_NEAR(g.store[g.f.h][i], 1.5 * std::cbrt(c.V[i]), 1e-15);
      }
      // The body's spacing is the coarsest particle's, as made.
      EXPECT_NEAR(g.bodies[0].spacing, std::cbrt(c.V.back()), 1e-15);
    }
    // The deck as run names the file by its absolute path.
    EXPECT_NE(deck.resolved_toml.find(tempPath(file.substr(13)).string()), std::string::npos)
        << deck.resolved_toml;
  }
}

TEST(CompositeShapes, ParticleFileErrorsPointIntoTheFile) {
  const auto check = [](const std::string& text, int line, const std::string& what) {
    const auto p = tempPath("bad.csv");
    std::ofstream(p) << text;
    try {
      io::readParticleFile(p.string(), 2, true);
      FAIL() << "accepted: " << text;
    } catch (const DeckError& e) {
      EXPECT_EQ(e.where().line, line) << e.what();
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  check("x,y\n0.1,0.2\n", 1, "no 'volume' column");
  check("r,z,volume\n0.1,0.2,1e-6\n0.2,zz,1e-6\n", 3, "'zz' is not a finite number");
  check("r,z,volume\n0.1,0.2,0\n", 2, "volumes must be > 0");
  check("r,z,volume\n# comment\n0.0,0.2,1e-6\n", 3, "r > 0");
  check("r,z,volume\n0.1,0.2,1e-6\n0.1,0.2,2e-6\n", 3, "at the place of particle 0");
  check("r,z,volume\n0.1,0.2\n", 2, "2 values where the header names 3");
  check("# nothing\n", 1, "no header");
}
