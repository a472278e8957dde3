// What each registered elastic solve says it takes before a body exists
// (ElasticSolveInfo::takes_spheres, takes_springs, read by a model's check before
// setup) against what an instance of it answers.
#include <gtest/gtest.h>

#include "elastic_body.h"
#include "elastic_solve.h"
#include "test_support.h"

namespace tb {
namespace {

TEST(ElasticSolveTools, EveryStrategyDeclaresWhatItsInstancesTake) {
  const HybridMesh& cube = testing::scenario_mesh("cube-pull");
  const TetMesh& m = cube.coarse_volume;
  const ElasticBody body(m, Material{}, testing::kCubeBottom.select(m.V));
  int sphere_takers = 0, spring_takers = 0;
  for (const ElasticSolveInfo& s : elastic_solves()) {
    const std::unique_ptr<ElasticSolve> solve =
        testing::make_solve(body, {{"solver", s.name}}, &m);
    EXPECT_EQ(s.takes_spheres, solve->linear() || solve->takes_spheres()) << s.name;
    EXPECT_EQ(s.takes_springs, solve->takes_springs()) << s.name;
    sphere_takers += s.takes_spheres;
    spring_takers += s.takes_springs;
  }
  // Not every strategy takes both (the corotational one takes neither): the check has
  // something to refuse.
  EXPECT_GT(sphere_takers, 0);
  EXPECT_LT(sphere_takers, static_cast<int>(elastic_solves().size()));
  EXPECT_LT(spring_takers, static_cast<int>(elastic_solves().size()));
}

}  // namespace
}  // namespace tb
