// The embedded model (coarse FEM + barycentric mapping of every surface vertex):
// at rest the mapping reproduces the surface, and it moves the surface vertices
// that are control points exactly as the hybrid's coarse FEM moves them.
#include <gtest/gtest.h>

#include "coarse_embedding.h"
#include "model.h"
#include "test_support.h"

namespace tb {
namespace {

const SupportBox kBottom{{-1, -1, -1e-9}, {1, 1, 1e-9}};
const FrameLoads kPull = testing::kCubePull.frame();

std::unique_ptr<Model> make(const std::string& name, const HybridMesh& mesh, const nlohmann::json& params = {}) {
  return testing::set_up_model(name, mesh, kBottom, params);
}

TEST(CoarseEmbedding, WeightsReproduceEverySurfaceVertexAtRest) {
  // The liver's vertices lie partly outside its given coarse mesh (up to about
  // 1 mm): unclamped weights still reproduce them.
  for (const std::string scenario : {"cube-pull", "liver-pull"}) {
    const HybridMesh& h = testing::scenario_mesh(scenario, false);
    const auto embedding = embed_vertices(h.fine_surface.V, h.coarse_volume);
    Eigen::VectorXd coarse_X(3 * h.coarse_volume.V.rows());
    for (Eigen::Index v = 0; v < h.coarse_volume.V.rows(); ++v) coarse_X.segment<3>(3 * v) = h.coarse_volume.V.row(v);
    Points mapped;
    interpolate_embedded(embedding, h.coarse_volume.T, coarse_X, mapped);
    EXPECT_LT((mapped - h.fine_surface.V).cwiseAbs().maxCoeff(), 1e-12) << scenario;
  }
}

TEST(EmbeddedModel, MovesControlPointsAsTheHybridsCoarseFem) {
  const HybridMesh& h = testing::scenario_mesh("cube-pull");
  auto embedded = make("embedded", h);
  auto hybrid = make("hybrid", h, {{"surface_force", "none"}});
  embedded->step(kPull);
  hybrid->step(kPull);
  const Displacements& a = embedded->surface_displacement();
  const Displacements& b = hybrid->surface_displacement();
  double largest = 0, worst = 0;
  for (const ControlPoint& cp : h.control_points) {
    worst = std::max(worst, (a.row(cp.surface_vertex) - b.row(cp.surface_vertex)).norm());
    largest = std::max(largest, b.row(cp.surface_vertex).norm());
  }
  ASSERT_GT(largest, 1e-4);
  EXPECT_LT(worst, 1e-14 * largest);
  // Elsewhere it differs from the hybrid (PBD moves those vertices): it is a different model.
  EXPECT_GT((a - b).norm(), 1e-6);
}

TEST(EmbeddedModel, ZeroLoadIsRest) {
  auto m = make("embedded", testing::scenario_mesh("cube-pull"));
  m->step(testing::kCubePull.scaled(0).frame());
  EXPECT_EQ(m->surface_displacement().cwiseAbs().maxCoeff(), 0.0);
}

}  // namespace
}  // namespace tb
