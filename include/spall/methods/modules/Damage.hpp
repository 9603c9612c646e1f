#pragma once
// Damage (a material with `damage`): the damage field, the intact material's stress and, for
// Grady-Kipp materials, each particle's Weibull flaws, drawn at t = 0 from (run.seed, id) and the
// particle's volume (materials/Damage.hpp), never from the rank. MaterialUpdate advances them; the
// solver reads the damage of neighbors (a pair with a failed particle carries no tension).
#include "spall/materials/Damage.hpp"
#include "spall/methods/Module.hpp"

#include <cstdint>
#include <optional>
#include <vector>

namespace spall::methods {

template <int Dim> class Damage final : public Module<Dim> {
public:
  // flaws: by material, the Grady-Kipp model of the materials that have one.
  Damage(std::vector<std::optional<materials::GradyKipp>> flaws, std::uint64_t seed)
      : flaws_(std::move(flaws)), seed_(seed) {
    for (const auto& g : flaws_) {
      anyFlaws_ = anyFlaws_ || g.has_value();
      anyTensor_ = anyTensor_ || (g && g->tensor);
    }
  }
  static void addFields(ParticleStore& s, ParticleFields<Dim>& f, bool flaws, bool tensor = false) {
    constexpr unsigned out = spall::kOutput | spall::kCheckpoint;
    f.damage = s.add<double>("damage", out | spall::kHalo);
    f.Sintact = s.add<Tensor<3>>("deviatoric_stress_intact", spall::kCheckpoint);
    if (!flaws) return;
    f.flawCount = s.add<std::int32_t>("flaw_count", out);
    f.flawsActive = s.add<std::int32_t>("flaws_active", out);
    f.flawScale = s.add<double>("flaw_strain_scale", spall::kCheckpoint);
    f.flawNext = s.add<double>("next_flaw_strain", out);
    if (!tensor) return;
    // Snapshots get the Dim x Dim block as `damage_tensor` (app/RunOutput.cpp).
    f.damageTensor = s.add<Tensor<3>>("damage_tensor_3x3", spall::kCheckpoint);
    f.strainTensor = s.add<Tensor<3>>("strain_tensor", spall::kCheckpoint);
  }
  void registerFields(ParticleStore& s, ParticleFields<Dim>& f) override {
    addFields(s, f, anyFlaws_, anyTensor_);
  }
  void initialise(ParticleStore& s, const ParticleFields<Dim>& f,
                  const RunStart& start) const override {
    const auto mat = s[f.material];
    for (std::size_t i = start.first; i < s.localCount(); ++i) {
      s[f.damage][i] = 0.0;
      s[f.Sintact][i].setZero();
      if (anyTensor_) s[f.damageTensor][i].setZero(), s[f.strainTensor][i].setZero();
    }
    if (!anyFlaws_) return;
    const auto id = s[f.id];
    const auto body = s[f.body];
    const auto m = s[f.m];
    const auto rho = s[f.rho];
    for (std::size_t i = start.first; i < s.localCount(); ++i) {
      const auto& g = flaws_[static_cast<std::size_t>(mat[i])];
      s[f.flawsActive][i] = 0;
      if (!g) {
        s[f.flawCount][i] = 0;
        s[f.flawScale][i] = 0.0;
        s[f.flawNext][i] = 0.0;
        continue;
      }
      const double V = materials::flawVolume<Dim>(m[i] / rho[i]);
      const materials::FlawSet set = materials::drawFlaws(
          *g, seed_, id[i], V, start.bodyParticles[static_cast<std::size_t>(body[i])]);
      s[f.flawCount][i] = set.count;
      s[f.flawScale][i] = set.scale;
      s[f.flawNext][i] = set.first;
    }
  }

private:
  std::vector<std::optional<materials::GradyKipp>> flaws_; // by material
  std::uint64_t seed_;
  bool anyFlaws_ = false, anyTensor_ = false;
};

} // namespace spall::methods
