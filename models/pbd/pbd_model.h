// Pure PBD on the fine surface (paper 1.4): stretch and bending constraints only.
#pragma once

#include "model.h"

namespace tb {
/// Registry entry for "pbd".
ModelInfo pbd_model_info();
}  // namespace tb
