// The boundary-value problem every model receives (docs/architecture.md): the
// support, and the loads, each placed in the rest configuration once (setup) and
// given a value every frame (a force that ramps, a gravity switched on). A model
// maps each load onto its meshes in setup, so a frame does no search and no
// allocation; ModelInfo::loads says which kinds it takes, and any other is one
// error before setup (check_supported).
//
// Tools prescribe where part of the surface is (a grasp, a plate); each holds the
// surface vertices it catches at setup and moves them by its value every frame.
//
// A new kind of load is: its LoadKind and name below, how it is placed (Load), and
// its mapping onto nodes in models/numerics/embedding/load_mapping.h; then each
// model that takes it lists it in its ModelInfo (docs/extending.md). A new tool
// kind the same, with tool_placement.h.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "mesh_types.h"

namespace tb {

/// Vertices whose rest position lies in [min, max] (component-wise) are clamped.
struct SupportBox {
  Eigen::Vector3d min = Eigen::Vector3d::Constant(-1e300), max = Eigen::Vector3d::Constant(1e300);
  bool contains(const Eigen::Vector3d& p) const {
    return (p.array() >= min.array()).all() && (p.array() <= max.array()).all();
  }
  /// #V flags: 1 where the row of V is clamped.
  std::vector<char> select(const Points& V) const;
  /// select(V), checked to hold the body: at least three clamped nodes not on
  /// one line, else a std::invalid_argument naming this box, `mesh_name` and the
  /// counts (a support that leaves rigid motions free makes K singular and PBD
  /// drift). Every model calls it for every mesh it uses, before factorising.
  std::vector<char> clamp(const Points& V, const std::string& mesh_name) const;
};

/// What a load is, and so what its value each frame means.
enum class LoadKind {
  PointForce,       ///< a force (N) at a point: the paper's load
  SurfaceTraction,  ///< a total force (N) spread uniformly over a disc on the surface
  BodyForce,        ///< an acceleration g (m/s^2): the force density rho g everywhere (gravity)
};
inline constexpr LoadKind kLoadKinds[] = {LoadKind::PointForce, LoadKind::SurfaceTraction, LoadKind::BodyForce};
/// "point_force", "surface_traction", "body_force": the names scenario files and
/// `tissuebench models` use.
const char* name(LoadKind kind);

/// A load as placed in the rest configuration, fixed for the run.
struct Load {
  LoadKind kind = LoadKind::PointForce;
  /// Where the scenario states it ("load", "loads[1]"): named in every error about it.
  std::string key = "load";
  /// PointForce: where it acts; SurfaceTraction: the disc's centre, on the surface (m).
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  double radius = 0;  ///< SurfaceTraction: the disc's radius (m)

  static Load point_force(const Eigen::Vector3d& point, std::string key = "load");
  static Load surface_traction(const Eigen::Vector3d& centre, double radius, std::string key = "load");
  static Load body_force(std::string key = "gravity");
};

/// What a tool does to the surface, and so what its value each frame means.
enum class ToolKind {
  Grasp,         ///< the surface vertices within a radius of a point, bonded; value: their displacement (m)
  BondedPlate,   ///< the surface vertices in a box, bonded to a rigid plate; value: its displacement (m)
  SlidingPlate,  ///< the same, frictionless: only the component along the plate's normal axis is held
  /// A rigid frictionless sphere in unilateral contact: the surface may not enter it
  /// and leaves it where the tissue pulls away; holds no vertex at setup. Value: its
  /// centre (m), not a displacement (docs/equations.md, "Contact with a rigid sphere").
  Sphere,
  /// A grasp through compliant jaw pads: the same vertices as Grasp, each tied to the
  /// jaw by a zero-length spring of stiffness pad_stiffness times its vertex area
  /// (ContactArea), a traction kappa (d - u) on the patch (a Robin condition) in
  /// place of the rigid patch's Dirichlet values, whose rim is a strain singularity
  /// (docs/equations.md, "A grasp through compliant pads"). Value: the jaw's
  /// displacement (m).
  CompliantGrasp,
};
inline constexpr ToolKind kToolKinds[] = {ToolKind::Grasp, ToolKind::BondedPlate, ToolKind::SlidingPlate,
                                          ToolKind::Sphere, ToolKind::CompliantGrasp};
/// "grasp", "bonded_plate", "sliding_plate", "sphere", "compliant_grasp".
const char* name(ToolKind kind);

/// A tool as placed in the rest configuration, fixed for the run: the surface
/// vertices it holds are chosen once (tool_vertices in tool_placement.h).
struct Tool {
  ToolKind kind = ToolKind::Grasp;
  std::string key = "tools[0]";  ///< where the scenario states it: named in every error about it
  /// Grasp: the grasped surface point (m); Sphere: its centre at the first frame
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  double radius = 0;  ///< Grasp: vertices within this distance of `point` (m); Sphere: its radius (m)
  SupportBox box;                                   ///< Plate: vertices whose rest position is in the box
  int normal_axis = 2;                              ///< SlidingPlate: 0, 1, 2 for x, y, z
  double pad_stiffness = 0;  ///< CompliantGrasp: the pads' traction per unit of relative displacement, Pa/m
  /// CompliantGrasp: the pads' stiffness across the disc: uniform (pad_stiffness
  /// everywhere: the traction jumps to zero at the rim) or smooth (pad_stiffness
  /// (1 - (r / radius)^2)^2 at distance r from the point: it falls to zero at the rim
  /// with zero slope, so the traction is continuous there).
  bool smooth_pads = false;

  static Tool grasp(const Eigen::Vector3d& point, double radius, std::string key = "tools[0]");
  static Tool plate(const SupportBox& box, bool sliding, int normal_axis = 2, std::string key = "tools[0]");
  static Tool sphere(const Eigen::Vector3d& first_centre, double radius, std::string key = "tools[0]");
  static Tool compliant_grasp(const Eigen::Vector3d& point, double radius, double pad_stiffness,
                              std::string key = "tools[0]", bool smooth_pads = false);
  /// Grasp and CompliantGrasp: the tools that hold the vertices within a radius of a point.
  bool holds_a_disc() const { return kind == ToolKind::Grasp || kind == ToolKind::CompliantGrasp; }
};

/// A sphere starting inside the body by more than this fraction of its radius is an
/// error (tool_vertices): a touching start is allowed up to rounding and meshing.
inline constexpr double kSphereStartTolerance = 1e-3;

/// Everything a run holds fixed about the boundary-value problem.
struct LoadCase {
  SupportBox support;
  std::vector<Load> loads;
  std::vector<Tool> tools;
};

/// One frame's value of every load and tool of the LoadCase, in its order: a force
/// (N) for PointForce and SurfaceTraction, an acceleration (m/s^2) for BodyForce;
/// a displacement (m) for every tool but a sphere, whose value is its centre (m).
struct FrameLoads {
  std::vector<Eigen::Vector3d> values;
  std::vector<Eigen::Vector3d> tool_values;
};

/// `values` for a LoadCase of one load (tests, benchmarks).
inline FrameLoads frame_of(const Eigen::Vector3d& value) { return FrameLoads{{value}, {}}; }

}  // namespace tb
