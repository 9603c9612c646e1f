#pragma once
// Probes (docs/reference.md, [[probe]]): "material" follows the particle nearest the probe position
// at t = 0 (by id, so it survives reordering and, later, migration); "space" interpolates at a
// fixed point with the Shepard-normalised kernel sum over the particles whose support covers it.
#include "spall/core/ParticleFields.hpp"
#include "spall/io/Deck.hpp"
#include "spall/parallel/Mpi.hpp"

#include <string>
#include <vector>

namespace spall::diagnostics {

// A probe field, resolved once from its name.
struct ProbeField {
  enum class Kind {
    Position,
    Velocity,
    Stress,
    HoopStress, // 2D: sigma_tt = S_tt - p (rz: the hoop stress; plane strain: the out-of-plane one)
    Pressure,
    Density,
    Energy,
    SoundSpeed,
    Mass,
    SmoothingLength,
    Column // a scalar snapshot field of the store (plastic_strain, damage, ...), by column
  };
  Kind kind;
  int a = 0, b = 0; // components, or the column index (Column)
  std::string name;
};

// Throws DeckError at `where` for a name this dimension does not have. With a store, every
// snapshot field it holds is a probe field too (the physics modules' fields: plastic_strain,
// temperature, damage, ...), a vector's or tensor's by component: name_x, and name_xy = T(x, y)
// as stress_xy is (deformation_gradient_xy = dx/dY, particle_domain_xy = r_2's x).
ProbeField resolveProbeField(const std::string& name, int dim, const SourceLocation& where,
                             const ParticleStore* store = nullptr);
// All probe field names available in `dim` dimensions (for messages and `spall check`).
std::vector<std::string> probeFieldNames(int dim, const ParticleStore* store = nullptr);

struct ProbeSample {
  std::string probe, field;
  double value;
};

template <int Dim> class Probes {
public:
  // axisymmetric: space probes weigh a particle by its area m/(2 pi r rho), not its ring volume.
  Probes(const std::vector<ProbeConfig>& config, const ParticleStore& store,
         bool axisymmetric = false);
  // Material probes pick their particle (global nearest, lowest id on ties).
  void attach(const ParticleStore& s, const ParticleFields<Dim>& f,
              const parallel::MpiContext& mpi);
  // Values of every probe field now; identical on every rank.
  std::vector<ProbeSample> sample(const ParticleStore& s, const ParticleFields<Dim>& f,
                                  const parallel::MpiContext& mpi, double support);
  bool empty() const { return probes_.empty(); }
  // The particle each probe follows (0 for "space" probes), for checkpoints, and back.
  std::vector<ParticleId> tracked() const {
    std::vector<ParticleId> ids;
    for (const auto& p : probes_) ids.push_back(p.particle);
    return ids;
  }
  void restoreTracked(const std::vector<ParticleId>& ids) {
    for (std::size_t k = 0; k < probes_.size() && k < ids.size(); ++k) {
      probes_[k].particle = ids[k];
      probes_[k].cachedIndex = 0;
    }
  }
  std::size_t size() const { return probes_.size(); }

private:
  bool axisymmetric_;
  struct Probe {
    ProbeConfig config;
    std::vector<ProbeField> fields;
    ParticleId particle = 0;
    std::size_t cachedIndex = 0;
  };
  std::vector<Probe> probes_;
  std::vector<std::size_t> who_; // a sample's scratch: the particles that hold a probe's value
  std::vector<double> weight_;
};

} // namespace spall::diagnostics
