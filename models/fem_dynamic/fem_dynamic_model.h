// The dynamic reference: the fine-volume FEM with a nonlinear material law
// integrated in time by implicit (backward) Euler with the lumped mass, one step
// of `time_step` a frame, so that a dynamic model's transient (not only its steady
// state) has a reference taken with its own step (docs/equations.md, "The dynamic
// reference").
#pragma once

#include "model.h"

namespace tb {

/// Registry entry for "fem_dynamic": parameters material_law, time_step, newton_tolerance.
ModelInfo fem_dynamic_model_info();

}  // namespace tb
