// The material laws, listed once: the runtime table a scenario or a solver picks
// a law from by name. Each entry reaches the law's header (energy, stress and
// tangent written once there) through the Lame parameters of the given (E, nu);
// code that evaluates a law in an inner loop uses the law's struct directly
// (LinearElastic, NeoHookean, NeoHookeanIsochoric, StableNeoHookean,
// XpbdNeoHookean, ArapVolume), or picks that struct by name with visit_material_law
// (material_law_visit.h).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "deformation_gradient.h"
#include "lame_parameters.h"

namespace tb {

/// One law of the table. The functions take F (3x3) and the Lame parameters of
/// (E, nu) (lame_parameters.h), map them to the law's own parameters and return
/// W (J/m^3), P (3x3, Pa) and dP/dF (9x9, Pa; deformation_gradient.h's convention).
struct MaterialLawInfo {
  std::string name;         ///< [a-z0-9_]+
  std::string description;  ///< the law, its parameters from (E, nu), and its source
  double (*energy)(const Eigen::Matrix3d& F, const LameParameters& lame);
  Eigen::Matrix3d (*first_piola)(const Eigen::Matrix3d& F, const LameParameters& lame);
  Matrix9d (*tangent)(const Eigen::Matrix3d& F, const LameParameters& lame);
  /// Whether the law is defined for det F <= 0; if not, energy is +infinity there
  /// and first_piola and tangent throw std::domain_error.
  bool defined_when_inverted;
};

/// Every law, each once, in a fixed order: linear, neo_hookean,
/// neo_hookean_isochoric, stable_neo_hookean, xpbd_neo_hookean, arap_volume.
const std::vector<MaterialLawInfo>& material_laws();

/// The law called name. Throws std::invalid_argument listing the known names.
const MaterialLawInfo& find_material_law(const std::string& name);

}  // namespace tb
