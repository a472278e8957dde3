#include "xpbd_neo_model.h"

#include "realtime_volume.h"
#include "xpbd_tet_solve.h"

namespace tb {

ModelInfo xpbd_neo_model_info() {
  ModelInfo m;
  m.name = "xpbd_neo";
  m.description =
      "Volumetric XPBD (Macklin and Mueller 2021) on the fine tet volume (or the coarse one with the fine surface "
      "embedded: volume): per tet a deviatoric and a hydrostatic "
      "constraint whose energies are the xpbd_neo_hookean law, sub-stepped, tets coloured for parallel sweeps";
  m.dynamic = true;
  m.parameters = xpbd_tet_parameters();
  m.parameters.push_back(volume_parameter());
  m.create = [] {
    return make_on_volume("xpbd_neo", [](const ElasticBody& body, const Problem& p) {
      return make_xpbd_tet_solve(body, xpbd_tet_settings(p.parameters));
    });
  };
  describe_on_volume(
      m,
      "zero inverse mass in their held components, "
      "moved linearly to the tool's position over the frame's sub-steps; a sliding plate holds the normal "
      "component only",
      "f - f_int(x) - m (x - x_n - h v_n) / h^2 at the held dofs (f_int from the xpbd_neo_hookean law the "
      "constraints minimise), summed per tool and over the support",
      "a collision projection of the surface nodes inside it after each sweep (Mueller et al. 2007)");
  return m;
}

}  // namespace tb
