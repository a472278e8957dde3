#include "tool_placement.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "point_location.h"

namespace tb {
namespace {

std::string point_text(const Eigen::Vector3d& p) {
  std::ostringstream os;
  os << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return os.str();
}

[[noreturn]] void fail(const Tool& tool, const std::string& problem) {
  throw std::invalid_argument(tool.key + " (" + name(tool.kind) + "): " + problem);
}

bool prescribes(const Tool& tool, int component) {
  return tool.kind != ToolKind::SlidingPlate || component == tool.normal_axis;
}

PrescribedGroup group_of(const Tool& tool, std::vector<int> nodes) {
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  PrescribedGroup g;
  g.nodes = std::move(nodes);
  for (int c = 0; c < 3; ++c) g.components[c] = prescribes(tool, c);
  return g;
}

}  // namespace

namespace {

void check_sphere(const Tool& tool, const SurfaceMesh& surface) {
  if (!(std::isfinite(tool.radius) && tool.radius > 0))
    fail(tool, "radius " + std::to_string(tool.radius) + " is not a positive length (m)");
  if (!tool.point.allFinite()) fail(tool, "its centre " + point_text(tool.point) + " is not finite");
  double deepest = 0;
  Eigen::Index at = -1;
  for (Eigen::Index v = 0; v < surface.V.rows(); ++v) {
    const double depth = tool.radius - (surface.V.row(v).transpose() - tool.point).norm();
    if (depth > deepest) {
      deepest = depth;
      at = v;
    }
  }
  std::ostringstream msg;
  if (deepest > kSphereStartTolerance * tool.radius) {
    msg << "at its first centre " << point_text(tool.point) << " surface vertex " << at << " is " << deepest
        << " m inside it (tolerance " << kSphereStartTolerance << " x radius): start the sphere outside the body";
    fail(tool, msg.str());
  }
  if (surface.F.rows() > 0 && winding_number(surface, tool.point) >= 0.5) {
    msg << "its first centre " << point_text(tool.point) << " is inside the body: start the sphere outside it";
    fail(tool, msg.str());
  }
}

}  // namespace

std::vector<int> tool_vertices(const Tool& tool, const SurfaceMesh& surface, const SupportBox& support) {
  if (tool.kind == ToolKind::Sphere) {
    check_sphere(tool, surface);
    return {};
  }
  const Points& V = surface.V;
  std::vector<int> held;
  double nearest = std::numeric_limits<double>::infinity();
  if (tool.kind == ToolKind::SlidingPlate && (tool.normal_axis < 0 || tool.normal_axis > 2))
    fail(tool, "normal axis " + std::to_string(tool.normal_axis) + " is not 0, 1 or 2");
  if (tool.holds_a_disc() && !(std::isfinite(tool.radius) && tool.radius > 0))
    fail(tool, "radius " + std::to_string(tool.radius) + " is not a positive length (m)");
  if (tool.kind == ToolKind::CompliantGrasp && !(std::isfinite(tool.pad_stiffness) && tool.pad_stiffness > 0))
    fail(tool, "pad stiffness " + std::to_string(tool.pad_stiffness) + " is not a positive traction per metre (Pa/m)");
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    const Eigen::Vector3d x = V.row(v).transpose();
    const double d = tool.holds_a_disc() ? (x - tool.point).norm() : 0;
    nearest = std::min(nearest, d);
    if (tool.holds_a_disc() ? d <= tool.radius : tool.box.contains(x)) held.push_back(static_cast<int>(v));
  }
  if (held.empty()) {
    if (tool.holds_a_disc()) {
      std::ostringstream msg;
      msg << "a radius of " << tool.radius << " m around " << point_text(tool.point)
          << " catches no surface vertex (the nearest is " << nearest << " m away)";
      fail(tool, msg.str());
    }
    fail(tool, "its box " + point_text(tool.box.min) + " to " + point_text(tool.box.max) + " holds no surface vertex");
  }
  int supported = 0;
  for (int v : held) supported += support.contains(V.row(v).transpose());
  if (supported > 0)
    fail(tool, std::to_string(supported) + " of its " + std::to_string(held.size()) +
                   " surface vertices are in the support box: a vertex cannot be clamped and moved");
  return held;
}

PrescribedGroup fine_volume_group(const Tool& tool, const std::vector<int>& vertices,
                                  const std::vector<int>& surface_to_volume) {
  std::vector<int> nodes;
  for (int v : vertices) {
    if (v < 0 || static_cast<size_t>(v) >= surface_to_volume.size())
      fail(tool, "surface vertex " + std::to_string(v) + " has no node in the volume");
    nodes.push_back(surface_to_volume[static_cast<size_t>(v)]);
  }
  return group_of(tool, nodes);
}

PrescribedGroup coarse_volume_group(const Tool& tool, const std::vector<int>& vertices, const Points& V_surface,
                                    const TetMesh& coarse, const std::vector<char>& clamped) {
  std::vector<int> nodes;
  for (int v : vertices) {
    Eigen::Index nearest = 0;
    (coarse.V.rowwise() - V_surface.row(v)).rowwise().squaredNorm().minCoeff(&nearest);
    if (!clamped[static_cast<size_t>(nearest)]) nodes.push_back(static_cast<int>(nearest));
  }
  if (nodes.empty())
    fail(tool, "the coarse nodes nearest its " + std::to_string(vertices.size()) +
                   " surface vertices are all clamped by the support: the coarse mesh cannot hold it");
  return group_of(tool, nodes);
}

ContactArea::ContactArea(const SurfaceMesh& surface) : vertex_area_(Eigen::VectorXd::Zero(surface.V.rows())) {
  for (Eigen::Index t = 0; t < surface.F.rows(); ++t) {
    const Eigen::Vector3d a = surface.V.row(surface.F(t, 0)), b = surface.V.row(surface.F(t, 1)),
                          c = surface.V.row(surface.F(t, 2));
    const double third = (b - a).cross(c - a).norm() / 6;
    for (int k = 0; k < 3; ++k) vertex_area_(surface.F(t, k)) += third;
  }
}

double ContactArea::area(const std::vector<int>& vertices) const {
  double sum = 0;
  for (int v : vertices) sum += vertex_area_(v);
  return sum;
}

std::vector<NodeSpring> pad_springs(const Tool& tool, const std::vector<int>& vertices, const SurfaceMesh& surface,
                                    const std::vector<int>& surface_to_volume) {
  if (tool.kind != ToolKind::CompliantGrasp) fail(tool, "only a compliant grasp has pads");
  const ContactArea area(surface);
  std::vector<NodeSpring> springs;
  for (int v : vertices) {
    if (v < 0 || static_cast<size_t>(v) >= surface_to_volume.size())
      fail(tool, "surface vertex " + std::to_string(v) + " has no node in the volume");
    double profile = 1;
    if (tool.smooth_pads) {
      const double r2 = (surface.V.row(v).transpose() - tool.point).squaredNorm() / (tool.radius * tool.radius);
      profile = (1 - r2) * (1 - r2);
      if (!(r2 < 1)) continue;  // on the rim: no hold
    }
    springs.push_back({surface_to_volume[static_cast<size_t>(v)], tool.pad_stiffness * profile * area.area({v})});
  }
  if (springs.empty()) fail(tool, "its smooth pads hold no vertex strictly inside its radius");
  return springs;
}

std::vector<TetEmbedding> place_probes(const Points& probes, const TetMesh& volume, const std::string& mesh_name,
                                       bool nearest) {
  std::vector<TetEmbedding> out;
  for (Eigen::Index p = 0; p < probes.rows(); ++p) {
    const TetEmbedding e = locate_point(volume, probes.row(p).transpose(), 1e-6);
    if (!nearest && (e.tet < 0 || e.distance > 0)) {
      std::ostringstream msg;
      msg << "probes[" << p << "] " << point_text(probes.row(p).transpose()) << " is outside the " << mesh_name
          << " (distance " << e.distance << " m)";
      throw std::invalid_argument(msg.str());
    }
    out.push_back(e);
  }
  return out;
}

void interpolate_probes(const std::vector<TetEmbedding>& probes, const Tetrahedra& T, const Eigen::VectorXd& u,
                        Points& out) {
  if (out.rows() != static_cast<Eigen::Index>(probes.size())) out.resize(static_cast<Eigen::Index>(probes.size()), 3);
  for (size_t p = 0; p < probes.size(); ++p) {
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    for (int k = 0; k < 4; ++k) x += probes[p].weights(k) * u.segment<3>(3 * T(probes[p].tet, k));
    out.row(static_cast<Eigen::Index>(p)) = x.transpose();
  }
}

}  // namespace tb
