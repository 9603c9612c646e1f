#include "spall/io/Xdmf.hpp"

#include "spall/core/Error.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

namespace spall::io {
namespace {

std::string escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
    case '&':
      out += "&amp;";
      break;
    case '<':
      out += "&lt;";
      break;
    case '>':
      out += "&gt;";
      break;
    case '"':
      out += "&quot;";
      break;
    default:
      out += c;
    }
  }
  return out;
}

std::string numberType(ScalarType t) {
  switch (t) {
  case ScalarType::F64:
    return R"(NumberType="Float" Precision="8")";
  case ScalarType::U64:
    return R"(NumberType="UInt" Precision="8")";
  case ScalarType::I32:
    return R"(NumberType="Int" Precision="4")";
  case ScalarType::I64:
    return R"(NumberType="Int" Precision="8")";
  }
  return "";
}

std::string dimensions(std::size_t n, const std::vector<int>& shape) {
  std::string d = std::to_string(n);
  for (int s : shape) d.append(" ").append(std::to_string(s)); // not `" " + ...`: GCC 12 -Wrestrict
  return d;
}

// How ParaView's XDMF reader sees a field. A single-component field ([N], [N,1], [N,1,1]) is a
// Scalar whatever its nominal rank, so 1D vectors and tensors colour directly. Vectors are padded
// to 3 components by the reader; 3x3 tensors are Tensor. Anything else (2D tensors) is a Matrix
// with the components flattened to "N k": declared "N 2 2", the reader makes 2 components.
struct XdmfShape {
  std::string type;
  std::vector<int> dims; // per-particle dimensions as declared
};

XdmfShape xdmfShape(const std::vector<int>& shape) {
  int n = 1;
  for (int s : shape) n *= s;
  if (n == 1) return {"Scalar", shape};
  if (shape.size() == 1) return {"Vector", shape};
  if (shape == std::vector<int>{3, 3}) return {"Tensor", shape};
  return {"Matrix", {n}};
}

std::string hdfItem(const std::string& h5, const std::string& group, const FieldInfo& f,
                    const std::vector<int>& shape, std::size_t n, const std::string& indent) {
  return indent + "<DataItem Dimensions=\"" + dimensions(n, shape) + "\" " + numberType(f.scalar) +
         " Format=\"HDF\">" + escape(h5) + ":/" + escape(group) + "/" + escape(f.name) +
         "</DataItem>\n";
}

// Writes path.tmp, then renames it over path.
void writeAtomically(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) throw RunError("cannot write " + tmp + ": " + std::strerror(errno));
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    throw RunError("cannot rename " + tmp + " to " + path + ": " + std::strerror(errno));
}

// Shortest text that reads back as the same double.
std::string formatTime(double t) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, t);
  return std::string(buf, r.ptr);
}

// No DOCTYPE: nobody ships Xdmf.dtd beside the files, and libxml2 warns about every include.
const char* kHeader = "<?xml version=\"1.0\" ?>\n";

} // namespace

void writeSnapshotXdmf(const std::string& xmfPath, const std::string& h5FileName, double time,
                       int dimension, std::span<const XdmfPoints> sets) {
  const bool collection = sets.size() > 1;
  const std::string in = collection ? "   " : "  "; // a grid's indent
  std::ostringstream x;
  x << kHeader << "<Xdmf Version=\"2.0\">\n <Domain>\n";
  if (collection)
    x << "  <Grid Name=\"snapshot\" GridType=\"Collection\" CollectionType=\"Spatial\">\n"
      << "   <Time Value=\"" << formatTime(time) << "\"/>\n";
  for (const auto& set : sets) {
    const auto& fields = set.fields;
    const auto pos = std::find_if(fields.begin(), fields.end(),
                                  [](const FieldInfo& f) { return f.name == "position"; });
    if (pos == fields.end())
      throw RunError("cannot describe " + h5FileName + " in XDMF: its /" + set.group +
                     " has no position field");
    const std::size_t count = set.globalCount;
    const std::string n = std::to_string(count);
    const auto item = [&](const FieldInfo& f, const std::vector<int>& shape,
                          const std::string& indent) {
      return hdfItem(h5FileName, set.group, f, shape, count, indent);
    };
    x << in << "<Grid Name=\"" << escape(set.group) << "\" GridType=\"Uniform\">\n";
    if (!collection) x << in << " <Time Value=\"" << formatTime(time) << "\"/>\n";
    x << in << " <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << n
      << "\" NodesPerElement=\"1\"/>\n";
    if (dimension == 1) {
      // XDMF has no X-only geometry. X_Y_Z takes three N-vectors: x is the position dataset and
      // y = z = 0 * x, a Function of it, so no zeros are stored anywhere.
      x << in << " <Geometry GeometryType=\"X_Y_Z\">\n" << item(*pos, pos->shape, in + "  ");
      for (int k = 0; k < 2; ++k) {
        x << in << "  <DataItem ItemType=\"Function\" Function=\"0 * $0\" Dimensions=\"" << n
          << " 1\">\n"
          << item(*pos, pos->shape, in + "   ") << in << "  </DataItem>\n";
      }
    } else {
      x << in << " <Geometry GeometryType=\"" << (dimension == 2 ? "XY" : "XYZ") << "\">\n"
        << item(*pos, pos->shape, in + "  ");
    }
    x << in << " </Geometry>\n";
    for (const auto& f : fields) {
      if (f.name == "position") continue; // it is the geometry
      const XdmfShape xs = xdmfShape(f.shape);
      x << in << " <Attribute Name=\"" << escape(f.name) << "\" AttributeType=\"" << xs.type
        << "\" Center=\"Node\">\n"
        << item(f, xs.dims, in + "  ") << in << " </Attribute>\n";
    }
    x << in << "</Grid>\n";
  }
  if (collection) x << "  </Grid>\n";
  x << " </Domain>\n</Xdmf>\n";
  writeAtomically(xmfPath, x.str());
}

void writeSnapshotXdmf(const std::string& xmfPath, const std::string& h5FileName, double time,
                       std::size_t globalCount, int dimension, std::span<const FieldInfo> fields) {
  const XdmfPoints particles{"particles", globalCount, fields};
  writeSnapshotXdmf(xmfPath, h5FileName, time, dimension,
                    std::span<const XdmfPoints>(&particles, 1));
}

void writeSeriesXdmf(const std::string& seriesPath,
                     const std::vector<std::pair<double, std::string>>& snapshots) {
  auto sorted = snapshots;
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::ostringstream x;
  x << kHeader << "<Xdmf Version=\"2.0\" xmlns:xi=\"http://www.w3.org/2001/XInclude\">\n";
  x << " <Domain>\n  <Grid Name=\"series\" GridType=\"Collection\" "
       "CollectionType=\"Temporal\">\n";
  for (const auto& [t, file] : sorted)
    x << "   <xi:include href=\"" << escape(file)
      << "\" xpointer=\"xpointer(//Xdmf/Domain/Grid)\"/>\n";
  x << "  </Grid>\n </Domain>\n</Xdmf>\n";
  writeAtomically(seriesPath, x.str());
}

} // namespace spall::io
