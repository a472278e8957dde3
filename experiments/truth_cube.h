// The Truth Cube's bead table (Kerdok, Cotin, Ottensmeyer, Galea, Howe, Dawson,
// "Truth cube: establishing physical standards for soft tissue simulation",
// Medical Image Analysis 7(3):283-291, 2003): 343 Teflon beads on a 7 x 7 x 7 grid
// in an 8 cm silicone cube, located by CT at rest and at three nominal compressive
// strains. The table is third-party data, read from the data directory (README,
// "Data"); docs/truth_cube.md says how it is used.
//
// The table's frame is the scanner's: millimetres, -z up (the layer that moves most
// under the plate, and in the +z direction, is the one of lowest z). The model's cube
// is centred on the z axis with its base on z = 0 and z up (cube_generator.h). The
// two are related by a rigid motion fixed from the beads at rest alone (never from
// the deformed positions, which are what a model is scored on): the grid's centre
// goes to the cube's centre line at half its height, and the frame is turned half a
// turn about x (y -> -y, z -> -z), which keeps it right-handed.
#pragma once

#include <Eigen/Core>
#include <array>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "mesh_types.h"

namespace tb {

struct TruthCubeBead {
  std::array<int, 3> grid{};                  ///< i, j, k, each 1..7
  std::vector<Eigen::Vector3d> positions_mm;  ///< at rest, then at each strain (table frame, mm)
};

struct TruthCubeTable {
  std::string file;
  std::vector<double> strains;  ///< nominal compressive strain of each position column: 0, then e.g. 0.05
  std::vector<TruthCubeBead> beads;
};

/// Reads the table as distributed (7 header lines naming the strains, then i, j, k
/// and x, y, z per strain, mm). Throws std::runtime_error, one line naming the file
/// (and line) and the problem, on anything else: a missing file, a malformed or
/// non-finite number, a grid index outside 1..7 or repeated.
TruthCubeTable read_truth_cube_table(const std::string& file);

/// The rigid motion from the table's frame (mm) to the model's (m): model =
/// centre_m + diag(axes) (table - origin_mm) / 1000.
struct TruthCubeFrame {
  Eigen::Vector3d origin_mm;  ///< the bead grid's centre at rest, table frame
  Eigen::Vector3d centre_m;   ///< where it goes: (0, 0, height / 2)
  Eigen::Vector3d axes;       ///< (1, -1, -1): half a turn about x
  Eigen::Vector3d to_model(const Eigen::Vector3d& table_mm) const;
  nlohmann::json to_json() const;
};

/// The frame that puts the grid's rest centre on the axis of a cube of this height
/// (m) standing on z = 0.
TruthCubeFrame truth_cube_frame(const TruthCubeTable& table, double cube_height);

/// The beads' rest positions in the model's frame (m), #beads by 3, table order.
Points truth_cube_rest_points(const TruthCubeTable& table, const TruthCubeFrame& frame);

}  // namespace tb
