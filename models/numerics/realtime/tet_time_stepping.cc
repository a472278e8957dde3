#include "tet_time_stepping.h"

namespace tb {

std::vector<ParameterSpec> time_stepping_parameters(double default_time_step) {
  using P = ParameterSpec;
  return {P::number("time_step", default_time_step, 1e-6, 1, "time step per frame, s"),
          P::whole_number("threads", 1, 1, 64,
                          "threads of the colour-by-colour sweep (the caller and threads - 1 more); the answer does "
                          "not depend on it")};
}

TimeStepping time_stepping(const Parameters& p) {
  TimeStepping s;
  s.time_step = p.number("time_step");
  s.threads = p.integer("threads");
  return s;
}

}  // namespace tb
