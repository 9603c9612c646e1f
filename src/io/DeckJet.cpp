// [[jet]]: a discrete jet (Austin 2013, Fig. 5.2), a train of cylindrical segments each with its
// own radius, length, speed and insert time, turned into bodies that join the run at their times.
#include "DeckDetail.hpp"
#include "keys/Keys.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace spall::io::deck_detail {

namespace {

constexpr std::array<const char*, 5> kColumns{"segment", "radius", "length", "velocity",
                                              "insert_time"};

std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ',')) {
    const auto a = cell.find_first_not_of(" \t\r"), b = cell.find_last_not_of(" \t\r");
    cells.push_back(a == std::string::npos ? "" : cell.substr(a, b - a + 1));
  }
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

// The rows of a jet file (columns in any order, named by its header), each
// [segment, radius, length, velocity, insert_time]; errors at the file's line and column.
toml::array readJetFile(const std::string& file, const SourceLocation& from) {
  std::ifstream in(file);
  if (!in) throw DeckError(from, "cannot read the jet file '" + file + "'");
  std::string line;
  int lineNo = 0;
  std::vector<int> column(kColumns.size(), -1);
  std::size_t cells = 0;
  toml::array rows;
  const auto fail = [&](int col, const std::string& message) {
    throw DeckError({file, lineNo, col}, message);
  };
  while (std::getline(in, line)) {
    ++lineNo;
    if (line.find_first_not_of(" \t\r") == std::string::npos || line[0] == '#') continue;
    const auto c = splitCsv(line);
    if (cells == 0) { // the header
      for (std::size_t k = 0; k < c.size(); ++k)
        for (std::size_t n = 0; n < kColumns.size(); ++n)
          if (c[k] == kColumns[n]) column[n] = static_cast<int>(k);
      for (std::size_t n = 0; n < kColumns.size(); ++n)
        if (column[n] < 0)
          fail(1, std::string("the jet file's header has no column '") + kColumns[n] +
                      "' (columns: segment,radius,length,velocity,insert_time)");
      cells = c.size();
      continue;
    }
    if (c.size() != cells)
      fail(1, "a row of " + std::to_string(c.size()) + " cells under a header of " +
                  std::to_string(cells));
    toml::array row;
    for (std::size_t n = 0; n < kColumns.size(); ++n) {
      const std::string& text = c[static_cast<std::size_t>(column[n])];
      int col = 1;
      for (int k = 0; k < column[n]; ++k)
        col += static_cast<int>(c[static_cast<std::size_t>(k)].size()) + 1;
      double v = 0.0;
      std::size_t used = 0;
      try {
        v = std::stod(text, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used == 0 || used != text.size() || !std::isfinite(v))
        fail(col, std::string("'") + kColumns[n] + "' must be a number, got '" + text + "'");
      row.push_back(v);
    }
    rows.push_back(std::move(row));
  }
  if (cells == 0) throw DeckError({file, 1, 1}, "the jet file is empty (it needs a header row)");
  if (rows.empty()) throw DeckError({file, lineNo, 1}, "the jet file has no segments");
  return rows;
}

// The same rows, value for value (an integer 1 and a float 1.0 alike).
bool sameRows(const toml::node& given, const toml::array& rows) {
  const toml::array* a = given.as_array();
  if (!a || a->size() != rows.size()) return false;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const toml::array* x = (*a)[k].as_array();
    const toml::array* y = rows[k].as_array();
    if (!x || x->size() != y->size()) return false;
    for (std::size_t c = 0; c < y->size(); ++c)
      if ((*x)[c].value<double>() != (*y)[c].value<double>()) return false;
  }
  return true;
}

} // namespace

void inlineJetFiles(toml::table& root, const std::string& deckPath) {
  toml::array* jets = root["jet"].as_array();
  if (!jets) return;
  for (auto& node : *jets) {
    toml::table* t = node.as_table();
    if (!t) continue; // the reader reports it
    const auto* file = t->get_as<std::string>("file");
    if (!file) continue;
    const SourceLocation at = locate(file->source(), deckPath);
    std::filesystem::path p(file->get());
    if (p.is_relative()) p = std::filesystem::path(deckPath).parent_path() / p;
    toml::array rows = readJetFile(p.string(), at);
    // A resolved deck (an output's deck.toml) carries both: they must agree.
    if (const auto* given = t->get("segments")) {
      if (!sameRows(*given, rows))
        throw DeckError(locate(given->source(), deckPath),
                        "'segments' differs from what the jet file '" + p.string() +
                            "' holds now; give one of them");
      continue;
    }
    t->insert("segments", std::move(rows));
  }
}

// Every segment a body: in 3D a cylinder, in rz a box from the axis, in plane strain a box of
// width 2 radius about the jet's line, in 1D a segment of the line; its front face at `entry` at
// its insert time, moving at its speed along `axis`.
void readJet(const TableReader& r, std::size_t dimension, bool rz,
             const std::vector<MaterialConfig>& materials, std::vector<BodyConfig>& bodies,
             const std::string& name) {
  const keys::JetConfig jet = keys::readJet(r, dimension);
  BodyConfig proto;
  proto.where = r.where();
  proto.material = jet.material;
  proto.material_index = materialIndex(r, proto.material, materials);
  proto.spacing = jet.spacing;
  std::vector<double> axis = jet.axis;
  const std::vector<double>& entry = jet.entry;
  double n = 0.0;
  for (double a : axis) n += a * a;
  n = std::sqrt(n);
  if (!(n > 0.0)) r.fail("axis", r.quoted("axis") + " must not be zero");
  for (double& a : axis) a /= n;
  // Boxes cannot turn: off the lattice axes a segment would be a sheared box.
  int along = -1;
  for (std::size_t d = 0; d < dimension; ++d)
    if (std::abs(std::abs(axis[d]) - 1.0) < 1e-12) along = static_cast<int>(d);
  if (rz && (along != 1 || entry[0] != 0.0))
    r.fail("axis", "in an rz run a jet flies along the axis: " + r.quoted("axis") +
                       " [0, 1] or [0, -1] and 'entry' on it (r = 0)");
  if (!rz && dimension < 3 && along < 0)
    r.fail("axis", "in " + std::to_string(dimension) + "D a jet flies along x or y: " +
                       r.quoted("axis") + " must be a coordinate direction");

  const toml::array* segments = r.table().get_as<toml::array>("segments");
  if (!segments) r.missing("file");
  std::set<long long> seen;
  for (std::size_t k = 0; k < segments->size(); ++k) {
    const toml::array* row = (*segments)[k].as_array();
    if (!row || row->size() != 5)
      r.fail("segments",
             r.quoted("segments") + " rows are [segment, radius, length, velocity, insert_time]");
    double v[5];
    for (std::size_t c = 0; c < 5; ++c) {
      const auto x = (*row)[c].value<double>();
      if (!x || !std::isfinite(*x))
        r.fail("segments", r.quoted("segments") + " holds a value that is not a number");
      v[c] = *x;
    }
    const double id = v[0], radius = v[1], length = v[2], speed = v[3], t = v[4];
    const std::string row1 = "segment " + formatNumber(id) + ": ";
    if (id != std::floor(id) || !seen.insert(static_cast<long long>(id)).second)
      r.fail("segments", row1 + "segment numbers are distinct integers");
    if (!(radius > 0.0 && length > 0.0)) r.fail("segments", row1 + "radius and length must be > 0");
    if (!(t >= 0.0)) r.fail("segments", row1 + "insert_time must be >= 0");
    BodyConfig b = proto;
    b.name = name + "_segment" + formatNumber(id);
    for (const auto& other : bodies)
      if (other.name == b.name)
        r.fail("segments", row1 + "its body name '" + b.name + "' is taken by another body");
    b.insert_time = t;
    b.spacingWhere = r.whereValue("spacing");
    b.velocityWhere = r.whereValue("segments");
    b.velocity.assign(dimension, 0.0);
    std::vector<double> back(dimension);
    for (std::size_t d = 0; d < dimension; ++d) {
      b.velocity[d] = speed * axis[d];
      back[d] = entry[d] - length * axis[d];
    }
    if (dimension == 3) {
      b.shape.type = ShapeType::Cylinder;
      b.shape.base = back;
      b.shape.axis = axis;
      b.shape.radius = radius;
      b.shape.length = length;
    } else {
      b.shape.type = ShapeType::Box;
      b.shape.min.resize(dimension);
      b.shape.max.resize(dimension);
      for (std::size_t d = 0; d < dimension; ++d) {
        b.shape.min[d] = std::min(entry[d], back[d]);
        b.shape.max[d] = std::max(entry[d], back[d]);
        if (static_cast<int>(d) != along) {
          b.shape.min[d] = rz ? 0.0 : entry[d] - radius;
          b.shape.max[d] = entry[d] + radius;
        }
      }
    }
    b.shape.where = proto.where;
    bodies.push_back(std::move(b));
  }
}

} // namespace spall::io::deck_detail
