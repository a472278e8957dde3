// Readers for triangle surfaces: OBJ, OFF, STL (ASCII and binary), PLY, VTU.
#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>

#include "atomic_file.h"
#include "mesh_io.h"
#include "text_parsing.h"

namespace tb {
namespace {

using detail::LineCursor;
using detail::to_double;
using detail::to_long;

struct RawSurface {
  std::vector<std::array<double, 3>> points;
  std::vector<std::array<long, 3>> triangles;
};

void add_polygon(RawSurface& s, const std::vector<long>& poly) {
  for (size_t k = 1; k + 1 < poly.size(); ++k) s.triangles.push_back({poly[0], poly[k], poly[k + 1]});
}

SurfaceMesh finish(const std::string& file, const RawSurface& s, double scale) {
  if (s.points.empty()) throw MeshError(file, "no vertices");
  if (s.triangles.empty()) throw MeshError(file, "no triangles");
  SurfaceMesh m;
  m.V.resize(static_cast<Eigen::Index>(s.points.size()), 3);
  for (size_t i = 0; i < s.points.size(); ++i)
    for (int d = 0; d < 3; ++d) {
      if (!std::isfinite(s.points[i][d]))
        throw MeshError(file, "vertex " + std::to_string(i) + " has a NaN or Inf coordinate");
      m.V(static_cast<Eigen::Index>(i), d) = s.points[i][d] * scale;
    }
  // Vertex indices are ints (mesh_types.h).
  if (s.points.size() > static_cast<size_t>(std::numeric_limits<int>::max()))
    throw MeshError(file, std::to_string(s.points.size()) + " vertices, more than a mesh can index");
  m.F.resize(static_cast<Eigen::Index>(s.triangles.size()), 3);
  size_t bad = 0;
  for (size_t t = 0; t < s.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const long idx = s.triangles[t][k];
      const bool in_range = idx >= 0 && idx < static_cast<long>(s.points.size());
      if (!in_range) ++bad;
      m.F(static_cast<Eigen::Index>(t), k) = in_range ? static_cast<int>(idx) : 0;
    }
  if (bad)
    throw MeshError(file, std::to_string(bad) + " triangle vertex indices out of range [0, " +
                              std::to_string(s.points.size()) + ")");
  return m;
}

SurfaceMesh read_obj(const std::string& file, double scale) {
  LineCursor c(file, read_file(file), '#');
  RawSurface s;
  while (!c.at_end()) {
    auto t = c.next("a line");
    if (t[0] == "v") {
      if (t.size() < 4) c.fail("vertex needs 3 coordinates");
      s.points.push_back({to_double(c, t[1]), to_double(c, t[2]), to_double(c, t[3])});
    } else if (t[0] == "f") {
      if (t.size() < 4) c.fail("face needs at least 3 vertices");
      std::vector<long> poly;
      for (size_t k = 1; k < t.size(); ++k) {
        const std::string idx = t[k].substr(0, t[k].find('/'));  // "v/vt/vn" -> "v"
        long v = to_long(c, idx);
        if (v == 0) c.fail("OBJ indices start at 1, found 0");
        // Negative indices count back from the last vertex read so far.
        poly.push_back(v > 0 ? v - 1 : static_cast<long>(s.points.size()) + v);
      }
      add_polygon(s, poly);
    }  // vt, vn, g, o, s, usemtl, mtllib, l: not geometry we need
  }
  return finish(file, s, scale);
}

SurfaceMesh read_off(const std::string& file, double scale) {
  LineCursor c(file, read_file(file), '#');
  auto t = c.next("OFF header");
  size_t first = 0;
  if (t[0] == "OFF")
    first = 1;
  else if (t[0].size() > 3 && t[0].compare(0, 3, "OFF") == 0 && t[0] != "OFF")
    c.fail("unsupported OFF variant '" + detail::shown(t[0]) + "'");
  else
    c.fail("not an OFF file (missing 'OFF' header)");
  if (t.size() == first)
    t = c.next("vertex and face counts");
  else
    t.erase(t.begin());
  if (t.size() < 2) c.fail("expected vertex and face counts");
  const long nv = c.count(t[0], "vertices", sizeof(std::array<double, 3>));
  const long nf = c.count(t[1], "faces", sizeof(std::array<long, 3>));
  RawSurface s;
  s.points.reserve(static_cast<size_t>(nv));
  for (long i = 0; i < nv; ++i) {
    auto p = c.next("vertex " + std::to_string(i) + " of " + std::to_string(nv));
    if (p.size() < 3) c.fail("vertex needs 3 coordinates");
    s.points.push_back({to_double(c, p[0]), to_double(c, p[1]), to_double(c, p[2])});
  }
  for (long f = 0; f < nf; ++f) {
    auto p = c.next("face " + std::to_string(f) + " of " + std::to_string(nf));
    const long n = to_long(c, p[0]);
    if (n < 3 || n > static_cast<long>(p.size()) - 1)
      c.fail("face says " + p[0] + " vertices and lists " + std::to_string(p.size() - 1) + " (at least 3 needed)");
    std::vector<long> poly;
    for (long k = 1; k <= n; ++k) poly.push_back(to_long(c, p[static_cast<size_t>(k)]));
    add_polygon(s, poly);
  }
  return finish(file, s, scale);
}

/// Merges exactly coincident STL corners into shared vertices (deterministic:
/// first occurrence wins).
struct VertexMerger {
  RawSurface s;
  std::map<std::array<double, 3>, long> index;
  long add(const std::array<double, 3>& p) {
    auto [it, inserted] = index.emplace(p, static_cast<long>(s.points.size()));
    if (inserted) s.points.push_back(p);
    return it->second;
  }
};

SurfaceMesh read_stl(const std::string& file, double scale) {
  const std::string data = read_file(file);
  // Binary STL: 80-byte header, uint32 count, 50 bytes per triangle. Some binary
  // files start their header with "solid", so decide by the size, not the text.
  bool binary = false;
  uint32_t count = 0;
  if (data.size() >= 84) {
    std::memcpy(&count, data.data() + 80, 4);
    binary = data.size() == 84 + 50ull * count;
  }
  const bool looks_ascii = data.compare(0, 5, "solid") == 0;
  VertexMerger m;
  if (binary || !looks_ascii) {
    if (data.size() < 84) throw MeshError(file, "truncated binary STL (shorter than its 84-byte header)");
    if (data.size() < 84 + 50ull * count)
      throw MeshError(file, "truncated binary STL: header says " + std::to_string(count) + " triangles, file holds " +
                                std::to_string((data.size() - 84) / 50));
    for (uint32_t t = 0; t < count; ++t) {
      const char* rec = data.data() + 84 + 50ull * t + 12;  // skip the normal
      std::array<long, 3> tri{};
      for (int k = 0; k < 3; ++k) {
        float xyz[3];
        std::memcpy(xyz, rec + 12 * k, 12);
        for (float f : xyz)
          if (!std::isfinite(f))
            throw MeshError(file, "triangle " + std::to_string(t) + " has a NaN or Inf coordinate");
        tri[k] = m.add({xyz[0], xyz[1], xyz[2]});
      }
      m.s.triangles.push_back(tri);
    }
    return finish(file, m.s, scale);
  }
  LineCursor c(file, data, 0);
  c.next("solid");
  std::vector<long> corners;
  bool ended = false;
  while (!c.at_end()) {
    auto t = c.next("a line");
    if (t[0] == "vertex") {
      if (t.size() < 4) c.fail("vertex needs 3 coordinates");
      corners.push_back(m.add({to_double(c, t[1]), to_double(c, t[2]), to_double(c, t[3])}));
    } else if (t[0] == "endloop") {
      if (corners.size() != 3) c.fail("facet with " + std::to_string(corners.size()) + " vertices (expected 3)");
      m.s.triangles.push_back({corners[0], corners[1], corners[2]});
      corners.clear();
    } else if (t[0] == "endsolid") {
      ended = true;
      break;
    }
  }
  if (!ended) throw MeshError(file, "truncated ASCII STL (no 'endsolid')");
  return finish(file, m.s, scale);
}

// ---- PLY ---------------------------------------------------------------------

struct PlyProperty {
  std::string name, type, list_count_type;  // list_count_type empty unless a list
};
struct PlyElement {
  std::string name;
  long count = 0;
  std::vector<PlyProperty> props;
};

/// The size of a PLY scalar type in bytes; 0 for an unknown type.
int ply_type_size(const std::string& t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32") return 4;
  if (t == "double" || t == "float64") return 8;
  return 0;
}

bool ply_integer_type(const std::string& t) {
  return t != "float" && t != "float32" && t != "double" && t != "float64";
}

/// A value read from a PLY file used as a count or an index: a whole number in
/// [0, max] (a float type may hold anything, and a cast of it beyond long is undefined).
long ply_whole(const std::string& file, double v, double max, const std::string& what) {
  if (!(v >= 0 && v <= max) || v != std::floor(v))
    throw MeshError(file, what + " " + detail::shown(std::to_string(v)) + " is not a whole number in [0, " +
                              std::to_string(static_cast<long>(max)) + "]");
  return static_cast<long>(v);
}

/// Reads binary PLY values with the file's byte order.
class PlyBinary {
 public:
  PlyBinary(std::string file, const std::string& data, size_t pos, bool big_endian)
      : file_(std::move(file)), data_(data), pos_(pos), big_(big_endian) {}
  double read(const std::string& t) {
    const size_t n = static_cast<size_t>(ply_type_size(t));  // the header check made it 1, 2, 4 or 8
    if (n > data_.size() - pos_) throw MeshError(file_, "truncated binary PLY (at byte " + std::to_string(pos_) + ")");
    unsigned char b[8];
    std::memcpy(b, data_.data() + pos_, n);
    pos_ += n;
    if (big_) std::reverse(b, b + n);
    auto get = [&](auto v) {
      std::memcpy(&v, b, sizeof v);
      return static_cast<double>(v);
    };
    if (t == "char" || t == "int8") return get(int8_t{});
    if (t == "uchar" || t == "uint8") return get(uint8_t{});
    if (t == "short" || t == "int16") return get(int16_t{});
    if (t == "ushort" || t == "uint16") return get(uint16_t{});
    if (t == "int" || t == "int32") return get(int32_t{});
    if (t == "uint" || t == "uint32") return get(uint32_t{});
    if (t == "float" || t == "float32") return get(float{});
    return get(double{});
  }
  size_t left() const { return data_.size() - pos_; }

 private:
  std::string file_;
  const std::string& data_;
  size_t pos_;
  bool big_;
};

SurfaceMesh read_ply(const std::string& file, double scale) {
  const std::string data = read_file(file);
  if (data.compare(0, 3, "ply") != 0) throw MeshError(file, "not a PLY file (missing 'ply' magic)");
  const size_t header_end = data.find("end_header");
  if (header_end == std::string::npos) throw MeshError(file, "truncated PLY header (no end_header)");
  std::istringstream hs(data.substr(0, header_end));
  std::string line, format;
  std::vector<PlyElement> elements;
  int line_no = 0;
  auto header_fail = [&](const std::string& problem) {
    throw MeshError(file, "header line " + std::to_string(line_no) + ": " + problem);
  };
  auto check_type = [&](const std::string& t) {
    if (!ply_type_size(t)) header_fail("unknown PLY property type '" + detail::shown(t) + "'");
  };
  while (std::getline(hs, line)) {
    ++line_no;
    auto t = detail::split_whitespace(line);
    if (t.empty() || t[0] == "comment" || t[0] == "obj_info" || (line_no == 1 && t[0] == "ply")) continue;
    if (t[0] == "format") {
      if (t.size() < 2) header_fail("format line without a format");
      format = t[1];
    } else if (t[0] == "element") {
      if (t.size() != 3) header_fail("expected 'element <name> <count>', found '" + detail::shown(line) + "'");
      char* end = nullptr;
      errno = 0;
      const long n = std::strtol(t[2].c_str(), &end, 10);
      if (end != t[2].c_str() + t[2].size() || errno == ERANGE || n < 0)
        header_fail("element count '" + detail::shown(t[2]) + "' is not a whole number >= 0");
      elements.push_back({t[1], n, {}});
    } else if (t[0] == "property") {
      if (elements.empty()) header_fail("property before any element");
      if (t.size() == 5 && t[1] == "list") {
        check_type(t[2]);
        check_type(t[3]);
        if (!ply_integer_type(t[2])) header_fail("a list count of type '" + t[2] + "' (an integer type is needed)");
        elements.back().props.push_back({t[4], t[3], t[2]});
      } else if (t.size() == 3) {
        check_type(t[1]);
        elements.back().props.push_back({t[2], t[1], ""});
      } else {
        header_fail("malformed property line '" + detail::shown(line) + "'");
      }
    }
  }
  if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian")
    throw MeshError(file, "unsupported PLY format '" + detail::shown(format) + "'");
  size_t body = data.find('\n', header_end);
  body = body == std::string::npos ? data.size() : body + 1;
  const bool binary = format != "ascii";
  for (const PlyElement& e : elements) {
    // Each item takes at least one line (ascii) or its scalars' and list counts'
    // bytes (binary), so a count the rest of the file cannot hold is a damaged
    // header; an element without properties holds nothing to read.
    if (e.props.empty()) {
      if (e.count > 0) throw MeshError(file, "element '" + detail::shown(e.name) + "' has no properties");
      continue;
    }
    size_t item_bytes = 0;
    for (const PlyProperty& p : e.props)
      item_bytes += static_cast<size_t>(ply_type_size(p.list_count_type.empty() ? p.type : p.list_count_type));
    const size_t room = (data.size() - body) / (binary ? item_bytes : 2);
    if (static_cast<size_t>(e.count) > room)
      throw MeshError(file, "truncated PLY: the header says " + std::to_string(e.count) + " " + detail::shown(e.name) +
                                " elements, more than the rest of the file can hold (at most " + std::to_string(room) +
                                ")");
    detail::check_allocation(file, static_cast<size_t>(e.count), 24, e.name + " elements");
  }

  RawSurface s;
  auto store = [&](const PlyElement& e, const std::vector<double>& scalars, const std::vector<long>& list) {
    if (e.name == "vertex") {
      std::array<double, 3> p{};
      int found = 0;
      for (size_t k = 0; k < e.props.size(); ++k) {
        const auto& n = e.props[k].name;
        if (n == "x") p[0] = scalars[k], found |= 1;
        if (n == "y") p[1] = scalars[k], found |= 2;
        if (n == "z") p[2] = scalars[k], found |= 4;
      }
      if (found != 7) throw MeshError(file, "PLY vertex element lacks x, y or z");
      s.points.push_back(p);
    } else if (e.name == "face") {
      if (list.size() < 3) throw MeshError(file, "PLY face with fewer than 3 vertices");
      add_polygon(s, list);
    }
  };
  std::vector<double> scalars;
  std::vector<long> list;
  if (!binary) {
    LineCursor c(file, data.substr(body), 0);
    for (const auto& e : elements)
      for (long i = 0; i < e.count; ++i) {
        auto t = c.next(e.name + " " + std::to_string(i) + " of " + std::to_string(e.count));
        scalars.clear();
        list.clear();
        size_t pos = 0;
        for (const auto& p : e.props) {
          if (pos >= t.size()) c.fail("too few values for " + detail::shown(e.name));
          if (p.list_count_type.empty()) {
            scalars.push_back(to_double(c, t[pos++]));
          } else {
            const long n = to_long(c, t[pos++]);
            if (n < 0 || n > static_cast<long>(t.size() - pos)) c.fail("list shorter than its count");
            scalars.push_back(0);
            for (long k = 0; k < n; ++k) list.push_back(to_long(c, t[pos++]));
          }
        }
        store(e, scalars, list);
      }
  } else {
    PlyBinary b(file, data, body, format == "binary_big_endian");
    for (const auto& e : elements)
      for (long i = 0; i < e.count; ++i) {
        scalars.clear();
        list.clear();
        for (const auto& p : e.props) {
          if (p.list_count_type.empty()) {
            scalars.push_back(b.read(p.type));
          } else {
            const size_t item = static_cast<size_t>(ply_type_size(p.type));
            const long n =
                ply_whole(file, b.read(p.list_count_type), 9.0e15, "a list count of element " + detail::shown(e.name));
            if (static_cast<size_t>(n) > b.left() / item)
              throw MeshError(file, "truncated binary PLY (a list of " + std::to_string(n) + " entries with room for " +
                                        std::to_string(b.left() / item) + ")");
            scalars.push_back(0);
            for (long k = 0; k < n; ++k)
              list.push_back(
                  ply_whole(file, b.read(p.type), 9.0e15, "a list entry of element " + detail::shown(e.name)));
          }
        }
        store(e, scalars, list);
      }
  }
  return finish(file, s, scale);
}

}  // namespace

SurfaceMesh read_surface(const std::string& path, double unit_scale) {
  if (!(unit_scale > 0) || !std::isfinite(unit_scale)) throw MeshError(path, "unit scale must be a positive number");
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  if (ext == ".obj") return read_obj(path, unit_scale);
  if (ext == ".off") return read_off(path, unit_scale);
  if (ext == ".stl") return read_stl(path, unit_scale);
  if (ext == ".ply") return read_ply(path, unit_scale);
  if (ext == ".vtu") {
    detail::VtuCells cells = detail::read_vtu_cells(path, /*VTK_TRIANGLE*/ 5, 3);
    SurfaceMesh m{cells.V * unit_scale, cells.cells};
    if (m.F.rows() == 0) throw MeshError(path, "no triangles");
    return m;
  }
  throw MeshError(path, "unknown surface format '" + ext + "' (expected .obj, .off, .stl, .ply or .vtu)");
}

}  // namespace tb
