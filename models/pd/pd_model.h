// Projective Dynamics on the fine tet volume (numerics/realtime/pd_solve.h): a
// dynamic nonlinear model, one implicit-Euler step a frame by Bouaziz et al.'s
// local/global iterations (2014) or L-BFGS on any law (Liu, Bouaziz and Kavan 2017),
// the global matrix factorised once.
#pragma once

#include "model.h"

namespace tb {

/// Registry entry for "pd".
ModelInfo pd_model_info();

}  // namespace tb
