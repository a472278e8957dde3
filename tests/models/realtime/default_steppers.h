// Either real-time stepper with its defaults but for the time stepping (step,
// threads), for the tests that run both the same way.
#pragma once

#include <memory>

#include "vbd_solve.h"
#include "xpbd_tet_solve.h"

namespace tb::testing {

enum class RealtimeStepper { Vbd, Xpbd };

inline std::unique_ptr<ElasticSolve> make_default_stepper(const ElasticBody& body, RealtimeStepper which,
                                                          const TimeStepping& stepping) {
  if (which == RealtimeStepper::Vbd) {
    VbdSettings o;
    o.stepping = stepping;
    return make_vbd_solve(body, o);
  }
  XpbdTetSettings o;
  o.stepping = stepping;
  return make_xpbd_tet_solve(body, o);
}

}  // namespace tb::testing
