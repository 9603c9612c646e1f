#pragma once
// Particles from a file (a mesher's output) for a body of shape 'particles': positions and the
// volume each stands for. CSV: a header naming the columns (x[,y[,z]],volume; r,z,volume also in
// rz), then a row a particle; '#' starts a comment line. HDF5 (.h5, .hdf5): datasets `position`
// [N][dim] and `volume` [N]. Every problem is a DeckError at the file's line (CSV) or naming the
// dataset (HDF5).
#include "spall/io/Deck.hpp"

#include <cstddef>
#include <string>

namespace spall::io {

// `path` as given (absolute, or as the caller resolved it); `rz`: x is the radius (r > 0).
ParticleCloud readParticleFile(const std::string& path, std::size_t dimension, bool rz);

} // namespace spall::io
