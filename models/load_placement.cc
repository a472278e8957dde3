#include "load_placement.h"

#include <stdexcept>

#include "point_location.h"
#include "surface_load.h"

namespace tb {
namespace {

/// `place()`, its std::invalid_argument prefixed by the load's scenario key.
template <class Place>
NodalWeights keyed(const Load& load, Place&& place) {
  try {
    return place();
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(load.key + " (" + name(load.kind) + "): " + e.what());
  }
}

NodalWeights point_on_volume(const Eigen::Vector3d& x, const VolumePlacement& w) {
  switch (w.points) {
    case PointInVolume::Containing:
      return containing_tet(*w.volume, x, w.name);
    case PointInVolume::Nearest:
      return nearest_tet(*w.volume, x);
    case PointInVolume::NearestNode:
      return nearest_vertex(w.volume->V, x);
  }
  throw std::logic_error("point_on_volume: unknown rule");
}

}  // namespace

std::vector<NodalWeights> place_on_volume(const std::vector<Load>& loads, const VolumePlacement& w) {
  std::vector<NodalWeights> out;
  for (const Load& load : loads)
    out.push_back(keyed(load, [&]() -> NodalWeights {
      switch (load.kind) {
        case LoadKind::PointForce:
          return point_on_volume(load.point, w);
        case LoadKind::SurfaceTraction: {
          if (!w.surface) throw std::invalid_argument("a traction needs the fine surface");
          if (w.surface_to_volume)  // the volume's own boundary: each point in the tet owning its triangle
            return nodal_weights_p1(*w.volume,
                                    disc_load_points(*w.volume, *w.surface, *w.surface_to_volume, load.point, load.radius));
          // Another volume (a coarse mesh): each point of the surface's disc where point forces go.
          std::vector<NodalWeights> parts;
          std::vector<double> scale;
          for (const SurfaceLoadPoint& p : disc_surface_points(*w.surface, load.point, load.radius)) {
            parts.push_back(point_on_volume(p.position, w));
            scale.push_back(p.weight);
          }
          return combine(parts, scale);
        }
        case LoadKind::BodyForce:
          if (!(w.density > 0)) throw std::invalid_argument("a body force needs a positive density");
          return nodal_masses(*w.volume, w.density);
      }
      throw std::logic_error("place_on_volume: unknown load kind");
    }));
  return out;
}

std::vector<NodalWeights> place_on_surface(const std::vector<Load>& loads, const SurfaceMesh& surface,
                                           bool spread_on_triangles, const Eigen::VectorXd& masses) {
  std::vector<NodalWeights> out;
  for (const Load& load : loads)
    out.push_back(keyed(load, [&]() -> NodalWeights {
      switch (load.kind) {
        case LoadKind::PointForce:
          return spread_on_triangles ? nearest_surface_point(surface, load.point)
                                     : nearest_vertex(surface.V, load.point);
        case LoadKind::SurfaceTraction:
          return surface_nodal_weights(surface, disc_surface_points(surface, load.point, load.radius));
        case LoadKind::BodyForce: {
          if (masses.size() != surface.V.rows()) throw std::invalid_argument("a body force needs the vertex masses");
          NodalWeights m;
          m.nodes = Eigen::VectorXi::LinSpaced(surface.V.rows(), 0, static_cast<int>(surface.V.rows()) - 1);
          m.weights = masses;
          return m;
        }
      }
      throw std::logic_error("place_on_surface: unknown load kind");
    }));
  return out;
}

}  // namespace tb
