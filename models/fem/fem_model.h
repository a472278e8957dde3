// The fine-mesh FEM reference (paper 1.3): a static linear-elastic solve on the
// fine tet volume each frame.
#pragma once

#include "model.h"

namespace tb {

/// Registry entry for "fem": parameters `solver` (direct | iterative) and
/// `cg_tolerance`.
ModelInfo fem_model_info();

}  // namespace tb
