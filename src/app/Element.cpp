#include "spall/app/Element.hpp"

#include "spall/app/Setup.hpp"
#include "spall/core/Error.hpp"
#include "spall/io/Deck.hpp"
#include "spall/io/FTable.hpp"
#include "spall/materials/MaterialUpdate.hpp"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <fmt/os.h>
#include <fstream>
#include <sstream>

namespace spall::app {

namespace {

namespace fs = std::filesystem;

// F of the table at the fraction s in [0, 1] of the interval from row r to r + 1, with the
// superimposed rotation applied: R(s) F(s), both interpolated linearly (the rotation by its angle
// about the interpolated axis).
Tensor<3> totalF(const io::FTable& table, std::size_t r, double s) {
  const io::FTableRow &a = table.rows[r], &b = table.rows[r + 1];
  const Tensor<3> F = (1.0 - s) * a.F + s * b.F;
  if (!table.rotation) return F;
  Vec<3> axis = (1.0 - s) * a.axis + s * b.axis;
  axis = axis.norm() > 0.0 ? axis.normalized() : a.axis; // opposite axes: keep the row's
  const double theta = ((1.0 - s) * a.thetaDeg + s * b.thetaDeg) * (M_PI / 180.0);
  return Eigen::AngleAxisd(theta, axis).toRotationMatrix() * F;
}

// The rotation of F's polar decomposition F = R U.
Tensor<3> polarRotation(const Tensor<3>& F) {
  const Eigen::JacobiSVD<Tensor<3>> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  return svd.matrixU() * svd.matrixV().transpose();
}

// A recorded particle's row: the density and energy at the step's end, and those its material
// update saw (before the kick's correction; recordings without them: the same).
struct RecordedRow {
  double rho = 0.0, e = 0.0, rhoUpdate = 0.0, eUpdate = 0.0;
  double alpha = 0.0;  // a porous material's distension (0: not recorded)
  double alphaP = 0.0; // its plastic part, with elastic distension (0: not recorded)
  // Scalar flaws as the run drew them, and the damage (NaN: not recorded)
  double flawCount = NAN, flawsActive = NAN, flawScale = NAN, flawNext = NAN, damage = NAN;
  // The state a replay starts from (a recording that starts mid-run: a failed run's replay),
  // NaN where not recorded: the deviatoric stress (intact: a damaged material's), plastic
  // strain, temperature, a cap's plastic volumetric strain.
  Tensor<3> S = Tensor<3>::Constant(NAN), Sintact = Tensor<3>::Constant(NAN);
  double plastic = NAN, temperature = NAN, epsVp = NAN;
  double id = NAN; // the particle's id: the run drew its flaws from it
  Tensor<3> damageTensor = Tensor<3>::Constant(NAN), strainTensor = Tensor<3>::Constant(NAN);
  // A rate-dependent cap's overstress (deviator, I1)
  Tensor<3> overS = Tensor<3>::Constant(NAN);
  double overI1 = NAN;
};

// Voigt order of the stress columns: xx yy zz xy yz xz.
constexpr int kVoigt[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {1, 2}, {0, 2}};

// The rows of a recorded state, one a table row.
std::vector<RecordedRow> readState(const std::string& path, const io::FTable& table) {
  std::ifstream in(path);
  if (!in) throw UsageError("cannot read the state " + path);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  for (std::size_t a = 0, b; a <= line.size(); a = b + 1) {
    b = line.find(',', a);
    if (b == std::string::npos) b = line.size();
    names.push_back(line.substr(a, b - a));
  }
  const auto find = [&](const std::string& name) {
    return static_cast<std::size_t>(std::find(names.begin(), names.end(), name) - names.begin());
  };
  const auto column = [&](const std::string& name) {
    const std::size_t c = find(name);
    if (c == names.size()) throw DeckError({path, 1, 0}, "no column '" + name + "'");
    return c;
  };
  const std::size_t ct = column("t"), crho = column("density"),
                    ce = column("specific_internal_energy");
  const std::size_t cru = find("update_density"), ceu = find("update_specific_internal_energy");
  const bool update = cru < names.size() && ceu < names.size();
  const std::size_t calpha = find("porosity_alpha");
  const auto optional = [&](const std::vector<double>& v, const char* name) {
    const std::size_t c = find(name);
    return c < names.size() ? v[c] : NAN;
  };
  std::vector<RecordedRow> out;
  int lineNo = 1;
  while (std::getline(in, line)) {
    ++lineNo;
    std::vector<double> v;
    std::istringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');)
      v.push_back(std::strtod(cell.c_str(), nullptr));
    const std::size_t k = out.size();
    if (v.size() != names.size() || k >= table.rows.size() || v[ct] != table.rows[k].t)
      throw DeckError({path, lineNo, 0}, "the state's rows must be the F-table's, time for time");
    RecordedRow row{
        v[crho],
        v[ce],
        update ? v[cru] : v[crho],
        update ? v[ceu] : v[ce],
        calpha < names.size() ? v[calpha] : 0.0,
        std::isnan(optional(v, "plastic_distension")) ? 0.0 : optional(v, "plastic_distension"),
        optional(v, "flaw_count"),
        optional(v, "flaws_active"),
        optional(v, "flaw_strain_scale"),
        optional(v, "next_flaw_strain"),
        optional(v, "damage")};
    const auto tensor = [&](const std::string& prefix, Tensor<3>& T) {
      static constexpr const char* kAxes[6] = {"xx", "yy", "zz", "xy", "yz", "xz"};
      for (int c = 0; c < 6; ++c) {
        const double x = optional(v, (prefix + kAxes[c]).c_str());
        T(kVoigt[c][0], kVoigt[c][1]) = T(kVoigt[c][1], kVoigt[c][0]) = x;
      }
    };
    tensor("S", row.S);
    tensor("intact_S", row.Sintact);
    row.plastic = optional(v, "plastic_strain"), row.temperature = optional(v, "temperature");
    row.epsVp = optional(v, "plastic_volumetric_strain");
    row.overI1 = optional(v, "cap_overstress_i1");
    row.id = optional(v, "id");
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        const std::string ab = fmt::format("_{}{}", a + 1, b + 1);
        row.damageTensor(a, b) = optional(v, ("damage_tensor" + ab).c_str());
        row.strainTensor(a, b) = optional(v, ("strain_tensor" + ab).c_str());
        row.overS(a, b) = optional(v, ("cap_overstress" + ab).c_str());
      }
    out.push_back(row);
  }
  if (out.size() != table.rows.size())
    throw DeckError({path, lineNo, 0}, fmt::format("the state has {} rows, the F-table {}",
                                                   out.size(), table.rows.size()));
  return out;
}

// The driven material point: every field the material update reads or writes, one row each. It
// starts without deviatoric stress at the table's first F (density rho0 / det F, which sets a cap
// material's mean stress), with no internal energy; a porous one at alpha0 (bulk density
// rho0 = density / alpha0); a recorded particle where its recording starts.
struct ElementPoint {
  const materials::Material& mat;
  bool strength, damage, cap, porous, flaws, tensor, elastic;
  double alpha0, rho0;
  std::vector<double> rho, e{0.0}, p{0.0}, cs{0.0};
  std::vector<double> plastic{0.0}, temperature, D{0.0}, flawScale{0.0}, flawNext{0.0};
  std::vector<std::int32_t> material{0}, flawCount{0}, flawsActive{0};
  std::vector<Tensor<3>> L{Tensor<3>::Zero()}, S{Tensor<3>::Zero()}, Sintact{Tensor<3>::Zero()};
  std::vector<Tensor<3>> damageTensor{Tensor<3>::Zero()}, strainTensor{Tensor<3>::Zero()};
  std::vector<ParticleId> id{0};
  std::vector<double> epsVp{0.0}, X{0.0}, phi{0.0}, pf{0.0};
  std::vector<Tensor<3>> overS{Tensor<3>::Zero()}; // a rate-dependent cap's overstress
  std::vector<double> overI1{0.0};
  std::vector<std::int32_t> iterations{0};
  std::vector<double> alpha, alphaP;

  ElementPoint(const materials::Material& m, const MaterialConfig& cfg, const io::FTable& table,
               const std::vector<RecordedRow>& recorded, std::uint64_t seed, double flawVolume)
      : mat(m), strength(m.strength.has_value()), damage(m.damage.has_value()),
        cap(m.cap.has_value()), porous(m.porosity.has_value()), flaws(m.scalesWithDamage()),
        tensor(m.tensorDamage()), elastic(porous && m.porosity->elastic()),
        alpha0(porous ? m.porosity->alpha0 : 1.0),
        rho0(cfg.density / alpha0), rho{rho0 / totalF(table, 0, 0.0).determinant()},
        temperature{cfg.strength.initialTemperature()}, alpha{alpha0} {
    const RecordedRow* r0 = recorded.empty() ? nullptr : &recorded[0];
    if (r0) rho[0] = r0->rho, e[0] = r0->e;
    // A recorded particle's id: flaws past those active at the first row are drawn from it.
    if (r0 && r0->id >= 0.0) id[0] = static_cast<ParticleId>(r0->id);
    if (porous && r0 && r0->alpha > 0.0) alpha[0] = r0->alpha;
    alphaP = {alpha[0]};
    if (elastic && r0 && r0->alphaP > 0.0) alphaP[0] = r0->alphaP;
    if (porous) phi[0] = 1.0 - 1.0 / alpha[0];
    if (flaws) {
      const auto set =
          materials::drawFlaws(std::get<materials::GradyKipp>(*mat.damage), seed, 0, flawVolume, 1);
      flawCount[0] = set.count, flawScale[0] = set.scale, flawNext[0] = set.first;
      // A recorded particle: the run's own draw (its id and volume), and where it stood.
      if (r0 && !std::isnan(r0->flawCount) && !std::isnan(r0->flawScale)) {
        flawCount[0] = static_cast<std::int32_t>(r0->flawCount);
        flawsActive[0] = static_cast<std::int32_t>(r0->flawsActive);
        flawScale[0] = r0->flawScale, flawNext[0] = r0->flawNext;
      }
    }
    if (damage && r0 && !std::isnan(r0->damage)) D[0] = r0->damage;
    if (r0) resume(*r0);
  }

  // Where the recording starts (mid-run: not the initial state).
  void resume(const RecordedRow& r0) {
    const auto take = [](double& x, double recordedValue) {
      if (!std::isnan(recordedValue)) x = recordedValue;
    };
    if (strength || cap) {
      if (r0.S.allFinite()) S[0] = r0.S;
      if (r0.Sintact.allFinite()) Sintact[0] = r0.Sintact;
      take(plastic[0], r0.plastic), take(temperature[0], r0.temperature);
    }
    if (cap) take(epsVp[0], r0.epsVp); // X, porosity and pore pressure follow from it
    if (cap && mat.cap->rateDependent() && r0.overS.allFinite())
      overS[0] = r0.overS, take(overI1[0], r0.overI1);
    if (tensor && r0.damageTensor.allFinite() && r0.strainTensor.allFinite())
      damageTensor[0] = r0.damageTensor, strainTensor[0] = r0.strainTensor;
  }

  materials::MaterialFields fields() {
    materials::MaterialFields f{rho, e, material, p, cs, L, S, plastic, temperature};
    if (damage) f.id = id, f.damage = D, f.Sintact = Sintact;
    if (flaws)
      f.flawCount = flawCount, f.flawsActive = flawsActive, f.flawScale = flawScale,
      f.flawNext = flawNext;
    if (tensor) f.damageTensor = damageTensor, f.strainTensor = strainTensor;
    if (cap)
      f.volumetricStrain = epsVp, f.capPosition = X, f.porosity = phi, f.porePressure = pf,
      f.returnIterations = iterations;
    if (cap && mat.cap->rateDependent()) f.capOverstress = overS, f.capOverstressI1 = overI1;
    if (porous) f.alpha = alpha, f.porosity = phi, f.returnIterations = iterations;
    if (elastic) f.alphaPlastic = alphaP;
    return f;
  }

  // The CSV's columns (docs/reference.md: the element driver's output) and a row of them.
  std::string header() const {
    std::string header = "t";
    for (int a = 1; a <= 3; ++a)
      for (int b = 1; b <= 3; ++b) header += fmt::format(",F{}{}", a, b);
    for (const char* c : {"sxx", "syy", "szz", "sxy", "syz", "sxz"})
      header += fmt::format(",{}", c);
    for (const char* c : {"usxx", "usyy", "uszz", "usxy", "usyz", "usxz"})
      header += fmt::format(",{}", c);
    header += ",density,specific_internal_energy,pressure,sound_speed";
    if (strength) header += ",plastic_strain,temperature";
    if (cap)
      header += ",plastic_strain,plastic_volumetric_strain,cap_position,porosity,pore_pressure,"
                "return_iterations";
    if (porous) header += ",porosity_alpha,porosity,return_iterations";
    if (elastic) header += ",plastic_distension";
    if (damage) header += ",damage";
    return header;
  }
  std::string row(double t, const Tensor<3>& F) const {
    const Tensor<3> sigma = S[0] - p[0] * Tensor<3>::Identity();
    const Tensor<3> R = polarRotation(F);
    const Tensor<3> unrotated = R.transpose() * sigma * R;
    std::string line = fmt::format("{:.17g}", t);
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) line += fmt::format(",{:.17g}", F(a, b));
    for (const auto& ij : kVoigt) line += fmt::format(",{:.17g}", sigma(ij[0], ij[1]));
    for (const auto& ij : kVoigt) line += fmt::format(",{:.17g}", unrotated(ij[0], ij[1]));
    line += fmt::format(",{:.17g},{:.17g},{:.17g},{:.17g}", rho[0], e[0], p[0], cs[0]);
    if (strength) line += fmt::format(",{:.17g},{:.17g}", plastic[0], temperature[0]);
    if (cap)
      line += fmt::format(",{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{}", plastic[0], epsVp[0], X[0],
                          phi[0], pf[0], iterations[0]);
    if (porous) line += fmt::format(",{:.17g},{:.17g},{}", alpha[0], phi[0], iterations[0]);
    if (elastic) line += fmt::format(",{:.17g}", alphaP[0]);
    if (damage) line += fmt::format(",{:.17g}", D[0]);
    return line;
  }
};

// The options' checks, and the deck's material they name.
std::size_t checkElementOptions(const ElementOptions& o, const Deck& deck) {
  std::size_t k = deck.materials.size();
  std::string names;
  for (std::size_t m = 0; m < deck.materials.size(); ++m) {
    if (deck.materials[m].name == o.material) k = m;
    names += (names.empty() ? "" : ", ") + deck.materials[m].name;
  }
  if (k == deck.materials.size())
    throw UsageError(
        fmt::format("no material '{}' in {} (it has: {})", o.material, o.deckPath, names));
  return k;
}

void checkElementOutput(const ElementOptions& o) {
  if (fs::exists(o.output) && !o.overwrite)
    throw UsageError(o.output + " exists; --overwrite replaces it");
  const fs::path parent = fs::path(o.output).parent_path();
  if (!parent.empty() && !fs::is_directory(parent))
    throw UsageError("the directory of " + o.output + " does not exist");
}

} // namespace

ElementOptions::Kinematics kinematicsFor(const ElementOptions& o) {
  if (o.kinematics) return *o.kinematics;
  return o.state.empty() ? ElementOptions::Kinematics::Midpoint : ElementOptions::Kinematics::Run;
}

void runElement(const ElementOptions& o) {
  if (o.substeps < 1) throw UsageError("--substeps must be at least 1");
  if (!(o.flawVolume > 0.0)) throw UsageError("--flaw-volume must be positive");
  const bool midpoint = kinematicsFor(o) == ElementOptions::Kinematics::Midpoint;
  if (!o.state.empty() && o.substeps != 1)
    throw UsageError("--state replays a recorded particle row by row: --substeps 1");
  const Deck deck = loadDeck(o.deckPath, o.overrides);
  const std::size_t k = checkElementOptions(o, deck);
  const io::FTable table = io::readFTable(o.table);
  const auto recorded = o.state.empty() ? std::vector<RecordedRow>{} : readState(o.state, table);
  checkElementOutput(o);

  const materials::Material mat = buildMaterials(deck)[k];
  const materials::MaterialUpdate update({mat}, deck.run.seed);
  ElementPoint pt(mat, deck.materials[k], table, recorded, deck.run.seed, o.flawVolume);
  materials::MaterialFields f = pt.fields();
  update.evaluate(f);

  // Written to a side file and renamed when complete: a failed drive leaves no partial CSV.
  const std::string partial = o.output + ".part";
  std::string failed; // the material failed (non-finite): the rows before it are kept
  {
    auto out = fmt::output_file(partial);
    out.print("{}\n", pt.header());
    out.print("{}\n", pt.row(table.rows[0].t, totalF(table, 0, 0.0)));
    for (std::size_t r = 0; r + 1 < table.rows.size() && failed.empty(); ++r) {
      const double t0 = table.rows[r].t, span = table.rows[r + 1].t - t0;
      const double dt = span / o.substeps;
      Tensor<3> Fa = totalF(table, r, 0.0);
      for (int s = 1; s <= o.substeps; ++s) {
        const Tensor<3> Fb = totalF(table, r, static_cast<double>(s) / o.substeps);
        // Austin (2013), Eq. 4.10 (the velocity gradient that takes F_n to F_n+1 over dt as a
        // run does) or Eq. 4.8 (midpoint).
        pt.L[0] = midpoint ? Tensor<3>((Fb - Fa) / dt * (0.5 * (Fb + Fa)).inverse())
                           : Tensor<3>((Fb * Fa.inverse() - Tensor<3>::Identity()) / dt);
        // The stress power heats the material (with the stress of the step's start, as a run's
        // explicit energy update); the density follows F exactly.
        const Tensor<3> sigma = pt.S[0] - pt.p[0] * Tensor<3>::Identity();
        const Tensor<3> Dsym = 0.5 * (pt.L[0] + pt.L[0].transpose());
        pt.e[0] += dt * (sigma.cwiseProduct(Dsym)).sum() / pt.rho[0];
        pt.rho[0] = pt.rho0 / Fb.determinant();
        if (recorded.empty()) {
          update.update(f, dt);
        } else { // the run's update, then its re-evaluation at the kick-corrected state
          const RecordedRow& rec = recorded[r + 1];
          pt.rho[0] = rec.rhoUpdate, pt.e[0] = rec.eUpdate;
          update.update(f, dt);
          pt.rho[0] = rec.rho, pt.e[0] = rec.e;
          update.evaluate(f);
        }
        const double t = t0 + span * s / o.substeps;
        if (!pt.S[0].allFinite() || !std::isfinite(pt.p[0]) || !std::isfinite(pt.e[0])) {
          failed = fmt::format("element: non-finite stress at t = {:.9g} (between the rows on "
                               "lines {} and {} of {}); the rows before it are in {}",
                               t, table.rows[r].line, table.rows[r + 1].line, o.table, o.output);
          break;
        }
        if (o.everySubstep || s == o.substeps)
          out.print("{}\n", pt.row(s == o.substeps ? table.rows[r + 1].t : t, Fb));
        Fa = Fb;
      }
    }
  }
  fs::rename(partial, o.output);
  if (!failed.empty()) throw RunError(failed);
}

} // namespace spall::app
