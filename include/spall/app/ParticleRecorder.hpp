#pragma once
// Particles recorded every step ([output] record_particles): for each, an F-table of its
// deformation gradient (particles/particle_ID.ftable, what `spall element` replays and `spall
// history` hands out) and its stress and state (particles/particle_ID.csv, what the replay is
// compared with). The owner rank fills a row, one reduction brings every row to rank 0, which
// writes them; a restart drops the rows after its checkpoint.
#include "spall/core/ParticleFields.hpp"
#include "spall/io/CsvLog.hpp"
#include "spall/io/Deck.hpp"
#include "spall/parallel/Mpi.hpp"

#include <cstdint>
#include <filesystem>
#include <vector>

namespace spall::app {

template <int Dim> class ParticleRecorder {
public:
  explicit ParticleRecorder(const OutputConfig& output);
  bool empty() const { return ids_.empty(); }
  // Collective: every id names a particle of the run (else a DeckError at the deck key).
  void check(const ParticleStore& s, const ParticleFields<Dim>& f,
             const parallel::MpiContext& mpi) const;
  // Rank 0: the files, new, or continued after a restart at `time`. A cap material's state
  // (plastic volumetric strain, cap position, porosity, pore pressure) is recorded when f has it.
  void open(const std::filesystem::path& dir, bool resumed, double time,
            const ParticleFields<Dim>& f, const parallel::MpiContext& mpi);
  // Collective: the recorded particles' rows at `time`.
  void write(double time, const ParticleStore& s, const ParticleFields<Dim>& f,
             const parallel::MpiContext& mpi);

private:
  std::vector<std::int64_t> ids_;
  bool cap_ = false;
  SourceLocation where_;
  std::vector<io::CsvLog> tables_, states_;
};

} // namespace spall::app
