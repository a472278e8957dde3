#include "deformation_gradient.h"

#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace tb {

void throw_inverted(const char* law, const char* quantity, double J) {
  std::ostringstream msg;
  msg << law << ": " << quantity << " is undefined at det F = " << std::setprecision(12) << J
      << " (the law needs det F > 0; its energy is +infinity there)";
  throw std::domain_error(msg.str());
}

}  // namespace tb
