#pragma once
// XDMF 3 descriptions of the snapshot HDF5 files, so ParaView, VisIt and meshio open them
// directly: one .xmf per point set of a snapshot (the particles, or MPM's grid nodes: a
// polyvertex grid, every field a node attribute, the position as well) and a temporal collection
// of them that carries the times. Serial: call on one rank.
#include "spall/core/ParticleStore.hpp"

#include <cstddef>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace spall::io {

// A group of h5FileName's rows as a point set: `fields` its datasets, one of them "position".
struct XdmfPoints {
  std::string group; // "particles", "grid"
  std::size_t globalCount = 0;
  std::span<const FieldInfo> fields;
};

// One Uniform grid, the form meshio reads: no Time element (meshio refuses one in a grid; the
// series carries the times). h5FileName is relative to the .xmf; the vertex list and, in 1D, the
// points are the file's /xdmf datasets (Snapshot.hpp). Written atomically (tmp file, rename).
void writeSnapshotXdmf(const std::string& xmfPath, const std::string& h5FileName, int dimension,
                       const XdmfPoints& set);

// A temporal collection of (time, snapshot .xmf relative to seriesPath's folder), in time order:
// each snapshot's grid inline with its Time, which ParaView, VisIt and meshio's TimeSeriesReader
// all read (XInclude is not read by meshio). Written atomically, so a viewer polling the file
// never sees half of it.
void writeSeriesXdmf(const std::string& seriesPath,
                     const std::vector<std::pair<double, std::string>>& snapshots);

} // namespace spall::io
