#include "vbd_model.h"

#include "realtime_volume.h"
#include "vbd_solve.h"

namespace tb {

ModelInfo vbd_model_info() {
  ModelInfo m;
  m.name = "vbd";
  m.description =
      "Vertex Block Descent (Chen et al. 2024) on the fine tet volume (or the coarse one with the fine surface "
      "embedded: volume): each frame one implicit-Euler step by coloured "
      "per-vertex 3x3 Newton sweeps on a nonlinear law (default neo_hookean)";
  m.dynamic = true;
  m.parameters = vbd_parameters();
  m.parameters.push_back(volume_parameter());
  m.create = [] {
    return make_on_volume("vbd", [](const ElasticBody& body, const Problem& p) {
      return make_vbd_solve(body, vbd_settings(p.parameters));
    });
  };
  describe_on_volume(
      m,
      "their held components are set to the tool's "
      "position each frame and never moved by the sweeps; a sliding plate holds the normal component only",
      "f - f_int(x) - m (x - x_n - h v_n) / h^2 at the held dofs, summed per tool and over the support (the "
      "implicit-Euler balance of the held nodes)",
      "the linearised gap as a constraint of each surface vertex's 3x3 Newton step (a projection in the metric of its "
      "block, not a penalty)",
      "each pad's spring k_i in its vertex's 3x3 Newton step beside m / h^2 (an exact quadratic term)");
  return m;
}

}  // namespace tb
