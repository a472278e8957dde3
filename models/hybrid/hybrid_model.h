// The hybrid model (paper 1.5): linear FEM on the coarse tets places the control
// points of the fine surface (eq. 33); PBD moves the other surface vertices.
#pragma once

#include "model.h"

namespace tb {
/// Registry entry for "hybrid".
ModelInfo hybrid_model_info();
}  // namespace tb
