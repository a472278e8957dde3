// The scenario's loads beyond the paper's `load`, its tools and its interior probes
// (docs/scenario_schema.md: "loads", "tools", "probes"), and the time dependence of
// each one's value: a ramp, or a path of waypoints.
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "data_dir.h"
#include "load_case.h"
#include "mesh_recipe.h"
#include "strict_json.h"

namespace tb {

/// A value over the frames: `value` reached linearly over ramp_frames ((frame + 1)
/// / ramp_frames of it until then), or, when `path` is given, the piecewise-linear
/// interpolation of its waypoints (frame, value), held before the first and after
/// the last.
struct Schedule {
  Eigen::Vector3d value = Eigen::Vector3d::Zero();
  int ramp_frames = 0;
  std::vector<std::pair<int, Eigen::Vector3d>> path;  ///< frames strictly increasing, >= 0
  Eigen::Vector3d at(int frame) const;
  /// The last frame at which the value changes (the ramp's or the path's end).
  int settled_from() const;
  nlohmann::json to_json() const;
};

struct ScenarioLoad {
  Load load;
  Schedule schedule;  ///< a force (N) or an acceleration (m/s^2)
};

struct ScenarioTool {
  Tool tool;
  Schedule schedule;  ///< the tool's displacement (m); a sphere's centre (m)
};

/// "loads": [...] of a scenario file. Each entry: "type" point_force (point, force),
/// surface_traction (point, radius, force) or gravity (g), and its schedule.
std::vector<ScenarioLoad> parse_loads(StrictObject& scenario);
/// "tools": [...]. Each entry: "type" grasp (point, radius) or plate (box {min,
/// max}, mode bonded | sliding, normal x | y | z), and its displacement schedule;
/// or sphere (radius, and the path of its centre: the schedule's value is the centre).
std::vector<ScenarioTool> parse_tools(StrictObject& scenario);
/// Interior points, and where they come from when it is not the scenario itself.
struct ScenarioProbes {
  Points points = Points(0, 3);
  /// Empty for points given in the scenario; {"truth_cube": {table, frame, ...}}
  /// for the Truth Cube's beads (truth_cube.h).
  nlohmann::json source = nlohmann::json::object();
};

/// "probes": {"points": [[x, y, z], ...]}, {"file": "points.csv"} (a header line,
/// then x,y,z per line; relative to the scenario file), or {"truth_cube": {"table":
/// "data:data/truthcube/uniaxial_positions.csv", "compare_at_strain": 0.05}} (the beads
/// at rest, on a cube mesh). Empty if absent.
ScenarioProbes parse_probes(StrictObject& scenario, const std::string& base_dir, const DataDir& data,
                            const MeshRecipe& mesh);

nlohmann::json to_json(const ScenarioLoad& l);
nlohmann::json to_json(const ScenarioTool& t);

}  // namespace tb
