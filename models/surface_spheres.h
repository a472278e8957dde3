// The sphere tools of a PBD surface (the pbd and hybrid models): which tools are
// spheres, their centres moved on the solver each frame (a collision constraint per
// vertex near each, pbd_solver.h), and what a frame measures on each (its force, the
// vertices in contact, their area, the deepest penetration).
#pragma once

#include <memory>
#include <vector>

#include "model.h"
#include "pbd_solver.h"
#include "tool_placement.h"

namespace tb {

class SurfaceSpheres {
 public:
  /// Finds the spheres among `tools` and sets them on `solver` at their starting centres.
  void setup(const std::vector<Tool>& tools, pbd::Solver& solver, const SurfaceMesh& surface);
  bool empty() const { return tools_.empty(); }
  /// Before a step: each sphere at this frame's centre (its tool value). Allocates nothing.
  void move(const FrameLoads& loads, pbd::Solver& solver);
  /// After a step: each sphere's force into `reactions` and its contact into `contacts`
  /// (both indexed by tool).
  void measure(const pbd::Solver& solver, std::vector<Eigen::Vector3d>& reactions,
               std::vector<ToolContact>& contacts) const;

 private:
  std::vector<size_t> tools_;  // the tools that are spheres
  Points centres_;
  Eigen::VectorXd radii_;
  std::unique_ptr<ContactArea> area_;
};

}  // namespace tb
