// The material every model is given: linear isotropic elasticity, SI units. Its own
// header so that the layers under the Model interface (fem/, pbd/) need not
// include model.h.
#pragma once

namespace tb {

/// Linear isotropic elastic material, SI units.
struct Material {
  double youngs_modulus = 3000;  ///< Pa
  double poisson_ratio = 0.45;
  double density = 1000;  ///< kg/m^3
};

}  // namespace tb
