// Every fine-surface vertex follows the coarse linear FEM through its barycentric
// weights, with no PBD (SOFA's barycentric mapping, the field's usual way to drive
// a fine surface from a coarse FEM). The baseline that shows what the hybrid's PBD
// adds.
#pragma once

#include "model.h"

namespace tb {
/// Registry entry for "embedded".
ModelInfo embedded_model_info();
}  // namespace tb
