// The global matrix of projective dynamics: its blocked and kept contact responses
// (node_constraints, add_constraint_response) against one vector solve per
// constraint, on a box whose holds give the coordinates two distinct factors, as
// the contact set shrinks, changes and grows again.
#include "pd_global_matrix.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "test_support.h"

namespace tb {
namespace {

TEST(PdGlobalMatrix, BlockedConstraintResponsesAreTheVectorSolves) {
  const TetMesh box = testing::box_mesh(0.04, 0.03, 0.02, 4, 3, 2, 2e-7);
  const auto n = static_cast<Eigen::Index>(box.V.rows());
  std::vector<TetShape> shapes;
  Eigen::VectorXd mass = Eigen::VectorXd::Zero(n);
  for (Eigen::Index t = 0; t < box.T.rows(); ++t) {
    shapes.push_back(
        tet_shape(box.V.row(box.T(t, 0)), box.V.row(box.T(t, 1)), box.V.row(box.T(t, 2)), box.V.row(box.T(t, 3))));
    for (int a = 0; a < 4; ++a) mass(box.T(t, a)) += 1000 * shapes.back().volume / 4;
  }
  // The bottom held in all three components, the face x = 0 in x only (a roller):
  // x's free nodes differ from y's and z's, so the matrix has two factors.
  Eigen::Matrix3Xd free = Eigen::Matrix3Xd::Ones(3, n);
  for (Eigen::Index v = 0; v < n; ++v) {
    if (box.V(v, 2) < 1e-9) free.col(v).setZero();
    if (box.V(v, 0) < 1e-9) free(0, v) = 0;
  }
  PdGlobalMatrix A(box.T, shapes, mass / (0.01 * 0.01), free, 3e4);
  ASSERT_EQ(A.factors(), 2);

  // Constraints on top nodes, one on the roller face (its x component held), and
  // one node twice (two spheres): m = 7, in no particular order.
  std::vector<int> nodes;
  for (Eigen::Index v = n - 1; v >= 0 && nodes.size() < 5; --v)
    if (box.V(v, 2) > 0.02 - 1e-9 && box.V(v, 0) > 1e-9) nodes.push_back(static_cast<int>(v));
  for (Eigen::Index v = 0; v < n; ++v)
    if (box.V(v, 0) < 1e-9 && box.V(v, 2) > 1e-9) {
      nodes.push_back(static_cast<int>(v));
      break;
    }
  nodes.push_back(nodes.front());
  ASSERT_EQ(nodes.size(), 7u);
  std::vector<Eigen::Vector3d> directions;
  for (size_t a = 0; a < nodes.size(); ++a) {
    Eigen::Vector3d d(std::cos(0.7 * a), std::sin(1.3 * a), 1.0 + 0.1 * a);
    directions.push_back(d.normalized().cwiseProduct(free.col(nodes[a])));
  }

  // One vector solve per constraint: column b of A^-1 N^T.
  std::vector<Eigen::Matrix3Xd> columns;
  Eigen::Matrix3Xd q(3, n), z(3, n);
  for (size_t b = 0; b < nodes.size(); ++b) {
    q.setZero();
    q.col(nodes[b]) = directions[b];
    A.solve(q, z);
    columns.push_back(z);
  }
  Eigen::MatrixXd schur;
  A.node_constraints(nodes, directions, schur);
  ASSERT_EQ(schur.rows(), 7);
  ASSERT_EQ(schur.cols(), 7);
  const double scale = schur.norm();
  for (size_t a = 0; a < nodes.size(); ++a)
    for (size_t b = 0; b < nodes.size(); ++b)
      EXPECT_NEAR(schur(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b)),
                  directions[a].dot(columns[b].col(nodes[a])), 1e-13 * scale)
          << a << ", " << b;
  EXPECT_LT((schur - schur.transpose()).norm(), 1e-13 * scale);

  Eigen::VectorXd mu(7);
  mu << 0.3, -1.1, 2.0, 0.5, -0.2, 1.7, 0.9;
  Eigen::Matrix3Xd expected = Eigen::Matrix3Xd::Constant(3, n, 0.25), blocked = expected;
  for (size_t b = 0; b < nodes.size(); ++b) expected += mu(static_cast<Eigen::Index>(b)) * columns[b];
  A.add_constraint_response(mu, blocked);
  EXPECT_LT((blocked - expected).norm(), 1e-13 * expected.norm());

  // A smaller set after a larger one (the workspace kept) gives its own answer.
  const std::vector<int> two(nodes.begin() + 1, nodes.begin() + 3);
  const std::vector<Eigen::Vector3d> two_directions(directions.begin() + 1, directions.begin() + 3);
  A.node_constraints(two, two_directions, schur);
  ASSERT_EQ(schur.rows(), 2);
  for (size_t a = 0; a < 2; ++a)
    for (size_t b = 0; b < 2; ++b)
      EXPECT_NEAR(schur(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b)),
                  directions[a + 1].dot(columns[b + 1].col(nodes[a + 1])), 1e-13 * scale)
          << "after the larger set: " << a << ", " << b;
  expected = mu(1) * columns[1] + mu(2) * columns[2];
  blocked.setZero();
  A.add_constraint_response(mu.segment(1, 2), blocked);
  EXPECT_LT((blocked - expected).norm(), 1e-13 * expected.norm());
  // A node new to the set (its column solved, another node's dropped), then the
  // first set again (the dropped column solved anew): each against the vector solves.
  int extra = -1;
  for (Eigen::Index v = 0; v < n && extra < 0; ++v)
    if (free.col(v).sum() == 3 && std::find(nodes.begin(), nodes.end(), v) == nodes.end()) extra = static_cast<int>(v);
  ASSERT_GE(extra, 0);
  q.setZero();
  q.col(extra) = Eigen::Vector3d(0.6, 0, 0.8);
  Eigen::Matrix3Xd extra_column(3, n);
  A.solve(q, extra_column);
  A.node_constraints({nodes[3], extra}, {directions[3], q.col(extra)}, schur);
  EXPECT_NEAR(schur(0, 0), directions[3].dot(columns[3].col(nodes[3])), 1e-13 * scale);
  EXPECT_NEAR(schur(1, 1), q.col(extra).dot(extra_column.col(extra)), 1e-13 * scale);
  EXPECT_NEAR(schur(0, 1), directions[3].dot(extra_column.col(nodes[3])), 1e-13 * scale);
  blocked.setZero();
  A.add_constraint_response(Eigen::Vector2d(0.4, -0.7), blocked);
  expected = 0.4 * columns[3] - 0.7 * extra_column;
  EXPECT_LT((blocked - expected).norm(), 1e-13 * expected.norm());
  A.node_constraints(nodes, directions, schur);
  for (size_t a = 0; a < nodes.size(); ++a)
    for (size_t b = 0; b < nodes.size(); ++b)
      EXPECT_NEAR(schur(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b)),
                  directions[a].dot(columns[b].col(nodes[a])), 1e-13 * scale)
          << "the first set again: " << a << ", " << b;
  // No constraint: an empty S, and no response.
  A.node_constraints({}, {}, schur);
  EXPECT_EQ(schur.size(), 0);
  blocked.setZero();
  A.add_constraint_response(Eigen::VectorXd(0), blocked);
  EXPECT_EQ(blocked.norm(), 0);
}

}  // namespace
}  // namespace tb
