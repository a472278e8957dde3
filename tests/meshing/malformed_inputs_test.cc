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

TEST_F(MalformedInputs, MessagesAreOneLineWhateverTheInputHolds) {
  EXPECT_EQ(one_line("a\nb\rc\x01"), "a\\nb\\rc\\x01");
  EXPECT_EQ(one_line(std::string(10, 'x'), 4), "xxxx ... (6 more characters)");
  // A format name read from the file holding a carriage return and a control byte.
  expect_refused(surface, "format.ply", "ply\nformat asc\x01ii\x7f 1.0\nend_header\n", "asc\\x01ii\\x7f");
}

}  // namespace
}  // namespace tb
