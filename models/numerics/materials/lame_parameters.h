// The Lame parameters of isotropic elasticity from Young's modulus and Poisson's
// ratio, checked once, here, for every material law of this folder. Each law
// takes them and maps them to its own parameters, so that all of them share the
// small-strain limit of linear elasticity with the given (E, nu).
#pragma once

namespace tb {

struct Material;

/// The two Lame parameters of isotropic linear elasticity, Pa.
struct LameParameters {
  double lambda = 0;  ///< first Lame parameter, Pa
  double mu = 0;      ///< second Lame parameter (shear modulus), Pa
  /// Bulk modulus K = lambda + 2 mu / 3, Pa.
  double bulk_modulus() const { return lambda + 2 * mu / 3; }
};

/// mu = E / (2 (1 + nu)), lambda = E nu / ((1 + nu)(1 - 2 nu)).
/// Throws std::invalid_argument, naming the value, unless E is finite and > 0 and
/// nu is finite with -1 < nu < 0.5: the range in which mu > 0 and K > 0, so the
/// isotropic elasticity tensor is positive definite.
LameParameters lame_parameters(double youngs_modulus, double poisson_ratio);
/// The same from a Material's youngs_modulus and poisson_ratio.
LameParameters lame_parameters(const Material& material);

}  // namespace tb
