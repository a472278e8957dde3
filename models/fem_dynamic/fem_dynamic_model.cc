#include "fem_dynamic_model.h"

#include "elastic_solve.h"
#include "fine_fem.h"
#include "material_laws.h"

namespace tb {

ModelInfo fem_dynamic_model_info() {
  std::vector<std::string> laws;
  for (const MaterialLawInfo& l : material_laws()) laws.push_back(l.name);
  ModelInfo m;
  m.name = "fem_dynamic";
  m.description =
      "Nonlinear FEM on the fine tet volume integrated in time by implicit Euler (lumped mass, Newton each step): "
      "the reference for a dynamic model's transient, with the model's own time step";
  m.dynamic = true;
  m.parameters = {
      ParameterSpec::choice("material_law", laws, "neo_hookean",
                            "the material law (numerics/materials), with the Lame parameters of the scenario's E and nu"),
      ParameterSpec::number("time_step", 0.01, 1e-6, 1, "time step per frame, s (the compared model's)"),
      ParameterSpec::number("newton_tolerance", 1e-10, 1e-15, 1e-3,
                            "converged when |R| <= this times the norm of the forces in play, or a Newton step moves u "
                            "by at most this times |u|")};
  m.create = [] {
    return make_fine_fem("fem_dynamic", [](const ElasticBody& body, const Problem& p) {
      return make_implicit_euler_solve(body, p.parameters.choice("material_law"),
                                       p.parameters.number("newton_tolerance"), p.parameters.number("time_step"));
    });
  };
  describe_fine_fem(m);
  m.tools_how = "the fine-volume nodes of the held surface vertices, as Dirichlet values moved with each step; a "
                "sliding plate holds the normal component only; a sphere: a primal-dual active set on the linearised "
                "gaps inside each step's Newton iteration (the static Newton solve's, on the incremental potential)";
  m.reactions =
      "f - f_int(u) - M (u - u_n - h v_n) / h^2 at the held dofs, summed per tool and over the support (the tool also "
      "accelerates the mass it holds); a sphere: minus the sum of its contact multipliers lambda_i n_i";
  return m;
}

}  // namespace tb
