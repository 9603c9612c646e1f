// The [[material]] tables: equation of state, strength, damage and erosion (materials/).
#include "DeckDetail.hpp"

#include <algorithm>

namespace spall::io::deck_detail {

namespace {

// The reader of a table inside r's.
TableReader child(const TableReader& r, const toml::table& t, Context c) {
  return {t, std::move(c), r.deckPath()};
}

void readEos(const TableReader& r, EosConfig& e) {
  e.where = r.where();
  e.type = readType(r, "material.eos", kEosNames, "eos type");
  const auto need = [&](std::string_view key) { return r.required(r.number(key), key); };
  switch (e.type) {
  case EosType::IdealGas:
    e.gamma = need("gamma");
    r.check(e.gamma > 1.0, "gamma", "> 1", e.gamma);
    break;
  case EosType::Linear:
    e.bulk_modulus = need("bulk_modulus");
    r.check(e.bulk_modulus > 0.0, "bulk_modulus", "> 0", e.bulk_modulus);
    break;
  case EosType::MieGruneisen:
    e.c0 = need("c0");
    r.check(e.c0 > 0.0, "c0", "> 0", e.c0);
    e.s = need("s");
    e.gamma0 = need("gamma0");
    break;
  case EosType::Tillotson:
    e.a = need("a");
    e.b = need("b");
    e.A = need("A");
    e.B = need("B");
    e.alpha = need("alpha");
    e.beta = need("beta");
    e.e0 = need("e0");
    e.e_iv = need("e_iv");
    e.e_cv = need("e_cv");
    r.check(e.a >= 0.0, "a", ">= 0", e.a);
    r.check(e.b >= 0.0, "b", ">= 0", e.b);
    r.check(e.A > 0.0, "A", "> 0", e.A);
    r.check(e.alpha >= 0.0, "alpha", ">= 0", e.alpha);
    r.check(e.beta >= 0.0, "beta", ">= 0", e.beta);
    r.check(e.e0 > 0.0, "e0", "> 0", e.e0);
    r.check(e.e_iv > 0.0, "e_iv", "> 0", e.e_iv);
    r.check(e.e_cv > e.e_iv, "e_cv", "> e_iv (" + formatNumber(e.e_iv) + ")", e.e_cv);
    break;
  }
  if (e.type != EosType::IdealGas) {
    e.min_pressure = r.number("min_pressure").value_or(e.min_pressure);
    r.check(e.min_pressure <= 0.0, "min_pressure", "<= 0 (a tension, Pa)", e.min_pressure);
  }
}

// strength = {type = "cap", ...}: the keys of docs/reference.md; compression negative.
void readCap(const TableReader& r, StrengthConfig& c) {
  const auto need = [&](std::string_view key) { return r.required(r.number(key), key); };
  c.bulk_modulus = need("bulk_modulus");
  r.check(c.bulk_modulus > 0.0, "bulk_modulus", "> 0", c.bulk_modulus);
  c.peak_i1 = need("peak_i1");
  r.check(c.peak_i1 >= 0.0, "peak_i1", ">= 0 (I1 at the tensile vertex, Pa)", c.peak_i1);
  c.f_slope = need("f_slope");
  r.check(c.f_slope > 0.0, "f_slope", "> 0", c.f_slope);
  c.cap_ratio = need("cap_ratio");
  r.check(c.cap_ratio > 0.0, "cap_ratio", "> 0", c.cap_ratio);
  c.crush_p0 = need("crush_p0");
  r.check(c.crush_p0 < 0.0, "crush_p0", "< 0 (the initial cap position: I1, compression negative)",
          c.crush_p0);
  c.crush_p1 = need("crush_p1");
  r.check(c.crush_p1 > 0.0, "crush_p1", "> 0 (1/Pa)", c.crush_p1);
  c.crush_p3 = need("crush_p3");
  r.check(c.crush_p3 > 0.0, "crush_p3", "> 0 (the largest compaction strain)", c.crush_p3);
  c.hardening = r.boolean("hardening").value_or(true);
  c.dilatancy = r.number("dilatancy").value_or(1.0);
  r.check(c.dilatancy >= 0.0 && c.dilatancy <= 1.0, "dilatancy", "in [0, 1]", c.dilatancy);
  c.fluid_bulk_modulus = r.number("fluid_bulk_modulus").value_or(0.0);
  r.check(c.fluid_bulk_modulus >= 0.0, "fluid_bulk_modulus", ">= 0 (0: drained)",
          c.fluid_bulk_modulus);
  c.initial_pore_pressure = r.number("initial_pore_pressure").value_or(0.0);
  r.check(c.initial_pore_pressure >= 0.0, "initial_pore_pressure", ">= 0", c.initial_pore_pressure);
}

// The keys of a model that heats by its plastic work: the starting temperature (K, absolute), the
// specific heat and the share of the work that heats (Taylor-Quinney).
void readHeating(const TableReader& r, StrengthConfig& c) {
  const auto need = [&](std::string_view key) { return r.required(r.number(key), key); };
  c.room_temperature = need("room_temperature");
  r.check(c.room_temperature > 0.0, "room_temperature", "> 0 (K)", c.room_temperature);
  c.specific_heat = need("specific_heat");
  r.check(c.specific_heat > 0.0, "specific_heat", "> 0", c.specific_heat);
  c.taylor_quinney = need("taylor_quinney");
  r.check(c.taylor_quinney >= 0.0 && c.taylor_quinney <= 1.0, "taylor_quinney", "in [0, 1]",
          c.taylor_quinney);
}

// Zerilli & Armstrong (1987): each constant optional (0 by default: an fcc metal sets C0, C2, C3,
// C4; a bcc one C0, C1, C3, C4, C5, n), all >= 0, and some stress to yield at.
void readZerilliArmstrong(const TableReader& r, StrengthConfig& c) {
  const auto constant = [&](std::string_view key, const char* unit) {
    const double v = r.number(key).value_or(0.0);
    r.check(v >= 0.0, key, std::string(">= 0 (") + unit + ")", v);
    return v;
  };
  c.C0 = constant("C0", "Pa");
  c.C1 = constant("C1", "Pa");
  c.C2 = constant("C2", "Pa");
  c.C3 = constant("C3", "1/K");
  c.C4 = constant("C4", "1/K");
  // The metals of Zerilli & Armstrong have C4 ~ 1e-4/K; past 1e-2/K exp(C4 T ln rate) overflows
  // in reach of a hypervelocity scene (T 3000 K, rate 1e10/s) and the return stalls.
  r.check(c.C4 <= 1e-2, "C4", "<= 1e-2 (1/K; metals have ~1e-4)", c.C4);
  c.C5 = constant("C5", "Pa");
  r.check(c.C0 + c.C1 + c.C2 + c.C5 > 0.0, "C0",
          "> 0, or one of C1, C2, C5 > 0 (the model has no stress to yield at)", c.C0);
  c.n = r.number("n").value_or(1.0);
  r.check(c.n > 0.0, "n", "> 0", c.n);
  c.reference_strain_rate = r.number("reference_strain_rate").value_or(1.0);
  r.check(c.reference_strain_rate > 0.0, "reference_strain_rate", "> 0 (1/s)",
          c.reference_strain_rate);
  readHeating(r, c);
}

void readStrength(const TableReader& r, StrengthConfig& c) {
  c.where = r.where();
  c.type = readType(r, "material.strength", kStrengthNames, "strength type");
  const auto need = [&](std::string_view key) { return r.required(r.number(key), key); };
  if (c.type == StrengthType::None) return;
  c.shear_modulus = need("shear_modulus");
  r.check(c.shear_modulus > 0.0, "shear_modulus", "> 0", c.shear_modulus);
  switch (c.type) {
  case StrengthType::None:
  case StrengthType::Elastic:
    break;
  case StrengthType::Cap:
    readCap(r, c);
    break;
  case StrengthType::VonMises:
    c.yield_stress = need("yield_stress");
    r.check(c.yield_stress > 0.0, "yield_stress", "> 0", c.yield_stress);
    break;
  case StrengthType::JohnsonCook:
    c.A = need("A");
    r.check(c.A > 0.0, "A", "> 0", c.A);
    c.B = need("B");
    r.check(c.B >= 0.0, "B", ">= 0", c.B);
    c.n = need("n");
    r.check(c.n > 0.0, "n", "> 0", c.n);
    c.C = need("C");
    r.check(c.C >= 0.0, "C", ">= 0", c.C);
    c.m = need("m");
    r.check(c.m > 0.0, "m", "> 0", c.m);
    c.reference_strain_rate = need("reference_strain_rate");
    r.check(c.reference_strain_rate > 0.0, "reference_strain_rate", "> 0", c.reference_strain_rate);
    readHeating(r, c);
    c.melt_temperature = need("melt_temperature");
    r.check(c.melt_temperature > c.room_temperature, "melt_temperature", "> room_temperature",
            c.melt_temperature);
    c.strain_rate = r.choice("strain_rate", kStrainRateNames, StrainRate::Plastic);
    break;
  case StrengthType::ZerilliArmstrong:
    readZerilliArmstrong(r, c);
    break;
  }
}

void readDamage(const TableReader& r, DamageConfig& c) {
  c.where = r.where();
  c.type = readType(r, "material.damage", kDamageNames, "damage type");
  const auto need = [&](std::string_view key) { return r.required(r.number(key), key); };
  switch (c.type) {
  case DamageType::None:
    break;
  case DamageType::GradyKipp:
    c.weibull_k = need("weibull_k");
    r.check(c.weibull_k > 0.0, "weibull_k", "> 0 (flaws per m^3)", c.weibull_k);
    c.weibull_m = need("weibull_m");
    r.check(c.weibull_m > 0.0, "weibull_m", "> 0", c.weibull_m);
    c.crack_speed = r.number("crack_speed").value_or(c.crack_speed);
    r.check(c.crack_speed > 0.0 && c.crack_speed <= 1.0, "crack_speed",
            "in (0, 1] (a fraction of the longitudinal sound speed)", c.crack_speed);
    c.mode = r.choice("mode", kDamageModeNames, DamageMode::Scalar);
    break;
  case DamageType::JohnsonCook:
    c.D1 = need("D1");
    c.D2 = need("D2");
    c.D3 = need("D3");
    c.D4 = need("D4");
    c.D5 = need("D5");
    c.reference_strain_rate = need("reference_strain_rate");
    r.check(c.reference_strain_rate > 0.0, "reference_strain_rate", "> 0", c.reference_strain_rate);
    c.room_temperature = need("room_temperature");
    r.check(c.room_temperature > 0.0, "room_temperature", "> 0", c.room_temperature);
    c.melt_temperature = need("melt_temperature");
    r.check(c.melt_temperature > c.room_temperature, "melt_temperature", "> room_temperature",
            c.melt_temperature);
    break;
  }
}

// porosity = {type = "p_alpha", ...}: the crush curve of materials/Porosity.hpp.
void readPorosity(const TableReader& r, PorosityConfig& c) {
  c.where = r.where();
  c.type = readType(r, "material.porosity", kPorosityNames, "porosity type");
  const auto need = [&](std::string_view key) { return r.required(r.number(key), key); };
  c.alpha0 = need("alpha0");
  r.check(c.alpha0 >= 1.0, "alpha0", ">= 1 (the distension: solid over bulk density)", c.alpha0);
  c.elastic_pressure = need("elastic_pressure");
  r.check(c.elastic_pressure >= 0.0, "elastic_pressure", ">= 0", c.elastic_pressure);
  c.solid_pressure = need("solid_pressure");
  r.check(c.solid_pressure > c.elastic_pressure, "solid_pressure",
          "> elastic_pressure (" + formatNumber(c.elastic_pressure) + ")", c.solid_pressure);
  c.exponent = r.number("exponent").value_or(c.exponent);
  r.check(c.exponent > 0.0, "exponent", "> 0", c.exponent);
  c.transition_pressure = r.number("transition_pressure");
  c.alpha_transition = r.number("alpha_transition");
  c.exponent_transition = r.number("exponent_transition");
  const int given = int(c.transition_pressure.has_value()) + int(c.alpha_transition.has_value()) +
                    int(c.exponent_transition.has_value());
  if (given > 0 && given < 3) { // point at a key that is there, name the one that is not
    const Names keys{"transition_pressure", "alpha_transition", "exponent_transition"};
    const auto there = *std::find_if(keys.begin(), keys.end(), [&](auto k) { return r.has(k); });
    const auto absent = *std::find_if(keys.begin(), keys.end(), [&](auto k) { return !r.has(k); });
    r.fail(there, "a two-stage crush curve in " + r.context().human +
                      " needs transition_pressure, alpha_transition and exponent_transition; '" +
                      std::string(absent) + "' is missing");
  }
  if (given == 3) {
    const double Pt = *c.transition_pressure, at = *c.alpha_transition;
    r.check(Pt > c.elastic_pressure && Pt < c.solid_pressure, "transition_pressure",
            "between elastic_pressure and solid_pressure", Pt);
    r.check(at > 1.0 && at < c.alpha0, "alpha_transition",
            "in (1, alpha0 (" + formatNumber(c.alpha0) + ")): strictly between, each stage crushes",
            at);
    r.check(*c.exponent_transition > 0.0, "exponent_transition", "> 0", *c.exponent_transition);
  }
  // Checked against the matrix's sound speed where the EOS is built (app/Setup.cpp).
  if (const auto ce = r.number("elastic_sound_speed")) {
    r.check(*ce > 0.0, "elastic_sound_speed", "> 0 (m/s)", *ce);
    if (c.alpha0 <= 1.0)
      r.fail("elastic_sound_speed", "elastic_sound_speed is the speed of the porous material at "
                                    "alpha0, and alpha0 = 1 is not porous");
    c.elastic_sound_speed = *ce;
    c.soundSpeedWhere = r.whereValue("elastic_sound_speed");
  }
}

} // namespace

void readMaterial(const TableReader& r, MaterialConfig& m) {
  r.allowOnly(*schemaKeys("material"));
  m.where = r.where();
  m.density = r.required(r.number("density"), "density");
  r.check(m.density > 0.0, "density", "> 0", m.density);
  if (const toml::table* t = r.subtable("strength")) {
    const TableReader s = child(r, *t, r.context().child("strength"));
    readStrength(s, m.strength);
  }
  const toml::table* eos = r.subtable("eos");
  if (m.strength.type == StrengthType::Cap) { // the cap model's elasticity is its equation of state
    if (r.has("eos"))
      r.fail("eos", "a 'cap' material computes its whole stress, pressure included, from its own "
                    "bulk_modulus and plasticity: remove 'eos' from " +
                        r.context().human);
    if (r.has("porosity"))
      r.fail("porosity", "a 'cap' material carries its own porosity (crush curve and pore "
                         "fluid): remove 'porosity' from " +
                             r.context().human);
    if (r.has("damage"))
      r.fail("damage", "damage of a 'cap' material is not available yet (its cap retracts as it "
                       "dilates: the model's own softening)");
  } else {
    if (!eos) r.missing("eos");
    readEos(child(r, *eos, r.context().child("eos")), m.eos);
  }
  if (const toml::table* t = r.subtable("damage")) {
    readDamage(child(r, *t, r.context().child("damage")), m.damage);
    if (m.strength.type == StrengthType::None)
      r.fail("damage", "damage in " + r.context().human +
                           " degrades a material's strength, and this material has none (add "
                           "strength = {type = ...})");
    if (m.damage.type == DamageType::JohnsonCook && !m.strength.hasPlasticStrain())
      r.fail("damage", "Johnson-Cook damage accumulates plastic strain; strength type '" +
                           std::string(kStrengthNames(m.strength.type)) +
                           "' has none (use von_mises, johnson_cook or zerilli_armstrong)");
  } else if (r.has("damage")) {
    r.fail("damage", "damage must be a table, e.g. {type = \"grady_kipp\", ...}");
  }
  if (const toml::table* t = r.subtable("porosity"))
    readPorosity(child(r, *t, r.context().child("porosity")), m.porosity);
  m.erosion = r.choice("erosion", materials::kErosionNames, materials::Erosion::None);
  if (m.erosion != materials::Erosion::None && m.damage.type == DamageType::None)
    r.fail("erosion", "erosion says what a fully damaged particle carries, and " +
                          r.context().human + " has no damage");
}

} // namespace spall::io::deck_detail
