// The Truth Cube's bead table (experiments/truth_cube.h): the reader on tables
// written here (values, strains, each malformed input a one-line error naming the
// file and line), the rigid frame, the distributed table's orientation (which
// layer the plate moves), and the scenario key probes.truth_cube.
#include "truth_cube.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "data_dir.h"
#include "scenario_fixture.h"

namespace tb {
namespace {

const char* kHeader =
    "Truth Cube,,,,,,,,,,,,,,\n"
    "Uniaxial Compression Test displacment field data for all 4 strains,,,,,,,,,,,,,,\n"
    "All positions in mm,,,,,,,,,,,,,,\n"
    "12-Oct-01,,,,,,,,,,,,,,\n"
    ",,,,,,,,,,,,,,\n"
    "bead nominal location,,,no strain,,,5% strain,,,12.5% strain,,,18.25% strain,,\n"
    "i,j,k,x0,y0,z0,x1,y1,z1,x2,y2,z2,x3,y3,z3\n";

class TruthCubeTables : public Scenarios {
 protected:
  std::string table(const std::string& rows) {
    const std::string p = (dir / "beads.csv").string();
    std::ofstream(p) << kHeader << rows;
    return p;
  }
  void expect_read_error(const std::string& rows, const std::string& message) {
    const std::string p = table(rows);
    try {
      read_truth_cube_table(p);
      FAIL() << "accepted: " << message;
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(p, 0), 0u) << what;  // starts with the file
      EXPECT_NE(what.find(message), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  }
};

const std::string kTwoBeads =
    "1,1,1,-30,-30,10,-30,-30,10.5,-30,-30,11,-30,-30,11.5\n"
    "7,7,7,30,30,-50,30.5,30.5,-46,31,31,-40,31.5,31.5,-35\n";

TEST_F(TruthCubeTables, ReadsTheStrainsAndEveryBeadsPositions) {
  const TruthCubeTable t = read_truth_cube_table(table(kTwoBeads));
  ASSERT_EQ(t.strains.size(), 4u);
  EXPECT_DOUBLE_EQ(t.strains[0], 0);
  EXPECT_DOUBLE_EQ(t.strains[1], 0.05);
  EXPECT_DOUBLE_EQ(t.strains[2], 0.125);
  EXPECT_DOUBLE_EQ(t.strains[3], 0.1825);
  ASSERT_EQ(t.beads.size(), 2u);
  EXPECT_EQ(t.beads[1].grid, (std::array<int, 3>{7, 7, 7}));
  ASSERT_EQ(t.beads[1].positions_mm.size(), 4u);
  EXPECT_EQ(t.beads[1].positions_mm[2], Eigen::Vector3d(31, 31, -40));
}

TEST_F(TruthCubeTables, MalformedTablesAreOneLineErrorsNamingFileAndLine) {
  expect_read_error("1,1,1,-30,-30,10,-30,-30,10.5,-30,-30,11,-30,-30\n", "line 8: expected 15 numbers");
  expect_read_error("1,1,1,-30,-30,10,-30,x,10.5,-30,-30,11,-30,-30,11.5\n", "line 8: column 8: 'x' is not a finite number");
  expect_read_error("1,1,1,-30,-30,10,-30,-30,nan,-30,-30,11,-30,-30,11.5\n", "column 9: 'nan' is not a finite number");
  expect_read_error("8,1,1,-30,-30,10,-30,-30,10.5,-30,-30,11,-30,-30,11.5\n", "grid index 8 is not a whole number in 1..7");
  expect_read_error(kTwoBeads + "1,1,1,0,0,0,0,0,0,0,0,0,0,0,0\n", "line 10: bead (1, 1, 1) appears twice");
  expect_read_error("", "no bead rows after the header");
  const std::string truncated = (dir / "short.csv").string();
  std::ofstream(truncated) << "Truth Cube\n";
  EXPECT_THROW(
      try { read_truth_cube_table(truncated); } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("short.csv: ends within its 7 header lines"), std::string::npos);
        throw;
      },
      std::runtime_error);
  EXPECT_THROW(read_truth_cube_table((dir / "none.csv").string()), std::runtime_error);
}

TEST_F(TruthCubeTables, TheFrameCentresTheRestGridAndTurnsHalfAboutX) {
  const TruthCubeTable t = read_truth_cube_table(table(kTwoBeads));
  const TruthCubeFrame f = truth_cube_frame(t, 0.08);
  EXPECT_EQ(f.origin_mm, Eigen::Vector3d(0, 0, -20));
  EXPECT_TRUE(f.to_model(f.origin_mm).isApprox(Eigen::Vector3d(0, 0, 0.04)));
  // 10 mm further along each table axis: +x stays +x, +y and +z turn over.
  EXPECT_TRUE(f.to_model(f.origin_mm + Eigen::Vector3d(10, 10, 10)).isApprox(Eigen::Vector3d(0.01, -0.01, 0.03)));
  const Points rest = truth_cube_rest_points(t, f);
  EXPECT_TRUE(rest.row(0).transpose().isApprox(Eigen::Vector3d(-0.03, 0.03, 0.01)));
  // A rigid motion: distances kept (mm to m).
  EXPECT_NEAR((rest.row(0) - rest.row(1)).norm() * 1000, (t.beads[0].positions_mm[0] - t.beads[1].positions_mm[0]).norm(),
              1e-9);
}

// The distributed table (data directory): 343 beads, all inside the 80 mm cube once
// moved, and the orientation the frame assumes: the layer the plate moves most is
// the highest in the model's frame, and it moves down.
TEST_F(TruthCubeTables, TheDistributedTableIsUprightInTheModelsFrame) {
  const std::string file = data_dir().path + "/data/truthcube/uniaxial_positions.csv";
  if (!std::filesystem::exists(file)) GTEST_SKIP() << file << " not present (README, 'Data')";
  const TruthCubeTable t = read_truth_cube_table(file);
  ASSERT_EQ(t.beads.size(), 343u);
  ASSERT_EQ(t.strains.size(), 4u);
  const TruthCubeFrame f = truth_cube_frame(t, 0.08);
  const Points rest = truth_cube_rest_points(t, f);
  EXPECT_LE(rest.col(0).cwiseAbs().maxCoeff(), 0.04);
  EXPECT_LE(rest.col(1).cwiseAbs().maxCoeff(), 0.04);
  EXPECT_GT(rest.col(2).minCoeff(), 0);
  EXPECT_LT(rest.col(2).maxCoeff(), 0.08);
  double top_layer_z = 0, top_layer_uz = 0, base_layer_uz = 0;
  int top = 0, base = 0;
  for (size_t b = 0; b < t.beads.size(); ++b) {
    const Eigen::Vector3d u = f.to_model(t.beads[b].positions_mm[3]) - f.to_model(t.beads[b].positions_mm[0]);
    if (t.beads[b].grid[2] == 7) top_layer_z += rest(b, 2), top_layer_uz += u.z(), ++top;
    if (t.beads[b].grid[2] == 1) base_layer_uz += u.z(), ++base;
  }
  ASSERT_EQ(top, 49);
  ASSERT_EQ(base, 49);
  EXPECT_GT(top_layer_z / top, 0.06);              // k = 7 is the layer near the plate
  EXPECT_LT(top_layer_uz / top, -0.01);            // pushed down by more than 10 mm at 18.25 %
  EXPECT_LT(std::abs(base_layer_uz / base), 0.003);  // the layer near the bonded base, a few mm at most
}

TEST_F(TruthCubeTables, TheScenarioKeyNeedsACubeAndAMeasuredStrain) {
  nlohmann::json j = small_cube();
  j["probes"] = {{"truth_cube", {{"table", table(kTwoBeads)}, {"compare_at_strain", 0.3}}}};
  expect_error(j, "probes.truth_cube.compare_at_strain: the table has no column at strain 0.300000");
  j["probes"] = {{"truth_cube", {{"table", "missing.csv"}, {"compare_at_strain", 0.05}}}};
  expect_error(j, "missing.csv: cannot open the Truth Cube table");
  j["probes"] = {{"truth_cube", {{"table", table(kTwoBeads)}, {"compare_at_strain", 0.05}}}, {"points", {{0, 0, 0.05}}}};
  expect_error(j, "give one of points, file or truth_cube");
  j = small_cube();
  j["mesh"] = {{"type", "shape"}, {"shape", "sphere"}};
  j["probes"] = {{"truth_cube", {{"table", table(kTwoBeads)}, {"compare_at_strain", 0.05}}}};
  expect_error(j, "probes.truth_cube.table: the Truth Cube's beads need a mesh of type cube");

  // Accepted: run.json records the table and the frame, not the points.
  j = small_cube();
  j["probes"] = {{"truth_cube", {{"table", table(kTwoBeads)}, {"compare_at_strain", 0.125}}}};
  const Experiment e = load_experiment(write("ok.json", j));
  const Scenario& s = e.scenarios.at(0);
  ASSERT_EQ(s.probes.rows(), 2);
  const nlohmann::json recorded = s.to_json();
  EXPECT_DOUBLE_EQ(recorded["probes"]["truth_cube"]["compare_at_strain"].get<double>(), 0.125);
  EXPECT_TRUE(recorded["probes"]["truth_cube"].contains("frame"));
  EXPECT_FALSE(recorded["probes"].is_array());
}

}  // namespace
}  // namespace tb
