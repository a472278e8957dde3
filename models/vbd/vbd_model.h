// Vertex Block Descent on the fine tet volume (numerics/realtime/vbd_solve.h): a
// dynamic nonlinear model, one implicit-Euler step of `iterations` coloured
// per-vertex Newton sweeps a frame.
#pragma once

#include "model.h"

namespace tb {

/// Registry entry for "vbd".
ModelInfo vbd_model_info();

}  // namespace tb
