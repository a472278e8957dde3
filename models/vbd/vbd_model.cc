#include "vbd_model.h"

#include "fine_fem.h"
#include "vbd_solve.h"

namespace tb {

ModelInfo vbd_model_info() {
  ModelInfo m;
  m.name = "vbd";
  m.description =
      "Vertex Block Descent (Chen et al. 2024) on the fine tet volume: each frame one implicit-Euler step by coloured "
      "per-vertex 3x3 Newton sweeps on a nonlinear law (default neo_hookean)";
  m.dynamic = true;
  m.parameters = vbd_parameters();
  m.create = [] {
    return make_fine_fem("vbd", [](const ElasticBody& body, const Problem& p) {
      return make_vbd_solve(body, vbd_settings(p.parameters));
    });
  };
  describe_fine_fem(m);
  m.tools = {ToolKind::Grasp, ToolKind::BondedPlate, ToolKind::SlidingPlate, ToolKind::Sphere};
  m.tools_how = "the fine-volume nodes of the held surface vertices: their held components are set to the tool's "
                "position each frame and never moved by the sweeps; a sliding plate holds the normal component only; a "
                "sphere: the linearised gap as a constraint of each surface vertex's 3x3 Newton step (a projection in "
                "the metric of its block, not a penalty)";
  m.reactions = "f - f_int(x) - m (x - x_n - h v_n) / h^2 at the held dofs, summed per tool and over the support (the "
                "implicit-Euler balance of the held nodes); a sphere: the normal part of that balance at its contact "
                "nodes";
  return m;
}

}  // namespace tb
