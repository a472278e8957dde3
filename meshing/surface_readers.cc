// Readers for triangle surfaces: OBJ, OFF, STL (ASCII and binary), PLY, VTU.
#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
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
  m.F.resize(static_cast<Eigen::Index>(s.triangles.size()), 3);
  size_t bad = 0;
  for (size_t t = 0; t < s.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const long idx = s.triangles[t][k];
      if (idx < 0 || idx >= static_cast<long>(s.points.size())) ++bad;
      m.F(static_cast<Eigen::Index>(t), k) = static_cast<int>(idx);
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
    c.fail("unsupported OFF variant '" + t[0] + "'");
  else
    c.fail("not an OFF file (missing 'OFF' header)");
  if (t.size() == first)
    t = c.next("vertex and face counts");
  else
    t.erase(t.begin());
  if (t.size() < 2) c.fail("expected vertex and face counts");
  const long nv = to_long(c, t[0]), nf = to_long(c, t[1]);
  if (nv < 0 || nf < 0) c.fail("negative counts");
  RawSurface s;
  for (long i = 0; i < nv; ++i) {
    auto p = c.next("vertex " + std::to_string(i) + " of " + std::to_string(nv));
    if (p.size() < 3) c.fail("vertex needs 3 coordinates");
    s.points.push_back({to_double(c, p[0]), to_double(c, p[1]), to_double(c, p[2])});
  }
  for (long f = 0; f < nf; ++f) {
    auto p = c.next("face " + std::to_string(f) + " of " + std::to_string(nf));
    const long n = to_long(c, p[0]);
    if (n < 3 || static_cast<long>(p.size()) < n + 1) c.fail("face has too few vertex indices");
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

int ply_type_size(const std::string& file, const std::string& t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32") return 4;
  if (t == "double" || t == "float64") return 8;
  throw MeshError(file, "unknown PLY property type '" + t + "'");
}

/// Reads binary PLY values with the file's byte order.
class PlyBinary {
 public:
  PlyBinary(std::string file, const std::string& data, size_t pos, bool big_endian)
      : file_(std::move(file)), data_(data), pos_(pos), big_(big_endian) {}
  double read(const std::string& t) {
    const int n = ply_type_size(file_, t);
    if (pos_ + n > data_.size()) throw MeshError(file_, "truncated binary PLY");
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

 private:
  std::string file_;
  const std::string& data_;
  size_t pos_;
  bool big_;
};

SurfaceMesh read_ply(const std::string& file, double scale) {
  const std::string data = read_file(file);
  const size_t header_end = data.find("end_header");
  if (data.compare(0, 3, "ply") != 0) throw MeshError(file, "not a PLY file (missing 'ply' magic)");
  if (header_end == std::string::npos) throw MeshError(file, "truncated PLY header (no end_header)");
  std::istringstream hs(data.substr(0, header_end));
  std::string line, format;
  std::vector<PlyElement> elements;
  while (std::getline(hs, line)) {
    auto t = detail::split_whitespace(line);
    if (t.empty()) continue;
    if (t[0] == "format" && t.size() > 1)
      format = t[1];
    else if (t[0] == "element" && t.size() == 3)
      elements.push_back({t[1], std::stol(t[2]), {}});
    else if (t[0] == "property" && !elements.empty()) {
      if (t.size() == 5 && t[1] == "list")
        elements.back().props.push_back({t[4], t[3], t[2]});
      else if (t.size() == 3)
        elements.back().props.push_back({t[2], t[1], ""});
      else
        throw MeshError(file, "malformed PLY property line '" + line + "'");
    }
  }
  if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian")
    throw MeshError(file, "unsupported PLY format '" + format + "'");
  size_t body = data.find('\n', header_end);
  body = body == std::string::npos ? data.size() : body + 1;

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
  if (format == "ascii") {
    LineCursor c(file, data.substr(body), 0);
    for (const auto& e : elements)
      for (long i = 0; i < e.count; ++i) {
        auto t = c.next(e.name + " " + std::to_string(i) + " of " + std::to_string(e.count));
        std::vector<double> scalars;
        std::vector<long> list;
        size_t pos = 0;
        for (const auto& p : e.props) {
          if (pos >= t.size()) c.fail("too few values for " + e.name);
          if (p.list_count_type.empty()) {
            scalars.push_back(to_double(c, t[pos++]));
          } else {
            const long n = to_long(c, t[pos++]);
            scalars.push_back(0);
            for (long k = 0; k < n; ++k) {
              if (pos >= t.size()) c.fail("list shorter than its count");
              list.push_back(to_long(c, t[pos++]));
            }
          }
        }
        store(e, scalars, list);
      }
  } else {
    PlyBinary b(file, data, body, format == "binary_big_endian");
    for (const auto& e : elements)
      for (long i = 0; i < e.count; ++i) {
        std::vector<double> scalars;
        std::vector<long> list;
        for (const auto& p : e.props) {
          if (p.list_count_type.empty()) {
            scalars.push_back(b.read(p.type));
          } else {
            const long n = static_cast<long>(b.read(p.list_count_type));
            scalars.push_back(0);
            for (long k = 0; k < n; ++k) list.push_back(static_cast<long>(b.read(p.type)));
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
