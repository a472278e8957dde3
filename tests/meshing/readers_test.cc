// One test per reader and per malformed input: each error names the file
// and the problem.
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "atomic_file.h"
#include "cube_generator.h"
#include "mesh_checks.h"
#include "mesh_error.h"
#include "mesh_io.h"
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
