#include "sphere_guard.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "point_location.h"

namespace tb {

SphereAgainstSurface sphere_against_surface(const Points& V, const Triangles& F, const Eigen::Vector3d& centre,
                                            double radius) {
  double solid_angle = 0;
  double nearest = std::numeric_limits<double>::infinity();
  for (Eigen::Index t = 0; t < F.rows(); ++t) {
    const Eigen::Vector3d a = V.row(F(t, 0)), b = V.row(F(t, 1)), c = V.row(F(t, 2));
    solid_angle += triangle_solid_angle(a, b, c, centre);
    nearest = std::min(nearest, point_triangle_distance(centre, a, b, c));
  }
  SphereAgainstSurface out;
  out.winding_number = solid_angle / (4 * M_PI);
  out.distance = nearest;
  out.face_penetration = std::max(0.0, radius - nearest);
  return out;
}

bool segment_meets_surface(const Points& V, const Triangles& F, const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
  for (Eigen::Index t = 0; t < F.rows(); ++t)
    if (segment_meets_triangle(p, q, V.row(F(t, 0)), V.row(F(t, 1)), V.row(F(t, 2)))) return true;
  return false;
}

namespace {

std::string point_text(const Eigen::Vector3d& p) {
  std::ostringstream os;
  os << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return os.str();
}

}  // namespace

SphereGuard::SphereGuard(const std::vector<Tool>& tools, const SurfaceMesh& surface) : rest_(surface) {
  for (size_t k = 0; k < tools.size(); ++k)
    if (tools[k].kind == ToolKind::Sphere) {
      Sphere s;
      s.tool = k;
      s.key = tools[k].key;
      s.radius = tools[k].radius;
      s.previous_centre = tools[k].point;
      // Outside the rest surface (tool_vertices checks it), at an unknown distance:
      // the first frame's swept test is pruned by this frame's distance alone.
      s.previous_distance = 0;
      spheres_.push_back(s);
    }
}

void SphereGuard::check(int frame, const Points& u, const std::vector<Eigen::Vector3d>& tool_values) {
  if (spheres_.empty()) return;
  if (frame == 0) previous_ = rest_.V;
  deformed_ = rest_.V + u;  // the same size every frame: allocated once
  for (Sphere& s : spheres_) {
    const Eigen::Vector3d& centre = tool_values.at(s.tool);
    const SphereAgainstSurface a = sphere_against_surface(deformed_, rest_.F, centre, s.radius);
    const double moved = (centre - s.previous_centre).norm();
    s.largest_move = std::max(s.largest_move, moved);
    // What to do. A long move passes the nodes whatever the model: ramp it. A centre
    // below the undeformed surface after a short move is a depth the model does not
    // hold: one that places the surface from the rest state each frame pushes the nodes
    // above the centre up around it however slowly it came (fem's linear solves, the
    // hybrid), and a sphere small against the node spacing slips between the nodes
    // (pbd on a coarse surface): press it less deep or refine the surface
    // (docs/equations.md, "The runner's tunnelling guard").
    auto stop = [&](const std::string& what) {
      std::ostringstream msg;
      msg << s.key << " (sphere) " << what << "; it moved " << moved
          << " m since the previous frame against its radius " << s.radius << " m";
      const SphereAgainstSurface at_rest = sphere_against_surface(rest_.V, rest_.F, centre, s.radius);
      const bool below_rest = at_rest.winding_number >= kInsideWindingNumber;
      if (below_rest) msg << ", its centre " << at_rest.distance << " m below the undeformed surface";
      if (moved >= kLongMoveFraction * s.radius || !below_rest)
        msg << ": ramp it over more frames (a move a frame well below its radius)";
      else
        msg << ": press it less deep or refine the surface where it presses (the nodes hold it, not the faces; a "
               "model that places the surface from the rest state each frame, fem's linear solves or the hybrid, "
               "cannot hold a centre below the undeformed surface)";
      throw std::runtime_error(msg.str());
    };
    // The nodes are held out of the sphere, never its centre: a centre inside the
    // body means the surface nodes were passed, not pressed.
    if (a.winding_number >= kInsideWindingNumber) {
      std::ostringstream what;
      what << "tunnelled through the surface at frame " << frame << ": its centre " << point_text(centre)
           << " is inside the deformed body (winding number " << a.winding_number
           << "), the surface nodes left on its far side";
      stop(what.str());
    }
    // Both ends outside, the path between them through the body: before the frame
    // the body lay across it, and after it the body still does (a press that pushes
    // the body ahead of the sphere clears the path by the frame's end; a release that
    // lets it spring back never entered it before). Every point of the segment is
    // within `moved` of either end, so a shorter move cannot reach either surface.
    if (moved > a.distance && moved > s.previous_distance &&
        segment_meets_surface(previous_, rest_.F, s.previous_centre, centre) &&
        segment_meets_surface(deformed_, rest_.F, s.previous_centre, centre)) {
      std::ostringstream what;
      what << "passed through the body within frame " << frame << ": the path of its centre from "
           << point_text(s.previous_centre) << " to " << point_text(centre)
           << " crosses the deformed surface before and after the frame, though it ends outside";
      stop(what.str());
    }
    if (a.face_penetration > s.max_face_penetration) {
      s.max_face_penetration = a.face_penetration;
      s.max_frame = frame;
    }
    s.previous_centre = centre;
    s.previous_distance = a.distance;
  }
  previous_.swap(deformed_);  // no copy: the next frame refills the other buffer
}

nlohmann::json SphereGuard::to_json() const {
  nlohmann::json j;
  j["how"] =
      "per sphere, the deepest reach of the deformed surface's triangles into it over the frames: radius minus the "
      "distance from its centre to the nearest point of any surface triangle (Ericson 2005, 5.1.5), when positive; "
      "the models hold the surface nodes out of the sphere, so this is how far faces sag into it between them. "
      "frame: the first frame of that maximum (-1: no face reached inside). largest_move_per_frame_m: the "
      "largest move of the centre between two frames. A case stops when a sphere's centre ends a frame inside the "
      "deformed body or its path over a frame crosses the body (docs/equations.md)";
  for (const Sphere& s : spheres_)
    j["tools"][s.key] = {{"max_face_penetration_m", s.max_face_penetration},
                         {"frame", s.max_frame},
                         {"largest_move_per_frame_m", s.largest_move}};
  return j;
}

}  // namespace tb
