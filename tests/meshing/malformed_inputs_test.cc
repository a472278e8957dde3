// Inputs the fuzz targets (tests/fuzz/, docs/robustness.md) found or aimed at, each
// now refused with one line naming the file and the problem: before the fixes they
// read out of bounds, asked for tens of GiB from a few bytes, or threw an exception
// without the file's name. The same inputs are seeds of the fuzz corpus
// (tests/fuzz/corpus/<target>/regression_*).
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>

#include "mesh_error.h"
#include "mesh_io.h"
#include "test_support.h"

namespace tb {
namespace {
namespace fs = std::filesystem;

class MalformedInputs : public ::testing::Test {
 protected:
  const tb::testing::TempFolder tmp{"malformed"};
  std::string write(const std::string& name, const std::string& content) {
    const std::string p = (tmp.path / name).string();
    std::ofstream(p, std::ios::binary) << content;
    return p;
  }
  /// `read` on a file `name` holding `content` throws MeshError: one line, naming
  /// the file and containing `problem`.
  template <class Read>
  void expect_refused(Read read, const std::string& name, const std::string& content, const std::string& problem) {
    const std::string p = write(name, content);
    try {
      read(p);
      ADD_FAILURE() << "accepted: " << name;
    } catch (const MeshError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find(name), std::string::npos) << m;
      EXPECT_NE(m.find(problem), std::string::npos) << m;
      EXPECT_EQ(m.find_first_of("\n\r"), std::string::npos) << m;
    }
  }
};

const char* kTetVertices = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
const auto surface = [](const std::string& p) { read_surface(p); };
const auto volume = [](const std::string& p) { read_volume(p); };

TEST_F(MalformedInputs, CountsBeyondWhatTheFileHoldsAreRefusedBeforeAllocating) {
  expect_refused(surface, "huge.off", "OFF\n99999999999 1 0\n0 0 0\n", "the header says 99999999999 vertices");
  expect_refused(volume, "huge.msh", "$NOD\n9223372036854775807\n1 0 0 0\n$ENDNOD\n", "the header says");
  // The .face count sized a matrix before any face was read (48 GB here).
  expect_refused([](const std::string& p) { read_tetgen_faces(p, 1); }, "huge.face", "4000000000 0\n1 1 2 3\n",
                 "the header says 4000000000 faces");
  expect_refused(surface, "huge.ply",
                 "ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\nend_header\n0\n",
                 "truncated PLY: the header says 4000000000 vertex");
}

TEST_F(MalformedInputs, IndicesAndFieldCountsAreCheckedBeforeUse) {
  // A negative tag count made the first node's field index wrap around (read out of bounds).
  expect_refused(volume, "tags.msh",
                 "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n"
                 "$Elements\n1\n1 4 -5 1 2 3 4\n$EndElements\n",
                 "element says -5 tags");
  expect_refused(surface, "face.off", std::string("OFF\n4 1 0\n") + kTetVertices + "9 0 1 2\n",
                 "face says 9 vertices and lists 3");
  expect_refused([](const std::string& p) { read_tetgen_faces(p, 1); }, "below.face", "1 0\n1 0 1 2\n",
                 "below the first index 1");
}

TEST_F(MalformedInputs, PlyHeadersAreCheckedLineByLine) {
  // std::stol threw std::invalid_argument ("stol"), with no file name.
  expect_refused(surface, "count.ply", "ply\nformat ascii 1.0\nelement vertex x\nend_header\n",
                 "header line 3: element count 'x' is not a whole number");
  expect_refused(surface, "type.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n0\n",
                 "header line 4: unknown PLY property type 'quad'");
  expect_refused(surface, "orphan.ply", "ply\nformat ascii 1.0\nproperty float x\nend_header\n",
                 "header line 3: property before any element");
  expect_refused(surface, "listcount.ply",
                 "ply\nformat ascii 1.0\nelement face 1\nproperty list float int vertex_indices\nend_header\n3 0 1 2\n",
                 "a list count of type 'float'");
}

TEST_F(MalformedInputs, BinaryPlyListsAreWholeNumbersTheFileCanHold) {
  const std::string ints(12, '\0');
  const std::string header =
      "ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\nelement face 1\n";
  // A count the rest of the file cannot hold (it was read entry by entry to the end).
  const uint32_t count = 3000000000u;
  expect_refused(surface, "long.ply",
                 header + "property list uint int vertex_indices\nend_header\n" +
                     std::string(reinterpret_cast<const char*>(&count), 4) + ints,
                 "truncated binary PLY (a list of 3000000000 entries with room for 3)");
  // Float list entries were cast to long: undefined for NaN (UBSan's float-cast-overflow).
  const float entries[3] = {0, std::numeric_limits<float>::quiet_NaN(), 2};
  expect_refused(surface, "nan.ply",
                 header + "property list uchar float vertex_indices\nend_header\n" + std::string(1, '\3') +
                     std::string(reinterpret_cast<const char*>(entries), sizeof entries),
                 "a list entry of element face nan is not a whole number");
}

TEST_F(MalformedInputs, NumbersEndAtTheirTokensEnd) {
  // strtod stopped at an embedded NUL and took "1\0x" for 1.
  expect_refused(surface, "nul.obj", std::string("v 0 0 1\0x\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", 34), "expected a number");
}

// Gmsh 4.1: a valid tetrahedron (kHead41 + kNodes41 + kElements41), then each part broken.
// Aimed at, not found: the format's seeds are the valid tests/fuzz/corpus/gmsh/cube_v41*.msh.
const std::string kHead41 = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
const std::string kNodes41 = "$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n" + std::string(kTetVertices) + "$EndNodes\n";
const std::string kElements41 = "$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3 4\n$EndElements\n";

TEST_F(MalformedInputs, Gmsh41CountsAndTagsAreCheckedBeforeUse) {
  EXPECT_EQ(read_volume(write("ok41.msh", kHead41 + kNodes41 + kElements41)).T.rows(), 1);
  // Counts larger than the rest of the file, refused before anything is allocated.
  expect_refused(volume, "nodes41.msh", kHead41 + "$Nodes\n1 99999999999 1 4\n3 1 0 4\n1\n",
                 "the header says 99999999999 nodes");
  expect_refused(volume, "blocks41.msh", kHead41 + "$Nodes\n99999999 4 1 4\n3 1 0 4\n1\n",
                 "the header says 99999999 node entity blocks");
  expect_refused(volume, "elements41.msh", kHead41 + kNodes41 + "$Elements\n1 4000000000 1 1\n3 1 4 1\n",
                 "the header says 4000000000 elements");
  expect_refused(volume, "elementblock41.msh", kHead41 + kNodes41 + "$Elements\n1 1 1 1\n3 1 4 4000000000\n",
                 "the header says 4000000000 elements in a block");
  expect_refused(volume, "entities41.msh", kHead41 + "$Entities\n99999999 0 0 0\n1 0 0 0 0\n$EndEntities\n",
                 "the header says 99999999 point entities");
  // Blocks holding more or fewer than the section's header says.
  expect_refused(volume, "over41.msh",
                 kHead41 + "$Nodes\n1 4 1 4\n3 1 0 5\n1\n2\n3\n4\n" + kTetVertices + "$EndNodes\n" + kElements41,
                 "line 6: node block 1 of 1 says 5 nodes, more than the 4 the $Nodes header leaves");
  expect_refused(volume, "under41.msh",
                 kHead41 + "$Nodes\n1 4 1 4\n3 1 0 3\n1\n2\n3\n0 0 0\n1 0 0\n0 1 0\n$EndNodes\n" + kElements41,
                 "the node blocks hold 3 nodes, the $Nodes header says 4");
  expect_refused(volume, "underelements41.msh",
                 kHead41 + kNodes41 + "$Elements\n1 2 1 2\n3 1 4 1\n1 1 2 3 4\n$EndElements\n",
                 "the element blocks hold 1 elements, the $Elements header says 2");
  // Tags outside the header's range; an element naming a node no block defines.
  expect_refused(volume, "tag41.msh",
                 kHead41 + "$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n9\n4\n" + kTetVertices + "$EndNodes\n" + kElements41,
                 "line 9: node tag 9 is outside the range 1 to 4 of the $Nodes header");
  expect_refused(volume, "elementtag41.msh",
                 kHead41 + kNodes41 + "$Elements\n1 1 1 1\n3 1 4 1\n5 1 2 3 4\n$EndElements\n",
                 "element tag 5 is outside the range 1 to 1");
  expect_refused(volume, "missing41.msh", kHead41 + kNodes41 + "$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3 7\n$EndElements\n",
                 "1 tetrahedron node references out of range (e.g. node 7 is not defined)");
  expect_refused(
      volume, "twice41.msh",
      kHead41 + "$Nodes\n2 4 1 4\n3 1 0 2\n1\n2\n0 0 0\n1 0 0\n3 1 0 2\n2\n4\n0 1 0\n0 0 1\n$EndNodes\n" + kElements41,
      "node id 2 defined twice");
}

TEST_F(MalformedInputs, Gmsh41LinesHoldWhatTheirCountsSay) {
  expect_refused(volume, "param41.msh",
                 kHead41 + "$Nodes\n1 4 1 4\n3 1 1 4\n1\n2\n3\n4\n" + kTetVertices + "$EndNodes\n" + kElements41,
                 "line 11: node 1 needs 6 coordinates, found 3");
  expect_refused(volume, "tags41.msh", kHead41 + "$Nodes\n1 4 1 4\n3 1 0 4\n1 2 3 4\n" + kTetVertices,
                 "expected one node tag on the line, found 4 fields");
  expect_refused(volume, "dim41.msh", kHead41 + "$Nodes\n1 4 1 4\n4 1 0 4\n1\n2\n3\n4\n" + kTetVertices,
                 "entity dimension 4 is not 0, 1, 2 or 3");
  expect_refused(volume, "tet41.msh", kHead41 + kNodes41 + "$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3\n$EndElements\n",
                 "tetrahedron needs a tag and 4 nodes, found 4 fields");
  expect_refused(volume, "physical41.msh", kHead41 + "$Entities\n1 0 0 0\n1 0 0 0 2 5\n$EndEntities\n",
                 "point entity says 2 physical tags and has 1 fields left");
  expect_refused(volume, "bounding41.msh", kHead41 + "$Entities\n0 0 0 1\n1 0 0 0 1 1 1 0 3 1 2\n$EndEntities\n",
                 "volume entity says 3 bounding entities and has 2 fields left");
  expect_refused(volume, "entityline41.msh", kHead41 + "$Entities\n0 0 1 0\n1 0 0 0 1 1 1 0 0 7\n$EndEntities\n",
                 "surface entity line has 10 fields, its counts say 9");
  expect_refused(volume, "header41.msh", kHead41 + "$Nodes\n1 4\n", "$Nodes header needs 4 numbers");
}

TEST_F(MalformedInputs, Gmsh41FilesEndWhereTheirSectionsSay) {
  // Counts the file can hold, but it ends inside $Nodes.
  expect_refused(volume, "truncated41.msh",
                 kHead41 + "$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n0.0 0.0 0.0\n1.0 0.0 0.0\n0.0 1.0 0.0\n",
                 "truncated file (expected coordinates of node 4)");
  expect_refused(volume, "noend41.msh", kHead41 + kNodes41 + "$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3 4\n",
                 "truncated file (expected $EndElements)");
  expect_refused(volume, "otherend41.msh",
                 kHead41 + kNodes41 + "$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3 4\n$NodeData\n$EndNodeData\n",
                 "line 20: expected $EndElements, found '$NodeData'");
  expect_refused(volume, "entitiesend41.msh", kHead41 + "$Entities\n1 0 0 0\n1 0 0 0 0\n" + kNodes41,
                 "expected $EndEntities, found '$Nodes'");
  // Binary 4.1 (file type 1) and 4.0 are refused at the format line.
  expect_refused(volume, "binary41.msh",
                 kHead41.substr(0, 12) + "4.1 1 8\n" + std::string("\x01\0\0\0\n", 5) + "$EndMeshFormat\n$Nodes\n",
                 "line 2: binary Gmsh files are not supported (file type 1; save as ASCII)");
  expect_refused(volume, "v40.msh", "$MeshFormat\n4 0 8\n$EndMeshFormat\n" + kNodes41 + kElements41,
                 "unsupported Gmsh version 4 (versions 1, 2 and 4.1 are read)");
}

TEST_F(MalformedInputs, MessagesAreOneLineWhateverTheInputHolds) {
  EXPECT_EQ(one_line("a\nb\rc\x01"), "a\\nb\\rc\\x01");
  EXPECT_EQ(one_line(std::string(10, 'x'), 4), "xxxx ... (6 more characters)");
  // A format name read from the file holding a carriage return and a control byte.
  expect_refused(surface, "format.ply", "ply\nformat asc\x01ii\x7f 1.0\nend_header\n", "asc\\x01ii\\x7f");
}

}  // namespace
}  // namespace tb
