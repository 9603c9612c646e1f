#pragma once
// P-alpha porosity (a material with `porosity`, materials/Porosity.hpp): the distension alpha,
// the history MaterialUpdate advances, and the porosity 1 - 1/alpha it means. Particles start at
// their material's alpha0 (1: not porous). With elastic distension, also its plastic part.
#include "spall/methods/Module.hpp"

#include <vector>

namespace spall::methods {

template <int Dim> class PAlpha final : public Module<Dim> {
public:
  // `elastic`: some material has elastic distension (its plastic part is then a field too).
  PAlpha(std::vector<double> alpha0, bool elastic)
      : alpha0_(std::move(alpha0)), elastic_(elastic) {}
  static void addFields(ParticleStore& s, ParticleFields<Dim>& f, bool elastic) {
    constexpr unsigned out = spall::kOutput | spall::kCheckpoint;
    f.alpha = s.add<double>("porosity_alpha", out);
    if (elastic) f.alphaPlastic = s.add<double>("plastic_distension", out);
    if (!f.porosity.valid()) f.porosity = s.add<double>("porosity", out);
  }
  void registerFields(ParticleStore& s, ParticleFields<Dim>& f) override {
    addFields(s, f, elastic_);
  }
  void initialise(ParticleStore& s, const ParticleFields<Dim>& f,
                  const RunStart& start) const override {
    for (std::size_t i = start.first; i < s.localCount(); ++i) {
      const double a = alpha0_[static_cast<std::size_t>(s[f.material][i])];
      s[f.alpha][i] = a;
      s[f.porosity][i] = 1.0 - 1.0 / a;
      if (elastic_) s[f.alphaPlastic][i] = a;
    }
  }

private:
  std::vector<double> alpha0_; // by material index
  bool elastic_;
};

} // namespace spall::methods
