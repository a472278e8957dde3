// What each registered elastic solve says it takes before a body exists
// (ElasticSolveInfo::refuses_spheres, refuses_springs, read by a model's check
// before setup) against what an instance made from the same parameters answers.
#include <gtest/gtest.h>

#include "elastic_body.h"
#include "elastic_solve.h"
#include "model.h"
#include "test_support.h"

namespace tb {
namespace {

TEST(ElasticSolveTools, EveryStrategyDeclaresWhatItsInstancesTake) {
  const HybridMesh& cube = testing::scenario_mesh("cube-pull");
  const TetMesh& m = cube.coarse_volume;
  const ElasticBody body(m, Material{}, testing::kCubeBottom.select(m.V));
  const ModelInfo& fem = find_model("fem");  // its parameters name the strategies' with prefix ""
  int sphere_refusals = 0, spring_refusals = 0, cases = 0;
  for (const ElasticSolveInfo& s : elastic_solves()) {
    std::vector<nlohmann::json> given = {{{"solver", s.name}}};
    // The Newton solve with a per-frame budget has no contact set.
    if (s.name == "newton") given.push_back({{"solver", s.name}, {"newton_max_iterations_per_frame", 1}});
    for (const nlohmann::json& g : given) {
      const Parameters p = resolve_parameters(fem.parameters, g, "fem");
      const std::unique_ptr<ElasticSolve> solve = testing::make_solve(body, g, &m);
      const std::string no_sphere = s.refuses_spheres(p, ""), no_springs = s.refuses_springs(p, "");
      EXPECT_EQ(no_sphere.empty(), solve->linear() || solve->takes_spheres()) << g.dump() << ": " << no_sphere;
      EXPECT_EQ(no_springs.empty(), solve->takes_springs()) << g.dump() << ": " << no_springs;
      sphere_refusals += !no_sphere.empty();
      spring_refusals += !no_springs.empty();
      ++cases;
    }
  }
  // The corotational solve takes neither, the budgeted Newton no sphere, the others both:
  // the check before setup has something to refuse and something to let through.
  EXPECT_EQ(sphere_refusals, 2);
  EXPECT_EQ(spring_refusals, 1);
  EXPECT_EQ(cases, 5);
}

}  // namespace
}  // namespace tb
