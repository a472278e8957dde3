#include "tet_time_stepping.h"

namespace tb {

std::vector<ParameterSpec> time_stepping_parameters(double default_time_step) {
  using P = ParameterSpec;
  return {P::number("time_step", default_time_step, 1e-6, 1, "time step per frame, s"),
          P::whole_number("threads", 1, 1, 64,
                          "threads of the colour-by-colour sweep (the caller and threads - 1 more); the answer does "
                          "not depend on it")};
}

ParameterSpec material_law_parameter(const std::string& default_law) {
  std::vector<std::string> laws;
  for (const MaterialLawInfo& l : material_laws()) laws.push_back(l.name);
  return ParameterSpec::choice("material_law", laws, default_law,
                               "the material law (numerics/materials), with the Lame parameters of the scenario's E and nu");
}

TimeStepping time_stepping(const Parameters& p) {
  TimeStepping s;
  s.time_step = p.number("time_step");
  s.threads = p.integer("threads");
  return s;
}

}  // namespace tb
