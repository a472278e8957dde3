// Each real-time stepper with its defaults but for the time stepping (step,
// threads), for the tests that run them all the same way.
#pragma once

#include <memory>

#include "pd_solve.h"
#include "vbd_solve.h"
#include "xpbd_tet_solve.h"

namespace tb::testing {

enum class RealtimeStepper { Vbd, Xpbd, Pd };
inline constexpr RealtimeStepper kRealtimeSteppers[] = {RealtimeStepper::Vbd, RealtimeStepper::Xpbd, RealtimeStepper::Pd};

inline const char* name(RealtimeStepper which) {
  return which == RealtimeStepper::Vbd ? "vbd" : which == RealtimeStepper::Xpbd ? "xpbd_neo" : "pd";
}

/// The law each minimises with its defaults.
inline const char* default_law(RealtimeStepper which) {
  return which == RealtimeStepper::Xpbd ? "xpbd_neo_hookean" : "neo_hookean";
}

inline std::unique_ptr<ElasticSolve> make_default_stepper(const ElasticBody& body, RealtimeStepper which,
                                                          const TimeStepping& stepping) {
  if (which == RealtimeStepper::Vbd) {
    VbdSettings o;
    o.stepping = stepping;
    return make_vbd_solve(body, o);
  }
  if (which == RealtimeStepper::Pd) {
    PdSettings o;
    o.stepping = stepping;
    return make_pd_solve(body, o);
  }
  XpbdTetSettings o;
  o.stepping = stepping;
  return make_xpbd_tet_solve(body, o);
}

}  // namespace tb::testing
