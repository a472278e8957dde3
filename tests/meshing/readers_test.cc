// One test per reader and per malformed input: each error names the file
// and the problem.
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "atomic_file.h"
#include "cube_generator.h"
#include "mesh_checks.h"
#include "mesh_error.h"
#include "mesh_io.h"
#include "mesh_recipe.h"
#include "test_support.h"

namespace tb {
namespace {
namespace fs = std::filesystem;

class Readers : public ::testing::Test {
 protected:
  const tb::testing::TempFolder tmp{"readers"};
  const fs::path dir = tmp.path;
  std::string write(const std::string& name, const std::string& content) {
    const std::string p = (dir / name).string();
    std::ofstream(p, std::ios::binary) << content;
    return p;
  }
};

// A tetrahedron surface, outward-oriented.
const char* kTetObj =
    "# tet\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvn 0 0 1\ng default\nusemtl m\n"
    "f 1/1/1 3/1/1 2/1/1\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

/// Expects `fn` to throw MeshError whose message contains the file and `problem`.
template <class F>
void expect_error(F fn, const std::string& file, const std::string& problem) {
  try {
    fn();
    FAIL() << "no error for " << file;
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(problem), std::string::npos) << e.what();
  }
}

TEST_F(Readers, ObjWithPolygonsAndAttributes) {
  const auto p = write(
      "quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1\nf 1 4 3 2\nf 1 2 5\nf 2 3 5\nf 3 4 5\nf 4 1 5\n");
  SurfaceMesh m = read_surface(p);
  EXPECT_EQ(m.V.rows(), 5);
  EXPECT_EQ(m.F.rows(), 6);  // the quad fan-triangulated
  check_and_orient_surface(p, m);
  EXPECT_NEAR(enclosed_volume(m), 1.0 / 3.0, 1e-12);
  SurfaceMesh t = read_surface(write("tet.obj", kTetObj), 0.01);
  EXPECT_EQ(t.F.rows(), 4);
  EXPECT_DOUBLE_EQ(t.V(1, 0), 0.01);
}

TEST_F(Readers, Off) {
  const auto p =
      write("tet.off", "OFF\n# comment\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  SurfaceMesh m = read_surface(p);
  EXPECT_EQ(m.V.rows(), 4);
  EXPECT_EQ(m.F.rows(), 4);
}

TEST_F(Readers, StlAsciiMergesVertices) {
  std::string s = "solid t\n";
  const char* tris[4][3] = {{"0 0 0", "0 1 0", "1 0 0"},
                            {"0 0 0", "1 0 0", "0 0 1"},
                            {"0 0 0", "0 0 1", "0 1 0"},
                            {"1 0 0", "0 1 0", "0 0 1"}};
  for (auto& t : tris) {
    s += "facet normal 0 0 0\nouter loop\n";
    for (auto* v : t) s += std::string("vertex ") + v + "\n";
    s += "endloop\nendfacet\n";
  }
  s += "endsolid t\n";
  SurfaceMesh m = read_surface(write("tet.stl", s));
  EXPECT_EQ(m.V.rows(), 4);
  EXPECT_EQ(m.F.rows(), 4);
}

TEST_F(Readers, StlBinaryWhoseHeaderStartsWithSolid) {
  std::string data(84 + 50 * 4, '\0');
  std::memcpy(data.data(), "solid but binary", 16);
  const uint32_t n = 4;
  std::memcpy(data.data() + 80, &n, 4);
  const float tris[4][9] = {{0, 0, 0, 0, 1, 0, 1, 0, 0},
                            {0, 0, 0, 1, 0, 0, 0, 0, 1},
                            {0, 0, 0, 0, 0, 1, 0, 1, 0},
                            {1, 0, 0, 0, 1, 0, 0, 0, 1}};
  for (int t = 0; t < 4; ++t) std::memcpy(data.data() + 84 + 50 * t + 12, tris[t], 36);
  SurfaceMesh m = read_surface(write("bin.stl", data));
  EXPECT_EQ(m.V.rows(), 4);
  EXPECT_EQ(m.F.rows(), 4);
  expect_error([&] { read_surface(write("short.stl", data.substr(0, 84 + 60))); }, "short.stl", "truncated");
}

TEST_F(Readers, PlyAsciiAndBinary) {
  const std::string header =
      "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 4\nproperty list uchar int vertex_indices\nend_header\n";
  SurfaceMesh a = read_surface(write("a.ply", "ply\nformat ascii 1.0\n" + header +
                                                  "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"));
  EXPECT_EQ(a.F.rows(), 4);
  std::string bin = "ply\nformat binary_little_endian 1.0\n" + header;
  const float V[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  bin.append(reinterpret_cast<const char*>(V), sizeof V);
  const int F[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  for (auto& f : F) {
    bin.push_back(3);
    bin.append(reinterpret_cast<const char*>(f), 12);
  }
  SurfaceMesh b = read_surface(write("b.ply", bin));
  EXPECT_EQ(b.V.rows(), 4);
  EXPECT_EQ(b.F(3, 2), 3);
  expect_error([&] { read_surface(write("c.ply", bin.substr(0, bin.size() - 5))); }, "c.ply", "truncated");
}

TEST_F(Readers, GmshVersion1And2WithMixedElements) {
  const std::string nodes = "5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n7 1 1 1\n";
  TetMesh v1 = read_volume(write("v1.msh", "$NOD\n" + nodes +
                                               "$ENDNOD\n$ELM\n3\n1 15 0 0 1 1\n2 2 1 1 3 1 2 3\n"
                                               "3 4 1 1 4 1 2 3 4\n$ENDELM\n"));
  EXPECT_EQ(v1.T.rows(), 1);
  EXPECT_EQ(v1.V.rows(), 5);
  TetMesh v2 = read_volume(write("v2.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n" + nodes +
                                               "$EndNodes\n$Elements\n3\n1 1 2 0 1 1 2\n2 4 2 0 1 1 3 2 4\n"
                                               "3 4 2 0 1 2 3 4 7\n$EndElements\n"));
  EXPECT_EQ(v2.T.rows(), 2);
  EXPECT_GT(total_volume(v2), 0);  // the negatively oriented first tet was flipped
  expect_error(
      [&] { read_volume(write("bad.msh", "$NOD\n" + nodes + "$ENDNOD\n$ELM\n1\n1 4 1 1 4 1 2 3 9\n$ENDELM\n")); },
      "bad.msh", "out of range");
  expect_error([&] { read_volume(write("trunc.msh", "$NOD\n5\n1 0 0 0\n")); }, "trunc.msh", "truncated");
}

// The same mesh in Gmsh 2.2 and 4.1: six nodes with sparse, unordered tags, three
// tets (the last negatively oriented), a triangle, and a 10-node tet both versions
// ignore. In 4.1 the nodes come in blocks (a point, a parametric surface block with
// u v, a volume block) in the 2.2 file's order.
const char* kGmsh22 =
    "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n6\n40 0 0 0\n7 1 0 0\n13 0 1 0\n2 0 0 1\n99 1 1 1\n58 0 0 -1\n"
    "$EndNodes\n$Elements\n5\n3 2 2 5 1 40 7 13\n10 4 2 1 1 40 7 13 2\n12 4 2 1 1 7 13 2 99\n"
    "11 4 2 1 1 40 7 13 58\n1 11 2 1 1 40 7 13 2 99 58 40 7 13 2\n$EndElements\n";
const char* kGmsh41 =
    "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 1 \"tissue\"\n$EndPhysicalNames\n"
    "$Entities\n1 0 1 1\n1 0 0 0 0\n1 0 0 0 1 1 0 1 5 0\n1 0 0 -1 1 1 1 1 1 1 1\n$EndEntities\n"
    "$Nodes\n3 6 2 99\n0 1 0 1\n40\n0 0 0\n2 1 1 2\n7\n13\n1 0 0 0.5 0\n0 1 0 0 0.5\n"
    "3 1 0 3\n2\n99\n58\n0 0 1\n1 1 1\n0 0 -1\n$EndNodes\n"
    "$Elements\n3 5 1 12\n2 1 2 1\n3 40 7 13\n3 1 4 3\n10 40 7 13 2\n12 7 13 2 99\n11 40 7 13 58\n"
    "3 1 11 1\n1 40 7 13 2 99 58 40 7 13 2\n$EndElements\n";

TEST_F(Readers, Gmsh41ReadsAsTheSameMeshIn22) {
  const TetMesh v22 = read_volume(write("v22.msh", kGmsh22));
  const TetMesh v41 = read_volume(write("v41.msh", kGmsh41));
  EXPECT_EQ(v41.V, v22.V);
  EXPECT_EQ(v41.T, v22.T);
  ASSERT_EQ(v41.V.rows(), 6);
  ASSERT_EQ(v41.T.rows(), 3);                            // the triangle and the 10-node tet ignored
  EXPECT_EQ(v41.V.row(0), Eigen::RowVector3d(0, 0, 0));  // tag 40: the file's order, not the tags'
  EXPECT_EQ(v41.V.row(5), Eigen::RowVector3d(0, 0, -1));
  EXPECT_NEAR(total_volume(v41), 4.0 / 6, 1e-15);  // the negative tet flipped
  // Scaled as the other formats.
  EXPECT_EQ(read_volume(write("v41cm.msh", kGmsh41), 0.01).V, v22.V * 0.01);
}

/// A node's tag in the Gmsh files written below: sparse and out of order (37 i mod
/// 1009 runs through 0..1008 once for i < 1009).
long sparse_tag(Eigen::Index i) { return (i * 37) % 1009 * 3 + 11; }

std::string xyz(const TetMesh& m, Eigen::Index i) {
  std::ostringstream os;
  os << std::setprecision(17) << m.V(i, 0) << ' ' << m.V(i, 1) << ' ' << m.V(i, 2);
  return os.str();
}

/// `m` as Gmsh 2.2 with sparse_tag node tags, a point and a triangle element before the tets.
std::string gmsh22_text(const TetMesh& m) {
  std::ostringstream os;
  os << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n" << m.V.rows() << '\n';
  for (Eigen::Index i = 0; i < m.V.rows(); ++i) os << sparse_tag(i) << ' ' << xyz(m, i) << '\n';
  os << "$EndNodes\n$Elements\n"
     << m.T.rows() + 2 << "\n1 15 2 0 1 " << sparse_tag(0) << "\n2 2 2 0 1 " << sparse_tag(m.T(0, 0)) << ' '
     << sparse_tag(m.T(0, 1)) << ' ' << sparse_tag(m.T(0, 2)) << '\n';
  for (Eigen::Index t = 0; t < m.T.rows(); ++t)
    os << t + 3 << " 4 2 0 1 " << sparse_tag(m.T(t, 0)) << ' ' << sparse_tag(m.T(t, 1)) << ' ' << sparse_tag(m.T(t, 2))
       << ' ' << sparse_tag(m.T(t, 3)) << '\n';
  os << "$EndElements\n";
  return os.str();
}

/// The same mesh as Gmsh 4.1, nodes in four blocks (a point, a parametric surface
/// block, an empty curve block, a volume block) and the tets in two volume blocks.
std::string gmsh41_text(const TetMesh& m) {
  const Eigen::Index n = m.V.rows(), t = m.T.rows(), half = n / 2;
  long lo = sparse_tag(0), hi = lo;
  for (Eigen::Index i = 0; i < n; ++i) {
    lo = std::min(lo, sparse_tag(i));
    hi = std::max(hi, sparse_tag(i));
  }
  std::ostringstream os;
  os << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n1 1 1 2\n1 0 0 0 0\n1 0 0 0 1 1 1 0 2 1 -1\n"
     << "1 0 0 0 1 1 1 0 0\n1 0 0 0 1 1 1 1 3 1 1\n2 0 0 0 1 1 1 0 1 1\n$EndEntities\n";
  os << "$Nodes\n4 " << n << ' ' << lo << ' ' << hi << '\n';
  auto block = [&](int dim, int parametric, Eigen::Index from, Eigen::Index to) {
    os << dim << " 1 " << parametric << ' ' << to - from << '\n';
    for (Eigen::Index i = from; i < to; ++i) os << sparse_tag(i) << '\n';
    for (Eigen::Index i = from; i < to; ++i) os << xyz(m, i) << (parametric ? " 0.25 0.75" : "") << '\n';
  };
  block(0, 0, 0, 1);
  block(2, 1, 1, half);
  block(1, 0, half, half);
  block(3, 0, half, n);
  os << "$EndNodes\n$Elements\n4 " << t + 2 << " 1 " << t + 2 << "\n0 1 15 1\n1 " << sparse_tag(0) << "\n2 1 2 1\n2 "
     << sparse_tag(m.T(0, 0)) << ' ' << sparse_tag(m.T(0, 1)) << ' ' << sparse_tag(m.T(0, 2)) << '\n';
  auto tets = [&](int entity, Eigen::Index from, Eigen::Index to) {
    os << "3 " << entity << " 4 " << to - from << '\n';
    for (Eigen::Index e = from; e < to; ++e)
      os << e + 3 << ' ' << sparse_tag(m.T(e, 0)) << ' ' << sparse_tag(m.T(e, 1)) << ' ' << sparse_tag(m.T(e, 2)) << ' '
         << sparse_tag(m.T(e, 3)) << '\n';
  };
  tets(1, 0, t / 2);
  tets(2, t / 2, t);
  os << "$EndElements\n";
  return os.str();
}

/// A generated cube mesh (TetGen), centred in x and y as the cube scenarios' surface.
TetMesh cube_volume(int n, double max_volume) {
  TetMesh m = testing::box_mesh(0.1, 0.1, 0.1, n, n, n, max_volume);
  m.V.col(0).array() -= 0.05;
  m.V.col(1).array() -= 0.05;
  return m;
}

TEST_F(Readers, Gmsh41WriterRoundTrip) {
  const TetMesh cube = cube_volume(4, 2e-6);
  ASSERT_GT(cube.T.rows(), 100);
  const std::string p = (dir / "cube41.msh").string();
  write_gmsh41(p, cube);
  const TetMesh back = read_volume(p);
  EXPECT_EQ(back.V, cube.V);  // 17 digits: bitwise
  EXPECT_EQ(back.T, cube.T);
  // The 2.2 and 4.1 files of the generated mesh with sparse tags read the same.
  ASSERT_LT(cube.V.rows(), 1009);
  const TetMesh v22 = read_volume(write("cube22_tags.msh", gmsh22_text(cube)));
  const TetMesh v41 = read_volume(write("cube41_tags.msh", gmsh41_text(cube)));
  EXPECT_EQ(v22.V, cube.V);
  EXPECT_EQ(v22.T, cube.T);
  EXPECT_EQ(v41.V, cube.V);
  EXPECT_EQ(v41.T, cube.T);
  // A tet naming a node the mesh lacks is not written.
  TetMesh bad = cube;
  bad.T(3, 2) = static_cast<int>(cube.V.rows());
  EXPECT_THROW(write_gmsh41((dir / "bad41.msh").string(), bad), std::runtime_error);
  EXPECT_FALSE(fs::exists(dir / "bad41.msh"));
}

TEST_F(Readers, Gmsh41CoarseVolumeMeshesAsVersion2) {
  // The scenario path (mesh_recipe.h, "type": "files" with a given "coarse" volume):
  // the cube surface embedded in a coarse cube given as 2.2, as 4.1 with the same
  // node tags, and as write_gmsh41 writes it, builds the same hybrid mesh.
  write_obj((dir / "cube.obj").string(), make_cube_surface({0.1, 0.1, 6, 6, 6}));
  const TetMesh coarse = cube_volume(2, 0);
  write("coarse22.msh", gmsh22_text(coarse));
  write("coarse41.msh", gmsh41_text(coarse));
  write_gmsh41((dir / "written41.msh").string(), coarse);
  auto build = [&](const std::string& coarse_file) {
    const nlohmann::json mesh = {
        {"type", "files"}, {"surface", "cube.obj"}, {"coarse", coarse_file}, {"build_fine_volume", false}};
    MeshReport report;
    return build_mesh(parse_mesh_recipe(mesh, dir.string(), "test.json: mesh"), report);
  };
  const HybridMesh h22 = build("coarse22.msh");
  EXPECT_EQ(h22.coarse_volume.V, coarse.V);
  EXPECT_EQ(h22.coarse_volume.T, coarse.T);
  ASSERT_GT(h22.control_points.size(), 8u);
  for (const std::string file : {"coarse41.msh", "written41.msh"}) {
    const HybridMesh h41 = build(file);
    EXPECT_EQ(h41.fine_surface.V, h22.fine_surface.V) << file;
    EXPECT_EQ(h41.coarse_volume.V, h22.coarse_volume.V) << file;
    EXPECT_EQ(h41.coarse_volume.T, h22.coarse_volume.T) << file;
    ASSERT_EQ(h41.control_points.size(), h22.control_points.size()) << file;
    for (size_t i = 0; i < h22.control_points.size(); ++i) {
      const ControlPoint &a = h22.control_points[i], &b = h41.control_points[i];
      EXPECT_EQ(b.surface_vertex, a.surface_vertex) << file;
      EXPECT_EQ(b.coarse.tet, a.coarse.tet) << file;
      EXPECT_EQ(b.coarse.weights, a.coarse.weights) << file;
    }
    EXPECT_EQ(max_embedding_distance(h41), max_embedding_distance(h22)) << file;
  }
}

TEST_F(Readers, TetgenNodeEleAndFace) {
  write("m.node", "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n");
  const auto ele = write("m.ele", "1 4 0\n1 1 2 3 4\n");
  TetMesh m = read_volume(ele);
  EXPECT_EQ(m.T.rows(), 1);
  EXPECT_NEAR(total_volume(m), 1.0 / 6, 1e-15);
  Triangles F = read_tetgen_faces(write("m.face", "1 0\n1 1 2 3\n"), 1);
  EXPECT_EQ(F(0, 2), 2);
}

TEST_F(Readers, VtuRoundTrip) {
  SurfaceMesh cube = make_cube_surface({});
  const auto p = (dir / "cube.vtu").string();
  write_surface_vtu(p, cube, {{"u", Eigen::MatrixXd::Ones(cube.V.rows(), 3)}});
  SurfaceMesh back = read_surface(p);
  EXPECT_EQ(back.V, cube.V);
  EXPECT_EQ(back.F, cube.F);
  TetMesh tet{(Points(4, 3) << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1).finished(),
              (Tetrahedra(1, 4) << 0, 1, 2, 3).finished()};
  write_volume_vtu((dir / "t.vtu").string(), tet);
  EXPECT_EQ(read_volume((dir / "t.vtu").string()).T, tet.T);
}

TEST_F(Readers, MalformedInputsNameTheFileAndProblem) {
  expect_error([&] { read_surface((dir / "missing.obj").string()); }, "missing.obj", "cannot open");
  expect_error([&] { read_surface(write("x.xyz", "")); }, "x.xyz", "unknown surface format");
  expect_error([&] { read_surface(write("nan.obj", "v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")); }, "nan.obj", "NaN");
  expect_error([&] { read_surface(write("idx.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")); }, "idx.obj",
               "out of range");
  expect_error([&] { read_surface(write("t.off", "OFF\n4 4 6\n0 0 0\n1 0 0\n")); }, "t.off", "truncated");
  expect_error([&] { read_surface(write("word.obj", "v 0 zero 0\n")); }, "word.obj", "expected a number");
  expect_error([&] { read_surface(write("t.stl", "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n")); },
               "t.stl", "truncated");
}

TEST_F(Readers, SurfaceChecks) {
  auto check = [&](const std::string& name, const std::string& obj) {
    SurfaceMesh m = read_surface(write(name, obj));
    check_and_orient_surface(name, m);
    return m;
  };
  // Open: a tet missing one face.
  expect_error([&] { check("open.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\n"); },
               "open.obj", "not closed: 3 boundary edges");
  // Non-manifold edge: three triangles on one edge.
  expect_error([&] { check("nm.obj", std::string(kTetObj) + "v 1 1 1\nf 1 2 5\n"); }, "nm.obj", "not 2-manifold");
  // Degenerate: a zero-area triangle.
  expect_error([&] { check("deg.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\nf 2 3 4\nf 1 3 4\n"); },
               "deg.obj", "degenerate");
  expect_error([&] { check("dup.obj", std::string(kTetObj) + "f 1 2 4\n"); }, "dup.obj", "1 duplicate triangles");
  // Two tets sharing one vertex only: a non-manifold vertex.
  expect_error(
      [&] {
        check("bow.obj", std::string(kTetObj) + "v 0 0 -1\nv -1 0 0\nv 0 -1 0\nf 1 6 5\nf 1 5 7\nf 1 7 6\nf 5 6 7\n");
      },
      "bow.obj", "more than one fan");
  // One triangle flipped and the whole surface inward: both fixed.
  SurfaceMesh m = check("flip.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 3 4\n");
  EXPECT_NEAR(enclosed_volume(m), 1.0 / 6, 1e-15);
}

TEST_F(Readers, TetChecks) {
  TetMesh flat{(Points(4, 3) << 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0).finished(),
               (Tetrahedra(1, 4) << 0, 1, 2, 3).finished()};
  expect_error([&] { orient_and_check_tets("flat.msh", flat); }, "flat.msh", "1 tetrahedra with zero volume");
  TetMesh neg{(Points(4, 3) << 0, 0, 0, 0, 1, 0, 1, 0, 0, 0, 0, 1).finished(),
              (Tetrahedra(1, 4) << 0, 1, 2, 3).finished()};
  EXPECT_EQ(orient_and_check_tets("neg", neg), 1);
  EXPECT_GT(total_volume(neg), 0);
}

}  // namespace
}  // namespace tb
