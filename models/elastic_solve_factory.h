// The solve a FEM-based model makes for one of its bodies (the fine volume, or the
// coarse one under an embedding), chosen from the scenario: the one signature the
// fine-volume, coarse and coarse-embedded models take.
#pragma once

#include <functional>
#include <memory>

#include "elastic_body.h"
#include "elastic_solve.h"
#include "model.h"

namespace tb {

/// Makes the solve for `body` (which outlives the solve) from the scenario's problem.
using ElasticSolveFactory = std::function<std::unique_ptr<ElasticSolve>(const ElasticBody&, const Problem&)>;

}  // namespace tb
