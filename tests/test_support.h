// Helpers shared by the tests: a temporary folder, the paper's meshes built from
// the committed scenario files, and a mirror-symmetry measure.
#pragma once

#include <unistd.h>

#include <Eigen/Core>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "elastic_solve.h"
#include "mesh_types.h"
#include "model.h"

namespace tb::testing {

/// The support of the paper's cube scenarios: the bottom face z = 0 clamped.
inline const SupportBox kCubeBottom{{-1, -1, -1e-9}, {1, 1, 1e-9}};

/// A point force for tests: where it acts (rest configuration) and its value.
struct PointForce {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  /// The load case's one load, and this frame's value of it.
  std::vector<Load> loads() const { return {Load::point_force(point)}; }
  FrameLoads frame() const { return frame_of(force); }
  /// The same point with force `scale` times this one's.
  PointForce scaled(double scale) const { return {point, scale * force}; }
};
/// The paper's cube pull: 1 N up at the top centre.
inline const PointForce kCubePull{{0, 0, 0.1}, {0, 0, 1}};

/// The registered model `name` set up on `mesh` with the default material,
/// `support`, `loads` and `parameters` (resolved against its specs).
std::unique_ptr<Model> set_up_model(const std::string& name, const HybridMesh& mesh,
                                    const SupportBox& support = kCubeBottom,
                                    const nlohmann::json& parameters = nlohmann::json::object(),
                                    const std::vector<Load>& loads = kCubePull.loads());

/// Steps `model` under `frame` once, then up to `max_more` frames more until its
/// reactions (every tool's and the support's) change by at most 1e-12 of their size
/// in a frame: a dynamic model's reactions carry the inertia of what it holds until
/// it settles (max_more 0 for a static model).
void step_until_reactions_settle(Model& model, const FrameLoads& frame, int max_more);

/// The elastic solve `given` asks for, e.g. {"solver": "corotational",
/// "cg_tolerance": 1e-10} (the fem model's parameter names; unnamed ones default),
/// on `body`, with `coarse_space` for the two-level preconditioner.
std::unique_ptr<ElasticSolve> make_solve(const ElasticBody& body, const nlohmann::json& given,
                                         const TetMesh* coarse_space = nullptr);

/// A fresh folder under the system temp dir, removed at destruction.
struct TempFolder {
  std::filesystem::path path;
  explicit TempFolder(const std::string& tag)
      : path(std::filesystem::temp_directory_path() / ("tb-" + tag + "-" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~TempFolder() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  std::string operator/(const std::string& name) const { return (path / name).string(); }
};

/// The hybrid mesh of a committed scenario (experiments/scenarios/<name>.json),
/// built once per process. `with_fine_volume` false skips the fine TetGen mesh;
/// `symmetric_fine_volume` asks for the mirror-symmetric fine volume (cube only).
const HybridMesh& scenario_mesh(const std::string& name, bool with_fine_volume = true,
                                bool symmetric_fine_volume = false);

/// A generated shape of meshing/shapes.h ("torus", "l_block", ...) at refinement 12,
/// meshed as the tests use it (TetGen radius-edge bound 1.414, about 120 coarse
/// nodes), built once per process.
const HybridMesh& shape_mesh(const std::string& shape);

/// TetGen's mesh of the box [0, lx] x [0, ly] x [0, lz], its surface a structured
/// nx x ny x nz grid (make_cube_surface), tets at most max_volume.
TetMesh box_mesh(double lx, double ly, double lz, int nx, int ny, int nz, double max_volume);

/// Largest |values(v) - parity values(mirror(v))| over vertices, where mirror(v)
/// is the vertex nearest v reflected across the plane x_axis = 0 (parity -1 for
/// the reflected component of a vector field).
///   V       #V by 3 positions, values  #V
double mirror_asymmetry(const Points& V, const Eigen::VectorXd& values, int axis, double parity = 1);

}  // namespace tb::testing
