// The FEM on the scenario's fine tet volume (paper 1.3), with the solve strategy its
// model chooses: the fem model (linear, corotational or Newton static solves, one
// per frame) and the fem_dynamic model (implicit Euler). Tools hold the
// fine-volume nodes of the surface vertices they hold as Dirichlet values; loads
// are consistent nodal forces (eq. 10); reactions and probes from the nodal field.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "elastic_body.h"
#include "elastic_solve.h"
#include "elastic_solve_factory.h"
#include "model.h"

namespace tb {

/// A model solving the fine volume with `make_solve`'s strategy each frame; its
/// errors begin with `model_name`.
std::unique_ptr<Model> make_fine_fem(const std::string& model_name, ElasticSolveFactory make_solve);

/// Throws std::invalid_argument, "fem: tools[0] (sphere): the corotational solver has
/// no contact; use solver direct, iterative or newton", when the elastic solve the
/// resolved parameters choose (names with `prefix`) cannot hold a tool of
/// `load_case` (ElasticSolveInfo::refuses_spheres, refuses_springs).
void check_elastic_solve_takes_tools(const std::string& model_name, const Parameters& p, const std::string& prefix,
                                     const LoadCase& load_case);

/// What the fine-volume FEM takes and measures (ModelInfo's loads, tools,
/// tools_how, reactions, probes), for the models built on it.
void describe_fine_fem(ModelInfo& info);

}  // namespace tb
