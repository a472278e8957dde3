// The fine FEM distributed over MPI ranks: the reference solve at 10^6
// dofs and beyond, on deal.II's parallel machinery (distributed_elasticity.h),
// with P1 or P2 elements, any material law of the table, the paper's point load or
// a uniform traction on a disc, and grasps and plates (tool_placement.h) held as
// Dirichlet values, with their reactions and interior probes. `mpirun -np N
// tissuebench run ...`; one rank without mpirun.
#pragma once

#include "model.h"

namespace tb {

/// Registry entry for "fem_distributed": parameters `degree`, `material_law`,
/// `load_steps`, `cg_tolerance`.
ModelInfo fem_distributed_model_info();

}  // namespace tb
