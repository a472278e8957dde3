// Readers for tetrahedral volumes: Gmsh .msh v1/v2 ASCII, TetGen .node/.ele/.face,
// VTU. Each result passes orient_and_check_tets (mesh_checks.h) before it returns.
#include <algorithm>
#include <filesystem>
#include <limits>
#include <unordered_map>

#include "atomic_file.h"
#include "mesh_checks.h"
#include "mesh_io.h"
#include "text_parsing.h"

namespace tb {
namespace {

using detail::LineCursor;
using detail::to_double;
using detail::to_long;

/// Nodes keyed by their file ids (any integers), tets as lists of those ids.
struct IdMesh {
  std::vector<long> ids;
  std::vector<std::array<double, 3>> points;
  std::vector<std::array<long, 4>> tets;
};

TetMesh resolve_ids(const std::string& file, const IdMesh& m, double scale, FlatTets flat) {
  if (m.points.empty()) throw MeshError(file, "no nodes");
  if (m.tets.empty()) throw MeshError(file, "no tetrahedra");
  // Node indices are ints (mesh_types.h).
  if (m.points.size() > static_cast<size_t>(std::numeric_limits<int>::max()))
    throw MeshError(file, std::to_string(m.points.size()) + " nodes, more than a mesh can index");
  std::unordered_map<long, int> index;
  for (size_t i = 0; i < m.ids.size(); ++i)
    if (!index.emplace(m.ids[i], static_cast<int>(i)).second)
      throw MeshError(file, "node id " + std::to_string(m.ids[i]) + " defined twice");
  TetMesh out;
  out.V.resize(static_cast<Eigen::Index>(m.points.size()), 3);
  for (size_t i = 0; i < m.points.size(); ++i)
    for (int d = 0; d < 3; ++d) out.V(static_cast<Eigen::Index>(i), d) = m.points[i][d] * scale;
  out.T.resize(static_cast<Eigen::Index>(m.tets.size()), 4);
  size_t missing = 0;
  long example = 0;
  for (size_t t = 0; t < m.tets.size(); ++t)
    for (int k = 0; k < 4; ++k) {
      auto it = index.find(m.tets[t][k]);
      if (it == index.end()) {
        if (!missing++) example = m.tets[t][k];
        out.T(static_cast<Eigen::Index>(t), k) = 0;
      } else {
        out.T(static_cast<Eigen::Index>(t), k) = it->second;
      }
    }
  if (missing)
    throw MeshError(file, std::to_string(missing) + " tetrahedron node references out of range (e.g. node " +
                              std::to_string(example) + " is not defined)");
  orient_and_check_tets(file, out, flat);
  return out;
}

std::array<double, 3> read_xyz(LineCursor& c, const std::vector<std::string>& t, size_t first) {
  if (t.size() < first + 3) c.fail("node needs 3 coordinates");
  return {to_double(c, t[first]), to_double(c, t[first + 1]), to_double(c, t[first + 2])};
}

void expect_section_end(LineCursor& c, const std::string& end) {
  auto t = c.next(end);
  if (t[0] != end) c.fail("expected " + end + ", found '" + detail::shown(t[0]) + "'");
}

TetMesh read_msh(const std::string& file, double scale) {
  LineCursor c(file, read_file(file), 0);
  IdMesh m;
  bool v2 = false, have_nodes = false, have_elements = false;
  while (!c.at_end()) {
    auto t = c.next("a section");
    if (t[0] == "$MeshFormat") {
      auto f = c.next("mesh format");
      if (f.size() < 3) c.fail("malformed $MeshFormat");
      if (f[0][0] != '2') c.fail("unsupported Gmsh version " + detail::shown(f[0]) + " (versions 1 and 2 are read)");
      if (f[1] != "0") c.fail("binary Gmsh files are not supported");
      v2 = true;
      expect_section_end(c, "$EndMeshFormat");
    } else if (t[0] == "$NOD" || t[0] == "$Nodes") {
      const long n = c.count(c.next("node count")[0], "nodes", sizeof(long) + sizeof(std::array<double, 3>));
      m.ids.reserve(m.ids.size() + static_cast<size_t>(n));
      m.points.reserve(m.points.size() + static_cast<size_t>(n));
      for (long i = 0; i < n; ++i) {
        auto p = c.next("node " + std::to_string(i + 1) + " of " + std::to_string(n));
        m.ids.push_back(to_long(c, p[0]));
        m.points.push_back(read_xyz(c, p, 1));
      }
      expect_section_end(c, v2 ? "$EndNodes" : "$ENDNOD");
      have_nodes = true;
    } else if (t[0] == "$ELM" || t[0] == "$Elements") {
      // Elements other than tetrahedra are skipped, so the count bounds no allocation.
      const long n = c.count(c.next("element count")[0], "elements", 0);
      for (long i = 0; i < n; ++i) {
        auto e = c.next("element " + std::to_string(i + 1) + " of " + std::to_string(n));
        if (e.size() < 3) c.fail("malformed element line");
        const long type = to_long(c, e[1]);
        if (type != 4) continue;  // 4 = 4-node tetrahedron; points, lines, triangles ignored
        // v1: id type phys elem nnodes nodes... ; v2: id type ntags tags... nodes...
        const long tags = v2 ? to_long(c, e[2]) : 0;
        if (tags < 0 || tags > static_cast<long>(e.size()))
          c.fail("element says " + detail::shown(e[2]) + " tags and has " + std::to_string(e.size()) + " fields");
        const size_t first = v2 ? 3 + static_cast<size_t>(tags) : 5;
        if (e.size() < first + 4) c.fail("tetrahedron with fewer than 4 nodes");
        m.tets.push_back(
            {to_long(c, e[first]), to_long(c, e[first + 1]), to_long(c, e[first + 2]), to_long(c, e[first + 3])});
      }
      expect_section_end(c, v2 ? "$EndElements" : "$ENDELM");
      have_elements = true;
    } else if (t[0][0] == '$' && t[0].compare(0, 4, "$End") != 0) {
      // Unknown section ($PhysicalNames, $NodeData ...): skip to its end marker.
      const std::string end = "$End" + t[0].substr(1);
      while (c.next(end)[0] != end) {
      }
    }
  }
  if (!have_nodes) throw MeshError(file, "no $Nodes/$NOD section");
  if (!have_elements) throw MeshError(file, "no $Elements/$ELM section");
  return resolve_ids(file, m, scale, FlatTets::Error);
}

std::string with_extension(const std::string& path, const std::string& ext) {
  return std::filesystem::path(path).replace_extension(ext).string();
}

/// Reads a TetGen .node file; returns the first node id (0 or 1).
long read_tetgen_nodes(const std::string& node_file, IdMesh& m) {
  LineCursor c(node_file, read_file(node_file), '#');
  auto h = c.next("node header");
  const long n = c.count(h[0], "nodes", sizeof(long) + sizeof(std::array<double, 3>));
  if (h.size() > 1 && to_long(c, h[1]) != 3) c.fail("only 3-D .node files are read");
  m.ids.reserve(static_cast<size_t>(n));
  m.points.reserve(static_cast<size_t>(n));
  long first = 0;
  for (long i = 0; i < n; ++i) {
    auto p = c.next("node " + std::to_string(i) + " of " + std::to_string(n));
    m.ids.push_back(to_long(c, p[0]));
    if (i == 0) first = m.ids.back();
    m.points.push_back(read_xyz(c, p, 1));
  }
  return first;
}

TetMesh read_tetgen(const std::string& path, double scale, FlatTets flat) {
  IdMesh m;
  read_tetgen_nodes(with_extension(path, ".node"), m);
  const std::string ele = with_extension(path, ".ele");
  LineCursor c(ele, read_file(ele), '#');
  auto h = c.next("element header");
  const long n = c.count(h[0], "tetrahedra", sizeof(std::array<long, 4>));
  if (h.size() > 1 && to_long(c, h[1]) != 4) c.fail("only 4-node tetrahedra are read");
  m.tets.reserve(static_cast<size_t>(n));
  for (long i = 0; i < n; ++i) {
    auto e = c.next("element " + std::to_string(i) + " of " + std::to_string(n));
    if (e.size() < 5) c.fail("tetrahedron with fewer than 4 nodes");
    m.tets.push_back({to_long(c, e[1]), to_long(c, e[2]), to_long(c, e[3]), to_long(c, e[4])});
  }
  return resolve_ids(ele, m, scale, flat);
}

}  // namespace

Triangles read_tetgen_faces(const std::string& face_path, int first_index) {
  LineCursor c(face_path, read_file(face_path), '#');
  // The count sizes the result before any face is read: bounded by the file first.
  const long n = c.count(c.next("face header")[0], "faces", 3 * sizeof(int));
  Triangles F(n, 3);
  for (long i = 0; i < n; ++i) {
    auto f = c.next("face " + std::to_string(i) + " of " + std::to_string(n));
    if (f.size() < 4) c.fail("face with fewer than 3 nodes");
    for (int k = 0; k < 3; ++k) {
      const long node = to_long(c, f[static_cast<size_t>(k) + 1]);
      if (node < first_index || node > first_index + static_cast<long>(std::numeric_limits<int>::max()))
        c.fail("node " + detail::shown(f[static_cast<size_t>(k) + 1]) + " is below the first index " +
               std::to_string(first_index) + " or beyond what a mesh can index");
      F(i, k) = static_cast<int>(node - first_index);
    }
  }
  return F;
}

TetMesh read_volume(const std::string& path, double unit_scale, FlatTets flat) {
  if (!(unit_scale > 0) || !std::isfinite(unit_scale)) throw MeshError(path, "unit scale must be a positive number");
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  if (ext == ".msh") return read_msh(path, unit_scale);
  if (ext == ".ele" || ext == ".node") return read_tetgen(path, unit_scale, flat);
  if (ext == ".vtu") {
    detail::VtuCells cells = detail::read_vtu_cells(path, /*VTK_TETRA*/ 10, 4);
    if (cells.cells.rows() == 0) throw MeshError(path, "no tetrahedra");
    TetMesh m{cells.V * unit_scale, cells.cells};
    orient_and_check_tets(path, m, flat);
    return m;
  }
  throw MeshError(path, "unknown volume format '" + ext + "' (expected .msh, .ele/.node or .vtu)");
}

}  // namespace tb
