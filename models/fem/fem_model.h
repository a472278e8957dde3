// The fine-mesh FEM reference (paper 1.3): a static elastic solve on the fine tet
// volume each frame. Serial P1 linear (direct or iterative), or distributed over
// MPI ranks with P1/P2 elements, linear or neo-Hookean, point or disc loads
// (distributed_elasticity.h).
#pragma once

#include "model.h"

namespace tb {

/// Registry entry for "fem": parameters `solver` (direct | iterative |
/// distributed), `preconditioner`, `cg_tolerance`, `degree`, `material_law`,
/// `load_steps`.
ModelInfo fem_model_info();

}  // namespace tb
