// Volumetric XPBD with neo-Hookean tet constraints on the fine tet volume
// (numerics/realtime/xpbd_tet_solve.h): a dynamic nonlinear model, `substeps`
// sub-steps of coloured constraint sweeps a frame.
#pragma once

#include "model.h"

namespace tb {

/// Registry entry for "xpbd_neo".
ModelInfo xpbd_neo_model_info();

}  // namespace tb
