// The kinds of PBD constraint on a surface, listed once (constraint_kinds.cc), in
// the order every sweep projects them (paper 1.4: all stretch constraints, then
// all bending constraints), and the constraint set built from them.
#pragma once

#include "constraint_kind.h"
#include "mesh_types.h"

namespace tb::pbd {

/// stretch, bending: the kinds the pbd and hybrid models run, in sweep order.
const KindTable& surface_constraint_kinds();

/// The table's kinds checked: names [a-z_]+ and unique, arity and rest values
/// non-negative and arity at least 1. Throws std::invalid_argument naming the kind.
void check_kinds(const KindTable& kinds);

/// The constraints of a closed manifold surface at its rest shape, kind by kind in
/// the table's order (each kind's build).
ConstraintSet build_constraints(const SurfaceMesh& surface, const KindTable& kinds = surface_constraint_kinds());

}  // namespace tb::pbd
