// The [[material]] tables: equation of state, strength, damage and erosion (materials/).
#include "DeckDetail.hpp"
#include "keys/Keys.hpp"

#include <algorithm>

namespace spall::io::deck_detail {

namespace {

// The reader of a table inside r's.
TableReader child(const TableReader& r, const toml::table& t, Context c) {
  return {t, std::move(c), r.deckPath(), r.notes()};
}

// A typed table's type: one of the types its key table lists (required), the table's keys
// checked against that type's.
std::string typeOf(const TableReader& r, std::string_view path, const std::string& noun) {
  std::string type = r.choice("type", typeNames(path), std::nullopt);
  allowTypedKeys(r, path, type, noun);
  return type;
}

} // namespace

void readMaterial(const TableReader& r, MaterialConfig& m) {
  r.allowOnly(*schemaKeys("material"));
  m.where = r.where();
  keys::readMaterialKeys(r, m); // density, erosion
  if (const toml::table* t = r.subtable("strength")) {
    const TableReader s = child(r, *t, r.context().child("strength"));
    m.strength.where = s.where();
    m.strength.model = keys::readStrength(s, typeOf(s, "material.strength", "strength type"));
  }
  const toml::table* eos = r.subtable("eos");
  if (m.strength.cap()) { // the cap model's elasticity is its equation of state
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
    std::get<materials::CapPlasticity>(m.strength.model).rho0 = m.density;
  } else {
    if (!eos) r.missing("eos");
    const TableReader e = child(r, *eos, r.context().child("eos"));
    m.eos.where = e.where();
    m.eos.model = keys::readEos(e, typeOf(e, "material.eos", "eos type"), m.eos.min_pressure);
    std::visit(
        [&](auto& model) {
          if constexpr (requires { model.rho0; }) model.rho0 = m.density;
        },
        m.eos.model);
  }
  // A solid's or liquid's reference density (MaterialKeys' note on density).
  constexpr double kLightest = 50.0, kDensest = 25000.0;
  const bool gas = !m.strength.cap() && std::holds_alternative<materials::IdealGas>(m.eos.model);
  if (!gas && (m.density < kLightest || m.density > kDensest))
    r.warn("density", fmt::format("{} = {} kg/m^3 is {} for a solid or liquid: {}",
                                  r.quoted("density"), formatNumber(m.density),
                                  m.density < kLightest ? "below 50 kg/m^3" : "above 25000 kg/m^3",
                                  m.density < kLightest ? "g/cm^3 typed for kg/m^3?"
                                                        : "denser than osmium (22590 kg/m^3)"));
  if (const toml::table* t = r.subtable("damage")) {
    const TableReader d = child(r, *t, r.context().child("damage"));
    m.damage.where = d.where();
    m.damage.model = keys::readDamage(d, typeOf(d, "material.damage", "damage type"));
    if (m.strength.none())
      r.fail("damage", "damage in " + r.context().human +
                           " degrades a material's strength, and this material has none (add "
                           "strength = {type = ...})");
    if (std::holds_alternative<materials::JohnsonCookDamage>(m.damage.model) &&
        !m.strength.hasPlasticStrain())
      r.fail("damage", "Johnson-Cook damage accumulates plastic strain; strength type '" +
                           std::string(strengthTypeName(m.strength)) +
                           "' has none (use von_mises, johnson_cook or zerilli_armstrong)");
  } else if (r.has("damage")) {
    r.fail("damage", "damage must be a table, e.g. {type = \"grady_kipp\", ...}");
  }
  if (const toml::table* t = r.subtable("porosity")) {
    const TableReader p = child(r, *t, r.context().child("porosity"));
    m.porosity.where = p.where();
    m.porosity.type = kPorosityNames.at(typeOf(p, "material.porosity", "porosity type"));
    keys::readPorosity(p, m.porosity);
  }
  if (m.erosion != materials::Erosion::None && m.damage.none())
    r.fail("erosion", "erosion says what a fully damaged particle carries, and " +
                          r.context().human + " has no damage");
}

} // namespace spall::io::deck_detail
