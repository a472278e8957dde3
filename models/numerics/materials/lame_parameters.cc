#include "lame_parameters.h"

#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "material.h"

namespace tb {

LameParameters lame_parameters(double E, double nu) {
  if (!(std::isfinite(E) && E > 0)) {
    std::ostringstream msg;
    msg << "material: Young's modulus must be finite and > 0 Pa, got " << std::setprecision(12) << E;
    throw std::invalid_argument(msg.str());
  }
  if (!(std::isfinite(nu) && nu > -1 && nu < 0.5)) {
    std::ostringstream msg;
    msg << "material: Poisson's ratio must lie in (-1, 0.5), got " << std::setprecision(12) << nu;
    throw std::invalid_argument(msg.str());
  }
  LameParameters l;
  l.mu = E / (2 * (1 + nu));
  l.lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
  return l;
}

LameParameters lame_parameters(const Material& material) {
  return lame_parameters(material.youngs_modulus, material.poisson_ratio);
}

}  // namespace tb
