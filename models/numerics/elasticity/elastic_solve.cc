// The elastic solve strategies, listed once (elastic_solve.h): adding one is its
// file and one line in elastic_solves().
#include "elastic_solve.h"

#include <set>
#include <stdexcept>

namespace tb {

const std::vector<ElasticSolveInfo>& elastic_solves() {
  static const std::vector<ElasticSolveInfo> list = {
      direct_solve_info(),
      iterative_solve_info(),
      corotational_solve_info(),
      newton_solve_info(),
  };
  return list;
}

std::vector<ParameterSpec> cg_tolerance_parameter(const std::string& prefix) {
  return {ParameterSpec::number(prefix + "cg_tolerance", 1e-8, 1e-14, 1e-2,
                                "relative residual tolerance of the iterative and corotational solvers")};
}

std::vector<ParameterSpec> elastic_solve_parameters(const std::string& prefix, const std::string& default_solver,
                                                    const std::string& default_preconditioner) {
  std::vector<std::string> names;
  std::string described;
  for (const auto& s : elastic_solves()) {
    names.push_back(s.name);
    described += (described.empty() ? "" : "; ") + s.name + ": " + s.description;
  }
  std::vector<ParameterSpec> specs = {ParameterSpec::choice(prefix + "solver", names, default_solver, described)};
  for (const auto& s : elastic_solves())
    for (ParameterSpec& p : s.parameters(prefix)) {
      if (p.name == prefix + "preconditioner") p.default_choice = default_preconditioner;
      bool declared = false;  // a parameter two strategies share (cg_tolerance) is listed once
      for (const ParameterSpec& q : specs) declared = declared || q.name == p.name;
      if (!declared) specs.push_back(std::move(p));
    }
  return specs;
}

std::unique_ptr<ElasticSolve> make_elastic_solve(const ElasticBody& body, const Parameters& p,
                                                 const std::string& prefix, const ElasticSolveContext& context) {
  const std::string& name = p.choice(prefix + "solver");
  // A parameter of another strategy only, given explicitly, would be ignored: say so.
  std::set<std::string> own;
  for (const auto& s : elastic_solves())
    if (s.name == name)
      for (const ParameterSpec& q : s.parameters(prefix)) own.insert(q.name);
  for (const auto& s : elastic_solves())
    for (const ParameterSpec& q : s.parameters(prefix))
      if (s.name != name && !own.count(q.name) && p.given(q.name))
        throw std::invalid_argument(q.name + " is a parameter of the " + s.name + " solver; " + prefix + "solver is " +
                                    name);
  for (const auto& s : elastic_solves())
    if (s.name == name) return s.create(body, p, prefix, context);
  std::string known;
  for (const auto& s : elastic_solves()) known += (known.empty() ? "" : ", ") + s.name;
  throw std::invalid_argument("unknown elastic solve '" + name + "' (known: " + known + ")");
}

}  // namespace tb
