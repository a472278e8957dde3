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
  out.face_penetration = std::max(0.0, radius - nearest);
  return out;
}

SphereGuard::SphereGuard(const std::vector<Tool>& tools, const SurfaceMesh& surface) : rest_(surface) {
  for (size_t k = 0; k < tools.size(); ++k)
    if (tools[k].kind == ToolKind::Sphere) {
      Sphere s;
      s.tool = k;
      s.key = tools[k].key;
      s.radius = tools[k].radius;
      s.previous_centre = tools[k].point;
      spheres_.push_back(s);
    }
}

void SphereGuard::check(int frame, const Points& u, const std::vector<Eigen::Vector3d>& tool_values) {
  if (spheres_.empty()) return;
  deformed_ = rest_.V + u;  // the same size every frame: allocated once
  for (Sphere& s : spheres_) {
    const Eigen::Vector3d& centre = tool_values.at(s.tool);
    const SphereAgainstSurface a = sphere_against_surface(deformed_, rest_.F, centre, s.radius);
    const double moved = (centre - s.previous_centre).norm();
    s.largest_move = std::max(s.largest_move, moved);
    if (a.winding_number >= kInsideWindingNumber) {
      // The nodes are held out of the sphere, never its centre: a centre inside the
      // body means the surface nodes were passed, not pressed.
      std::ostringstream msg;
      msg << s.key << " (sphere) tunnelled through the surface at frame " << frame << ": its centre (" << centre.x()
          << ", " << centre.y() << ", " << centre.z() << ") is inside the deformed body (winding number "
          << a.winding_number << "), the surface nodes left on its far side; it moved " << moved
          << " m since the previous frame against its radius " << s.radius
          << " m: ramp it over more frames (a move a frame well below its radius)";
      throw std::runtime_error(msg.str());
    }
    if (a.face_penetration > s.max_face_penetration) {
      s.max_face_penetration = a.face_penetration;
      s.max_frame = frame;
    }
    s.previous_centre = centre;
  }
}

nlohmann::json SphereGuard::to_json() const {
  nlohmann::json j;
  j["how"] =
      "per sphere, the deepest reach of the deformed surface's triangles into it over the frames: radius minus the "
      "distance from its centre to the nearest point of any surface triangle (Ericson 2005, 5.1.5), when positive; "
      "the models hold the surface nodes out of the sphere, so this is how far faces sag into it between them. "
      "frame: the first frame of that maximum (-1: no face reached inside). largest_move_per_frame_m: the "
      "largest move of the centre between two frames; the guard stops a case whose sphere's centre ends a frame "
      "inside the deformed body, and cannot see a sphere that passes through a part thinner than about that move "
      "less its radius and leaves it within one frame (docs/equations.md)";
  for (const Sphere& s : spheres_)
    j["tools"][s.key] = {{"max_face_penetration_m", s.max_face_penetration},
                         {"frame", s.max_frame},
                         {"largest_move_per_frame_m", s.largest_move}};
  return j;
}

}  // namespace tb
