// [[material]] itself: its name, density and erosion, and the tables of its models (each read by
// its own key file; io/DeckMaterial.cpp joins them and checks how they combine).
#include "Keys.hpp"

namespace spall::io::keys {

namespace {

template <class K> void keysOf(K& k, MaterialConfig& m) {
  k.section("", "A material: its reference density and its models, each a table with a type.");
  k.other("name", "string", "required", "", "unique, non-empty, no '.'",
          "What bodies and jets call it by; --set addresses it as material.NAME.");
  k.other("library", "string", "none", "", "a file of decks/materials (NAME.toml)",
          "A published set to start from: its keys fill what this entry leaves out.");
  k.number("density", m.density, required, "kg/m^3", above(0),
           "rho0, the reference density (a porous material's: its matrix's).");
  k.note("density", "warns outside [50, 25000] unless the eos is ideal_gas (g/cm^3 typed for "
                    "kg/m^3?): aerogels and foams to osmium's 22590");
  k.table("eos", "required unless strength is cap", "not with a cap strength",
          "The equation of state: {type = ..., ...}.");
  k.table("strength", "none", "", "The strength model: {type = ..., ...}; none: a fluid.");
  k.table("damage", "none", "needs a strength model, not cap",
          "The damage model: {type = ..., ...}.");
  k.choice("erosion", m.erosion, materials::kErosionNames, materials::Erosion::None,
           "What a fully damaged particle carries (Austin 2013, Sec. 6.4, Eqs. 6.11-6.14).");
  k.note("erosion", "needs damage, but \"none\"");
  k.table("porosity", "none", "not with a cap strength",
          "The porosity model: {type = \"p_alpha\", ...}.");
}

} // namespace

std::vector<KeySection> material() {
  return {sectionOf<MaterialConfig>(
      "material", [](auto& k, auto& m) -> decltype(keysOf(k, m)) { keysOf(k, m); })};
}

void readMaterialKeys(const deck_detail::TableReader& r, MaterialConfig& m) {
  Read read(r);
  keysOf(read, m);
}

} // namespace spall::io::keys
