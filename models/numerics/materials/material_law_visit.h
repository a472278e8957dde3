// A law of the table chosen by name at run time, used as its struct at compile
// time: a solver whose inner loop evaluates the law per element or per vertex
// (numerics/realtime) is instantiated once per law, so the law's stress and
// node stiffness inline there, where the table's function pointers would not.
#pragma once

#include <stdexcept>
#include <string>

#include "arap_volume.h"
#include "lame_parameters.h"
#include "linear_elastic.h"
#include "material_laws.h"
#include "neo_hookean.h"
#include "neo_hookean_isochoric.h"
#include "stable_neo_hookean.h"
#include "xpbd_neo_hookean.h"

namespace tb {

/// visit(Law(lame)) for the law of material_laws() called `name`, returning what
/// visit returns (the same type for every law). Throws std::invalid_argument (as
/// find_material_law) for an unknown name; std::logic_error for a law of the table
/// not listed here (the test tests/models/numerics/materials checks every one is).
template <class Visit>
auto visit_material_law(const std::string& name, const LameParameters& lame, Visit&& visit) {
  find_material_law(name);  // the table's error for an unknown name
  if (name == "linear") return visit(LinearElastic(lame));
  if (name == "neo_hookean") return visit(NeoHookean(lame));
  if (name == "neo_hookean_isochoric") return visit(NeoHookeanIsochoric(lame));
  if (name == "stable_neo_hookean") return visit(StableNeoHookean(lame));
  if (name == "xpbd_neo_hookean") return visit(XpbdNeoHookean(lame));
  if (name == "arap_volume") return visit(ArapVolume(lame));
  throw std::logic_error("visit_material_law: law '" + name + "' is in material_laws() but not here (material_law_visit.h)");
}

}  // namespace tb
