// The distributed FEM's element integrals (elasticity_cell.h), for every material
// law of the table: the tangent is the derivative of the internal force (central
// differences), and at zero displacement it is the linear element matrix of eq. (9);
// the body force's consistent load against its closed forms (P1 and P2).
// On one P2 tet with a distorted shape, so every term is exercised. A deal.II
// translation unit.
#include "elasticity_cell.h"

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_fe.h>
#include <deal.II/grid/tria.h>
#include <gtest/gtest.h>

#include <random>
#include <sstream>

namespace tb {
namespace {

using namespace dealii;

/// One tet of degree P2 (or P1) with the engine's quadrature (degree-exact rule).
struct OneTet {
  Triangulation<3> tria;
  FESystem<3> fe;
  MappingFE<3> mapping{FE_SimplexP<3>(1)};
  QGaussSimplex<3> quadrature;
  std::unique_ptr<FEValues<3>> fe_values;
  std::vector<unsigned> component;
  explicit OneTet(unsigned degree = 2) : fe(FE_SimplexP<3>(degree), 3), quadrature(degree) {
    const std::vector<Point<3>> v = {{0, 0, 0}, {1.2, 0.1, 0}, {0.2, 0.9, 0.1}, {0.1, 0.3, 1.1}};
    std::vector<CellData<3>> cells(1, CellData<3>(4));
    for (unsigned k = 0; k < 4; ++k) cells[0].vertices[k] = k;
    tria.create_triangulation(v, cells, SubCellData());
    fe_values =
        std::make_unique<FEValues<3>>(mapping, fe, quadrature, update_values | update_gradients | update_JxW_values);
    fe_values->reinit(tria.begin_active());
    for (unsigned i = 0; i < fe.n_dofs_per_cell(); ++i) component.push_back(fe.system_to_component_index(i).first);
  }
};

const LameParameters kLame = lame_parameters(3000, 0.45);

class EveryLaw : public ::testing::TestWithParam<std::string> {};

TEST_P(EveryLaw, TangentAtRestIsTheLinearElementMatrix) {
  OneTet t;
  const MaterialLawInfo& law = find_material_law(GetParam());
  const unsigned n = t.fe.n_dofs_per_cell();
  FullMatrix<double> K_linear, K_law;
  dealii::Vector<double> R, u(n);
  std::vector<Tensor<1, 3>> grad;
  linear_elastic_cell_matrix(*t.fe_values, t.component, LinearElastic(kLame), K_linear, grad);
  ASSERT_TRUE(hyperelastic_cell(*t.fe_values, t.component, u, law, kLame, &K_law, R, grad));
  EXPECT_LT(R.l2_norm(), 1e-12 * K_linear.frobenius_norm()) << "no stress at rest";
  K_law.add(-1, K_linear);
  EXPECT_LT(K_law.frobenius_norm(), 1e-10 * K_linear.frobenius_norm());
}

TEST_P(EveryLaw, TangentIsTheDerivativeOfTheInternalForce) {
  OneTet t;
  const MaterialLawInfo& law = find_material_law(GetParam());
  const unsigned n = t.fe.n_dofs_per_cell();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1, 1);
  dealii::Vector<double> u(n), R, R_plus, R_minus, u_step(n);
  for (unsigned i = 0; i < n; ++i) u[i] = 0.08 * unit(rng);  // strains of ~10%: well inside the nonlinear range
  FullMatrix<double> K;
  std::vector<Tensor<1, 3>> grad;
  ASSERT_TRUE(hyperelastic_cell(*t.fe_values, t.component, u, law, kLame, &K, R, grad));
  const double h = 1e-6;
  double worst = 0;
  for (unsigned j = 0; j < n; ++j) {
    u_step = u;
    u_step[j] += h;
    ASSERT_TRUE(hyperelastic_cell(*t.fe_values, t.component, u_step, law, kLame, nullptr, R_plus, grad));
    u_step[j] -= 2 * h;
    ASSERT_TRUE(hyperelastic_cell(*t.fe_values, t.component, u_step, law, kLame, nullptr, R_minus, grad));
    for (unsigned i = 0; i < n; ++i) worst = std::max(worst, std::abs((R_plus[i] - R_minus[i]) / (2 * h) - K(i, j)));
  }
  // Central differences: error O(h^2) times third derivatives, plus round-off
  // |R| eps / h; both far below 1e-6 of the tangent's size here.
  EXPECT_LT(worst, 1e-6 * K.linfty_norm()) << "worst entry error " << worst << " of " << K.linfty_norm();
  std::ostringstream os;
  os << worst / K.linfty_norm();
  RecordProperty("worst_relative_entry_error", os.str());
}

TEST_P(EveryLaw, AnInvertedElementIsRejectedWhereTheLawIsUndefined) {
  OneTet t;
  const MaterialLawInfo& law = find_material_law(GetParam());
  const unsigned n = t.fe.n_dofs_per_cell();
  dealii::Vector<double> u(n), R;
  std::vector<Tensor<1, 3>> grad;
  // u = -2 x: F = -I, J = -1.
  const std::vector<Point<3>>& support = t.fe.get_unit_support_points();
  for (unsigned i = 0; i < n; ++i) {
    const Point<3> x = t.mapping.transform_unit_to_real_cell(t.tria.begin_active(), support[i]);
    u[i] = -2 * x[t.component[i]];
  }
  FullMatrix<double> K;
  const bool accepted = hyperelastic_cell(*t.fe_values, t.component, u, law, kLame, &K, R, grad);
  EXPECT_EQ(accepted, law.defined_when_inverted) << law.name;
  if (accepted) {  // then finite, never NaN
    for (unsigned i = 0; i < n; ++i) EXPECT_TRUE(std::isfinite(R[i])) << i;
    EXPECT_TRUE(std::isfinite(K.frobenius_norm()));
  }
}

/// The consistent load of a uniform body force b: int b_c N_i dV, whose closed
/// forms on a tet of volume V are b V / 4 at each vertex (P1) and -b V / 20 at each
/// vertex, b V / 5 at each edge midpoint (P2; Zienkiewicz and Taylor, The Finite
/// Element Method vol. 1, 5th ed. 2000, section 8.8.2, the quadratic tetrahedron):
/// the rule the engine uses integrates them exactly, and each component's sum is b V.
TEST(BodyForceCell, IsTheConsistentLoadOfP1AndP2) {
  const Eigen::Vector3d b(1.5, -2, 9.81);
  for (unsigned degree = 1; degree <= 2; ++degree) {
    OneTet t(degree);
    const std::vector<Point<3>> v = {{0, 0, 0}, {1.2, 0.1, 0}, {0.2, 0.9, 0.1}, {0.1, 0.3, 1.1}};
    const double V = std::abs((v[1] - v[0]) * cross_product_3d(v[2] - v[0], v[3] - v[0])) / 6;
    dealii::Vector<double> f;
    body_force_cell(*t.fe_values, t.component, b, f);
    ASSERT_EQ(f.size(), t.fe.n_dofs_per_cell());
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (unsigned i = 0; i < f.size(); ++i) {
      const unsigned c = t.component[i];
      // A vertex's shape function is the first 4 per component (deal.II's dof order).
      const bool vertex = t.fe.system_to_component_index(i).second < 4;
      const double share = degree == 1 ? 0.25 : vertex ? -0.05 : 0.2;
      EXPECT_NEAR(f[i], share * b[c] * V, 1e-14 * b.norm() * V) << "P" << degree << " dof " << i;
      sum[c] += f[i];
    }
    EXPECT_LT((sum - b * V).norm(), 1e-14 * b.norm() * V) << "P" << degree;
  }
}

std::vector<std::string> law_names() {
  std::vector<std::string> names;
  for (const MaterialLawInfo& law : material_laws()) names.push_back(law.name);
  return names;
}

INSTANTIATE_TEST_SUITE_P(Laws, EveryLaw, ::testing::ValuesIn(law_names()),
                         [](const ::testing::TestParamInfo<std::string>& i) { return i.param; });

}  // namespace
}  // namespace tb
