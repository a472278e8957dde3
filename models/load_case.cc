// The load kinds' names and the Load constructors (load_case.h); the support box is
// in support.cc.
#include "load_case.h"

namespace tb {

const char* name(LoadKind kind) {
  switch (kind) {
    case LoadKind::PointForce:
      return "point_force";
    case LoadKind::SurfaceTraction:
      return "surface_traction";
    case LoadKind::BodyForce:
      return "body_force";
  }
  return "unknown";
}

Load Load::point_force(const Eigen::Vector3d& point, std::string key) {
  return Load{LoadKind::PointForce, std::move(key), point, 0};
}

Load Load::surface_traction(const Eigen::Vector3d& centre, double radius, std::string key) {
  return Load{LoadKind::SurfaceTraction, std::move(key), centre, radius};
}

Load Load::body_force(std::string key) { return Load{LoadKind::BodyForce, std::move(key), Eigen::Vector3d::Zero(), 0}; }

const char* name(ToolKind kind) {
  switch (kind) {
    case ToolKind::Grasp:
      return "grasp";
    case ToolKind::BondedPlate:
      return "bonded_plate";
    case ToolKind::SlidingPlate:
      return "sliding_plate";
    case ToolKind::Sphere:
      return "sphere";
    case ToolKind::CompliantGrasp:
      return "compliant_grasp";
  }
  return "unknown";
}

Tool Tool::grasp(const Eigen::Vector3d& point, double radius, std::string key) {
  Tool t;
  t.kind = ToolKind::Grasp;
  t.key = std::move(key);
  t.point = point;
  t.radius = radius;
  return t;
}

Tool Tool::plate(const SupportBox& box, bool sliding, int normal_axis, std::string key) {
  Tool t;
  t.kind = sliding ? ToolKind::SlidingPlate : ToolKind::BondedPlate;
  t.key = std::move(key);
  t.box = box;
  t.normal_axis = normal_axis;
  return t;
}

Tool Tool::sphere(const Eigen::Vector3d& first_centre, double radius, std::string key) {
  Tool t;
  t.kind = ToolKind::Sphere;
  t.key = std::move(key);
  t.point = first_centre;
  t.radius = radius;
  return t;
}

Tool Tool::compliant_grasp(const Eigen::Vector3d& point, double radius, double pad_stiffness, std::string key,
                           bool smooth_pads) {
  Tool t = grasp(point, radius, std::move(key));
  t.kind = ToolKind::CompliantGrasp;
  t.pad_stiffness = pad_stiffness;
  t.smooth_pads = smooth_pads;
  return t;
}

}  // namespace tb
