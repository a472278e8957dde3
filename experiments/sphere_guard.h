// The runner's per-frame guard on rigid sphere tools, the same for every model.
//
// Every model enforces a sphere on the surface NODES only (fem: an active set on the
// factor, sphere_contact.h; Newton, vbd, xpbd_neo, pd: sphere_obstacles.h; pbd and
// the hybrid: a collision projection, surface_spheres.h). A sphere moved deep in one
// frame can pass the nodes, which then sit on its far side: every solver converges
// with no contact and the result looks valid. After each frame, on the deformed
// surface (rest + u, the triangles the model answers with):
//  - the generalized winding number at the sphere's centre (Jacobson, Kavan and
//    Sorkine-Hornung 2013: the triangles' signed solid angles, Van Oosterom and
//    Strackee 1983, summed / 4 pi): >= 1/2 is inside the closed surface, and a centre
//    inside the body is a sphere that has tunnelled (a pressing sphere keeps its
//    centre about its radius outside): the case stops with a one-line error;
//  - a sphere that crossed the body within the frame and ended outside it: the path
//    of its centre over the frame (a segment: the scenario's path is piecewise
//    linear over the frames) meets the deformed surface of the frame before and of
//    this frame; tested only when the move is longer than the centre's distance to
//    both surfaces (shorter, it cannot reach them), so a ramped run never pays for it;
//  - the deepest penetration of the surface TRIANGLES, r - min over triangles of the
//    distance from the centre (Ericson 2005, 5.1.5), when positive: how far faces
//    sag into the sphere between the nodes the models hold out of it.
// docs/equations.md, "Contact with a rigid sphere", "The runner's tunnelling guard".
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "load_case.h"
#include "mesh_types.h"

namespace tb {

/// A sphere against a closed surface.
struct SphereAgainstSurface {
  double winding_number = 0;    ///< at the centre: ~1 inside the surface, ~0 outside
  double distance = 0;          ///< m: from the centre to the nearest point of any triangle
  double face_penetration = 0;  ///< m: radius - distance, or 0
};

/// One pass over the triangles: the winding number at `centre`, its distance to the
/// surface and how deep the triangles reach into the sphere (centre, radius). No
/// allocation.
///   V  #V by 3 positions, F  #F by 3 outward-oriented (counter-clockwise seen from
///   outside) triangles of a closed surface
SphereAgainstSurface sphere_against_surface(const Points& V, const Triangles& F, const Eigen::Vector3d& centre,
                                            double radius);

/// Whether the segment from p to q meets any triangle of (V, F) (segment_meets_triangle).
///   V  #V by 3, F  #F by 3
bool segment_meets_surface(const Points& V, const Triangles& F, const Eigen::Vector3d& p, const Eigen::Vector3d& q);

/// Centres whose winding number reaches this are inside the body (Jacobson et al.
/// 2013: the winding number of a closed surface is 1 inside and 0 outside, 1/2 on it).
inline constexpr double kInsideWindingNumber = 0.5;

/// A move of the centre between two frames of at least this fraction of the radius
/// can pass the surface nodes (a pressing sphere's centre is about its radius from
/// them, less the faces' sag: up to 0.56 of it measured on the palpation); the
/// error's advice then is to ramp the sphere over more frames.
inline constexpr double kLongMoveFraction = 0.5;

/// The runner's guard over a case's frames: checks each sphere of `tools` after each
/// frame and keeps, per sphere, its deepest face penetration and the frame of it.
/// Does nothing (and costs nothing) for a case without spheres.
class SphereGuard {
 public:
  ///   surface  the rest surface (the reference must outlive the guard)
  SphereGuard(const std::vector<Tool>& tools, const SurfaceMesh& surface);

  bool active() const { return !spheres_.empty(); }

  /// After frame `frame` (called for frames 0, 1, ... in order): the deformed
  /// surface rest + u and each tool's value (a sphere's centre,
  /// FrameLoads::tool_values). Throws std::runtime_error, one line naming the tool,
  /// the frame and the centre, when a sphere's centre is inside the deformed surface
  /// or its path over the frame crossed the body. Allocates only on the first call.
  ///   u  #V by 3 displacements of the surface vertices
  void check(int frame, const Points& u, const std::vector<Eigen::Vector3d>& tool_values);

  /// run.json's record: per sphere key its deepest face penetration (m), the frame
  /// of it and its largest move between two frames (m), and how they are measured.
  nlohmann::json to_json() const;

 private:
  struct Sphere {
    size_t tool = 0;  ///< index in the LoadCase's tools
    std::string key;
    double radius = 0;
    Eigen::Vector3d previous_centre = Eigen::Vector3d::Zero();
    double previous_distance = 0;  ///< m: of previous_centre to the previous surface
    double largest_move = 0;       ///< m: the largest move of the centre between two frames
    double max_face_penetration = 0;
    int max_frame = -1;  ///< the first frame of the deepest penetration (-1: no face ever inside)
  };
  const SurfaceMesh& rest_;
  Points deformed_;  ///< this frame's surface positions
  Points previous_;  ///< the frame before's (at frame 0: the rest surface)
  std::vector<Sphere> spheres_;
};

}  // namespace tb
