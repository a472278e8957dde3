// A model on the coarse tet volume with the fine surface embedded in it (SOFA's
// barycentric mapping): the coarse FEM (coarse_fem.h: support, loads, tools,
// reactions, probes on the coarse mesh) advanced each frame by a solve, and every
// fine-surface vertex moved by its barycentric weights in the coarse tet nearest it
// (coarse_embedding.h). The embedded model (the coarse_solver strategies) and the
// real-time nonlinear models on `volume coarse_embedded` (their steppers on the
// coarse mesh) are this one model with a different solve.
#pragma once

#include <memory>
#include <string>

#include "coarse_fem.h"
#include "model.h"

namespace tb {

/// A model whose coarse FEM is solved by `make_solve` (empty: the coarse_solver
/// parameters' strategy); its errors begin with `model_name`.
std::unique_ptr<Model> make_coarse_embedded(const std::string& model_name, ElasticSolveFactory make_solve = {});

}  // namespace tb
