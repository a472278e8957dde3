// The fine linear FEM reduced to its surface by precomputation:
// Bro-Nielsen and Cotin 1996 (condensation), Cotin, Delingette and Ayache 1999
// (precomputed elementary responses). The same solution as "fem" with the direct
// solver, for a frame cost of a weighted sum of columns.
#pragma once

#include "model.h"

namespace tb {
/// Registry entry for "condensed".
ModelInfo condensed_model_info();
}  // namespace tb
