// Readers for tetrahedral volumes: Gmsh .msh v1/v2/v4.1 ASCII, TetGen .node/.ele/.face,
// VTU. Each result passes orient_and_check_tets (mesh_checks.h) before it returns.
// Also the Gmsh 4.1 writer (write_gmsh41), beside the reader of its format.
#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <sstream>
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

/// The four numbers opening a Gmsh 4.1 $Nodes or $Elements section or one of its
/// blocks; fails naming `what` when there are fewer.
std::vector<std::string> four_numbers(LineCursor& c, const std::string& what, const std::string& fields) {
  auto h = c.next(what);
  if (h.size() < 4) c.fail(what + " needs 4 numbers (" + fields + "), found " + std::to_string(h.size()));
  return h;
}

/// The [min, max] tag range of a Gmsh 4.1 section header holding `count` items.
std::array<long, 2> tag_range(LineCursor& c, const std::vector<std::string>& h, long count, const std::string& what) {
  const long lo = to_long(c, h[2]), hi = to_long(c, h[3]);
  if (count > 0 && (lo < 0 || hi < lo))
    c.fail(what + " tags range from " + detail::shown(h[2]) + " to " + detail::shown(h[3]));
  return {lo, hi};
}

/// An entity block's dimension: 0 (point) to 3 (volume).
long entity_dimension(LineCursor& c, const std::string& token) {
  const long dim = to_long(c, token);
  if (dim < 0 || dim > 3) c.fail("entity dimension " + detail::shown(token) + " is not 0, 1, 2 or 3");
  return dim;
}

/// Gmsh 4.1 $Entities: its counts and every entity line are checked (points: tag,
/// x y z, physical tags; curves, surfaces, volumes: tag, bounding box, physical
/// tags, bounding entities), then the block is dropped: tets need none of it.
void skip_entities41(LineCursor& c) {
  const auto h = four_numbers(c, "$Entities header", "points, curves, surfaces, volumes");
  static const char* const kKinds[4] = {"point", "curve", "surface", "volume"};
  std::array<long, 4> n{};
  for (int d = 0; d < 4; ++d) n[d] = c.count(h[d], std::string(kKinds[d]) + " entities", 0, 10);
  for (int d = 0; d < 4; ++d)
    for (long i = 0; i < n[d]; ++i) {
      const std::string kind = kKinds[d];
      auto e = c.next(kind + " entity " + std::to_string(i + 1) + " of " + std::to_string(n[d]));
      // A list: its length at e[at], then that many integers; returns the index after it.
      auto list = [&](size_t at, const std::string& of) {
        if (e.size() <= at) c.fail(kind + " entity line ends before its number of " + of);
        const long k = to_long(c, e[at]);
        if (k < 0 || k > static_cast<long>(e.size() - at - 1))
          c.fail(kind + " entity says " + detail::shown(e[at]) + " " + of + " and has " +
                 std::to_string(e.size() - at - 1) + " fields left");
        for (size_t j = at + 1; j <= at + static_cast<size_t>(k); ++j) to_long(c, e[j]);
        return at + 1 + static_cast<size_t>(k);
      };
      const size_t reals = d == 0 ? 3 : 6;  // x y z, or a bounding box
      if (e.size() < 1 + reals) c.fail(kind + " entity line has " + std::to_string(e.size()) + " fields");
      to_long(c, e[0]);
      for (size_t j = 1; j <= reals; ++j) to_double(c, e[j]);
      size_t end = list(1 + reals, "physical tags");
      if (d > 0) end = list(end, "bounding entities");
      if (end != e.size())
        c.fail(kind + " entity line has " + std::to_string(e.size()) + " fields, its counts say " +
               std::to_string(end));
    }
  expect_section_end(c, "$EndEntities");
}

/// Gmsh 4.1 $Nodes: entity blocks of tags then coordinates (x y z, and u v w up
/// to the entity's dimension when parametric). Nodes are kept in file order.
void read_nodes41(LineCursor& c, IdMesh& m) {
  const auto h = four_numbers(c, "$Nodes header", "entity blocks, nodes, smallest and largest node tag");
  // A block takes a header line (>= 8 bytes); a node a tag and a coordinate line (>= 8).
  const long blocks = c.count(h[0], "node entity blocks", 0, 8);
  const long n = c.count(h[1], "nodes", sizeof(long) + sizeof(std::array<double, 3>), 8);
  const auto [lo, hi] = tag_range(c, h, n, "node");
  m.ids.reserve(m.ids.size() + static_cast<size_t>(n));
  m.points.reserve(m.points.size() + static_cast<size_t>(n));
  long left = n;
  std::vector<long> tags;
  for (long b = 0; b < blocks; ++b) {
    const std::string block = "node block " + std::to_string(b + 1) + " of " + std::to_string(blocks);
    const auto bh = four_numbers(c, block, "entity dimension and tag, parametric, nodes");
    const long dim = entity_dimension(c, bh[0]);
    to_long(c, bh[1]);
    const long parametric = to_long(c, bh[2]);
    if (parametric != 0 && parametric != 1) c.fail("parametric flag " + detail::shown(bh[2]) + " is not 0 or 1");
    const long k = c.count(bh[3], "nodes in a block", 0, 8);
    if (k > left)
      c.fail(block + " says " + bh[3] + " nodes, more than the " + std::to_string(left) + " the $Nodes header leaves");
    left -= k;
    tags.clear();
    for (long i = 0; i < k; ++i) {
      const auto t = c.next("node tag " + std::to_string(i + 1) + " of " + std::to_string(k) + " in " + block);
      if (t.size() != 1) c.fail("expected one node tag on the line, found " + std::to_string(t.size()) + " fields");
      const long tag = to_long(c, t[0]);
      if (tag < lo || tag > hi)
        c.fail("node tag " + t[0] + " is outside the range " + h[2] + " to " + h[3] + " of the $Nodes header");
      tags.push_back(tag);
    }
    const size_t fields = 3 + static_cast<size_t>(parametric * dim);
    for (long i = 0; i < k; ++i) {
      const auto p = c.next("coordinates of node " + std::to_string(tags[static_cast<size_t>(i)]));
      if (p.size() != fields)
        c.fail("node " + std::to_string(tags[static_cast<size_t>(i)]) + " needs " + std::to_string(fields) +
               " coordinates, found " + std::to_string(p.size()));
      for (size_t j = 3; j < fields; ++j) to_double(c, p[j]);  // parametric u v w, unused
      m.ids.push_back(tags[static_cast<size_t>(i)]);
      m.points.push_back(read_xyz(c, p, 0));
    }
  }
  if (left) c.fail("the node blocks hold " + std::to_string(n - left) + " nodes, the $Nodes header says " + h[1]);
  expect_section_end(c, "$EndNodes");
}

/// Gmsh 4.1 $Elements: entity blocks of one element type each, a line `tag nodes...`
/// per element. Tetrahedra (type 4) are kept; other types are skipped, as in v1/v2.
void read_elements41(LineCursor& c, IdMesh& m) {
  const auto h = four_numbers(c, "$Elements header", "entity blocks, elements, smallest and largest element tag");
  // Elements other than tetrahedra are skipped, so the counts bound no allocation.
  const long blocks = c.count(h[0], "element entity blocks", 0, 8);
  const long n = c.count(h[1], "elements", 0, 4);
  const auto [lo, hi] = tag_range(c, h, n, "element");
  long left = n;
  for (long b = 0; b < blocks; ++b) {
    const std::string block = "element block " + std::to_string(b + 1) + " of " + std::to_string(blocks);
    const auto bh = four_numbers(c, block, "entity dimension and tag, element type, elements");
    entity_dimension(c, bh[0]);
    to_long(c, bh[1]);
    const long type = to_long(c, bh[2]);
    const long k = c.count(bh[3], "elements in a block", 0, 4);
    if (k > left)
      c.fail(block + " says " + bh[3] + " elements, more than the " + std::to_string(left) +
             " the $Elements header leaves");
    left -= k;
    for (long i = 0; i < k; ++i) {
      const auto e = c.next("element " + std::to_string(i + 1) + " of " + std::to_string(k) + " in " + block);
      if (e.size() < 2) c.fail("element line needs a tag and its nodes");
      const long tag = to_long(c, e[0]);
      if (tag < lo || tag > hi)
        c.fail("element tag " + e[0] + " is outside the range " + h[2] + " to " + h[3] + " of the $Elements header");
      if (type != 4) continue;  // 4 = 4-node tetrahedron; points, lines, triangles ignored
      if (e.size() != 5) c.fail("tetrahedron needs a tag and 4 nodes, found " + std::to_string(e.size()) + " fields");
      m.tets.push_back({to_long(c, e[1]), to_long(c, e[2]), to_long(c, e[3]), to_long(c, e[4])});
    }
  }
  if (left)
    c.fail("the element blocks hold " + std::to_string(n - left) + " elements, the $Elements header says " + h[1]);
  expect_section_end(c, "$EndElements");
}

TetMesh read_msh(const std::string& file, double scale) {
  LineCursor c(file, read_file(file), 0);
  IdMesh m;
  bool v2 = false, v41 = false, have_nodes = false, have_elements = false;
  while (!c.at_end()) {
    auto t = c.next("a section");
    if (t[0] == "$MeshFormat") {
      auto f = c.next("mesh format");
      if (f.size() < 3) c.fail("malformed $MeshFormat");
      v41 = f[0] == "4.1";
      if (f[0][0] != '2' && !v41)
        c.fail("unsupported Gmsh version " + detail::shown(f[0]) + " (versions 1, 2 and 4.1 are read)");
      if (f[1] != "0")
        c.fail("binary Gmsh files are not supported (file type " + detail::shown(f[1]) + "; save as ASCII)");
      v2 = true;
      expect_section_end(c, "$EndMeshFormat");
    } else if (v41 && t[0] == "$Entities") {
      skip_entities41(c);
    } else if (v41 && t[0] == "$Nodes") {
      read_nodes41(c, m);
      have_nodes = true;
    } else if (v41 && t[0] == "$Elements") {
      read_elements41(c, m);
      have_elements = true;
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

void write_gmsh41(const std::string& path, const TetMesh& m) {
  const Eigen::Index n = m.V.rows(), t = m.T.rows();
  for (Eigen::Index e = 0; e < t; ++e)
    for (int k = 0; k < 4; ++k)
      if (m.T(e, k) < 0 || m.T(e, k) >= n)
        throw std::runtime_error(path + ": tetrahedron " + std::to_string(e) + " names node " +
                                 std::to_string(m.T(e, k)) + " of a mesh of " + std::to_string(n) + " nodes");
  std::ostringstream os;
  os << std::setprecision(17);
  os << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
  // One volume entity (tag 1): its bounding box, no physical tags, no bounding surfaces.
  Eigen::RowVector3d lo = Eigen::RowVector3d::Zero(), hi = Eigen::RowVector3d::Zero();
  if (n) {
    lo = m.V.colwise().minCoeff();
    hi = m.V.colwise().maxCoeff();
  }
  os << "$Entities\n0 0 0 1\n1 " << lo(0) << ' ' << lo(1) << ' ' << lo(2) << ' ' << hi(0) << ' ' << hi(1) << ' '
     << hi(2) << " 0 0\n$EndEntities\n";
  // Node tags 1..n in the mesh's order, element tags 1..t.
  os << "$Nodes\n" << (n ? 1 : 0) << ' ' << n << ' ' << (n ? 1 : 0) << ' ' << n << '\n';
  if (n) {
    os << "3 1 0 " << n << '\n';
    for (Eigen::Index i = 0; i < n; ++i) os << i + 1 << '\n';
    for (Eigen::Index i = 0; i < n; ++i) os << m.V(i, 0) << ' ' << m.V(i, 1) << ' ' << m.V(i, 2) << '\n';
  }
  os << "$EndNodes\n$Elements\n" << (t ? 1 : 0) << ' ' << t << ' ' << (t ? 1 : 0) << ' ' << t << '\n';
  if (t) {
    os << "3 1 4 " << t << '\n';
    for (Eigen::Index e = 0; e < t; ++e)
      os << e + 1 << ' ' << m.T(e, 0) + 1 << ' ' << m.T(e, 1) + 1 << ' ' << m.T(e, 2) + 1 << ' ' << m.T(e, 3) + 1
         << '\n';
  }
  os << "$EndElements\n";
  write_file_atomically(path, os.str());
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
