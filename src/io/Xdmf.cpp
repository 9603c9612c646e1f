#include "spall/io/Xdmf.hpp"

#include "spall/core/Error.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <climits>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
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

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw RunError("cannot read " + path + ": " + std::strerror(errno));
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A snapshot .xmf's text, read once while the file stays as it was: the series is rewritten at
// every snapshot, and reading every earlier one again would cost O(n^2) over a run.
const std::string& cachedText(const std::string& path) {
  struct Entry {
    std::filesystem::file_time_type written;
    std::uintmax_t size = 0;
    std::string text;
  };
  static std::map<std::string, Entry> cache;
  std::error_code ec;
  const auto written = std::filesystem::last_write_time(path, ec);
  const auto size = ec ? 0 : std::filesystem::file_size(path, ec);
  auto it = cache.find(path);
  if (ec || it == cache.end() || it->second.written != written || it->second.size != size) {
    std::string text = slurp(path); // throws for a missing file
    it = cache.insert_or_assign(path, Entry{written, size, std::move(text)}).first;
  }
  return it->second.text;
}

} // namespace

void writeSnapshotXdmf(const std::string& xmfPath, const std::string& h5FileName, int dimension,
                       const XdmfPoints& set) {
  const auto& fields = set.fields;
  const auto pos = std::find_if(fields.begin(), fields.end(),
                                [](const FieldInfo& f) { return f.name == "position"; });
  if (pos == fields.end())
    throw RunError("cannot describe " + h5FileName + " in XDMF: its /" + set.group +
                   " has no position field");
  const std::size_t count = set.globalCount;
  const std::string n = std::to_string(count);
  const bool wide = count > static_cast<std::size_t>(INT32_MAX);
  std::ostringstream x;
  x << kHeader << "<Xdmf Version=\"3.0\">\n <Domain>\n";
  x << "  <Grid Name=\"" << escape(set.group) << "\" GridType=\"Uniform\">\n";
  x << "   <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << n
    << "\" NodesPerElement=\"1\">\n"
    << "    <DataItem Dimensions=\"" << n << " 1\" NumberType=\"Int\" Precision=\""
    << (wide ? 8 : 4) << "\" Format=\"HDF\">" << escape(h5FileName) << ":/xdmf/"
    << escape(set.group) << "_vertices</DataItem>\n   </Topology>\n";
  if (dimension == 1) {
    x << "   <Geometry GeometryType=\"XYZ\">\n    <DataItem Dimensions=\"" << n
      << " 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << escape(h5FileName)
      << ":/xdmf/" << escape(set.group) << "_points</DataItem>\n";
  } else {
    x << "   <Geometry GeometryType=\"" << (dimension == 2 ? "XY" : "XYZ") << "\">\n"
      << hdfItem(h5FileName, set.group, *pos, pos->shape, count, "    ");
  }
  x << "   </Geometry>\n";
  for (const auto& f : fields) {
    const XdmfShape xs = xdmfShape(f.shape);
    x << "   <Attribute Name=\"" << escape(f.name) << "\" AttributeType=\"" << xs.type
      << "\" Center=\"Node\">\n"
      << hdfItem(h5FileName, set.group, f, xs.dims, count, "    ") << "   </Attribute>\n";
  }
  x << "  </Grid>\n </Domain>\n</Xdmf>\n";
  writeAtomically(xmfPath, x.str());
}

void writeSeriesXdmf(const std::string& seriesPath,
                     const std::vector<std::pair<double, std::string>>& snapshots) {
  auto sorted = snapshots;
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  const std::filesystem::path dir = std::filesystem::path(seriesPath).parent_path();
  std::ostringstream x;
  x << kHeader << "<Xdmf Version=\"3.0\">\n";
  x << " <Domain>\n  <Grid Name=\"series\" GridType=\"Collection\" "
       "CollectionType=\"Temporal\">\n";
  for (const auto& [t, file] : sorted) {
    // The snapshot's own grid (writeSnapshotXdmf's, its lines indented by 2), with its time.
    const std::string& text = cachedText((dir / file).string());
    const std::size_t open = text.find("  <Grid ");
    const std::size_t close = text.rfind("  </Grid>");
    const std::size_t eol = open == std::string::npos ? open : text.find('\n', open);
    if (open == std::string::npos || close == std::string::npos || eol == std::string::npos ||
        close < eol)
      throw RunError("cannot list " + file + " in " + seriesPath + ": it holds no spall grid");
    std::istringstream lines(text.substr(eol + 1, close - eol - 1));
    x << "   " << text.substr(open + 2, eol - open - 2) << "\n";
    x << "     <Time Value=\"" << formatTime(t) << "\"/>\n";
    for (std::string line; std::getline(lines, line);) x << "  " << line << "\n";
    x << "   </Grid>\n";
  }
  x << "  </Grid>\n </Domain>\n</Xdmf>\n";
  writeAtomically(seriesPath, x.str());
}

} // namespace spall::io
