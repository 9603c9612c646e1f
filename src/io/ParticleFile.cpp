#include "spall/io/ParticleFile.hpp"

#include "Hdf5Util.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <span>
#include <sstream>
#include <string_view>

namespace spall::io {

namespace {

std::string trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return std::string(s);
}

// A CSV row's cells, trimmed, each with the 1-based column where its text starts.
struct Cell {
  std::string text;
  int column;
};

std::vector<Cell> cells(const std::string& line) {
  std::vector<Cell> out;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = line.find(',', start);
    const std::string_view raw = std::string_view(line).substr(start, comma - start);
    const std::size_t lead = std::min(raw.find_first_not_of(" \t"), raw.size());
    out.push_back({trim(raw), static_cast<int>(start + lead) + 1});
    if (comma == std::string::npos) return out;
    start = comma + 1;
  }
}

// Where a CSV row and its position's and volume's cells are (1-based line and columns).
struct RowPlace {
  int line, position, volume;
};

std::string header(const std::vector<Cell>& row) {
  std::string out;
  for (const Cell& c : row) out += (out.empty() ? "" : ", ") + c.text;
  return out;
}

// The columns a dimension needs, by name; rz also takes r, z for x, y.
std::vector<std::vector<std::string>> wantedColumns(std::size_t dimension, bool rz) {
  std::vector<std::vector<std::string>> w;
  const char* axes[3] = {"x", "y", "z"};
  for (std::size_t d = 0; d < dimension; ++d) w.push_back({axes[d]});
  if (rz) w[0].push_back("r"), w[1].push_back("z");
  w.push_back({"volume"});
  return w;
}

ParticleCloud readCsv(const std::string& path, std::size_t dimension, bool rz,
                      std::vector<RowPlace>& rows) {
  std::ifstream in(path);
  if (!in) throw DeckError({path, 0, 0}, "cannot open the particle file");
  ParticleCloud c;
  c.path = path;
  c.dimension = dimension;
  std::vector<std::size_t> column; // of each wanted value: its column in a row
  std::size_t width = 0;
  int line = 0;
  for (std::string text; std::getline(in, text);) {
    ++line;
    const std::string t = trim(text);
    if (t.empty() || t.front() == '#') continue;
    const auto row = cells(text);
    if (column.empty()) {
      const auto wanted = wantedColumns(dimension, rz);
      for (const auto& names : wanted) {
        std::size_t found = row.size();
        for (std::size_t k = 0; k < row.size() && found == row.size(); ++k)
          if (std::find(names.begin(), names.end(), row[k].text) != names.end()) found = k;
        if (found == row.size())
          throw DeckError({path, line, 1},
                          fmt::format("the header names no '{}' column (it needs {}; got {})",
                                      fmt::join(names, "' or '"),
                                      dimension == 3   ? "x, y, z, volume"
                                      : dimension == 2 ? (rz ? "r, z, volume" : "x, y, volume")
                                                       : "x, volume",
                                      header(row)));
        column.push_back(found);
      }
      width = row.size();
      continue;
    }
    if (row.size() != width)
      throw DeckError(
          {path, line, row.front().column},
          fmt::format("{} values where the header names {} columns", row.size(), width));
    double v[4];
    for (std::size_t k = 0; k < column.size(); ++k) {
      const std::string& s = row[column[k]].text;
      const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v[k]);
      if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v[k]))
        throw DeckError({path, line, row[column[k]].column},
                        fmt::format("'{}' is not a finite number", s));
    }
    for (std::size_t d = 0; d < dimension; ++d) c.position.push_back(v[d]);
    c.volume.push_back(v[dimension]);
    rows.push_back({line, row[column[0]].column, row[column[dimension]].column});
  }
  if (column.empty()) throw DeckError({path, line, 0}, "the particle file holds no header");
  return c;
}

// A dataset of doubles: its extents and values.
std::vector<double> readDataset(hid_t file, const std::string& path, const char* name,
                                std::vector<hsize_t>& dims) {
  if (H5Lexists(file, name, H5P_DEFAULT) <= 0)
    throw DeckError({path, 0, 0}, fmt::format("the particle file has no dataset '{}'", name));
  hdf5::Handle set(H5Dopen2(file, name, H5P_DEFAULT), H5Dclose, path, "H5Dopen2");
  hdf5::Handle space(H5Dget_space(set), H5Sclose, path, "H5Dget_space");
  const int rank = H5Sget_simple_extent_ndims(space);
  if (rank < 1 || rank > 2)
    throw DeckError({path, 0, 0}, fmt::format("dataset '{}' has rank {}", name, rank));
  dims.assign(static_cast<std::size_t>(rank), 0);
  H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  std::size_t n = 1;
  for (hsize_t d : dims) n *= static_cast<std::size_t>(d);
  std::vector<double> v(n);
  if (n > 0)
    hdf5::check(H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), path,
                "H5Dread");
  return v;
}

ParticleCloud readHdf5(const std::string& path, std::size_t dimension) {
  hdf5::Quiet quiet;
  const hid_t id = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (id < 0)
    throw DeckError({path, 0, 0}, "cannot open the particle file as HDF5: " + hdf5::detail());
  hdf5::Handle file(id, H5Fclose, path, "H5Fopen");
  ParticleCloud c;
  c.path = path;
  c.dimension = dimension;
  std::vector<hsize_t> dp, dv;
  c.position = readDataset(file, path, "position", dp);
  c.volume = readDataset(file, path, "volume", dv);
  const hsize_t n = dp[0];
  const hsize_t cols = dp.size() == 2 ? dp[1] : 1;
  if (cols != dimension || dv.size() != 1 || dv[0] != n)
    throw DeckError({path, 0, 0},
                    fmt::format("dataset 'position' is [{}][{}] and 'volume' [{}]: they must be "
                                "[N][{}] and [N] (run.dimension {})",
                                n, cols, fmt::join(dv, "]["), dimension, dimension));
  return c;
}

} // namespace

ParticleCloud readParticleFile(const std::string& path, std::size_t dimension, bool rz) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw DeckError({path, 0, 0}, std::filesystem::exists(path, ec)
                                      ? "the particle file is not a regular file"
                                      : "the particle file does not exist");
  const bool hdf5 = path.ends_with(".h5") || path.ends_with(".hdf5");
  std::vector<RowPlace> rows; // where each CSV row is, for the messages below
  ParticleCloud c = hdf5 ? readHdf5(path, dimension) : readCsv(path, dimension, rz, rows);
  // A CSV particle's position (its first coordinate) or volume, for the messages below.
  const auto at = [&](std::size_t i, bool volume = false) -> SourceLocation {
    if (hdf5) return {path, 0, 0};
    return {path, rows[i].line, volume ? rows[i].volume : rows[i].position};
  };
  const auto name = [&](std::size_t i) {
    return hdf5 ? fmt::format("particle {} (row {} of the datasets)", i, i)
                : fmt::format("particle {}", i);
  };
  const std::size_t n = c.size(), D = dimension;
  if (n == 0) throw DeckError({path, 0, 0}, "the particle file holds no particles");
  c.lo.assign(D, std::numeric_limits<double>::infinity());
  c.hi.assign(D, -std::numeric_limits<double>::infinity());
  c.coarsest = 0.0;
  c.finest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    const double V = c.volume[i];
    if (!(V > 0.0) || !std::isfinite(V))
      throw DeckError(at(i, true),
                      fmt::format("{} has volume {}: volumes must be > 0", name(i), V));
    for (std::size_t d = 0; d < D; ++d) {
      const double x = c.position[i * D + d];
      if (!std::isfinite(x))
        throw DeckError(at(i), fmt::format("{} has a position that is not finite", name(i)));
      c.lo[d] = std::min(c.lo[d], x), c.hi[d] = std::max(c.hi[d], x);
    }
    if (rz && !(c.position[i * D] > 0.0))
      throw DeckError(at(i), fmt::format("{} has r = {}: in geometry 'rz' a particle is a ring "
                                         "about the axis, r > 0",
                                         name(i), c.position[i * D]));
    const double s = std::pow(V, 1.0 / static_cast<double>(D));
    c.coarsest = std::max(c.coarsest, s), c.finest = std::min(c.finest, s);
  }
  // Two particles at one place would share their kernel's centre: SPH's gradients vanish there.
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  const auto pos = [&](std::size_t i) { return std::span<const double>(&c.position[i * D], D); };
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    const auto pa = pos(a), pb = pos(b);
    return std::lexicographical_compare(pa.begin(), pa.end(), pb.begin(), pb.end());
  });
  for (std::size_t k = 1; k < n; ++k) {
    const auto pa = pos(order[k - 1]), pb = pos(order[k]);
    if (std::equal(pa.begin(), pa.end(), pb.begin())) {
      const std::size_t i = std::max(order[k - 1], order[k]), j = std::min(order[k - 1], order[k]);
      throw DeckError(at(i), fmt::format("{} is at the place of particle {}", name(i), j));
    }
  }
  return c;
}

} // namespace spall::io
