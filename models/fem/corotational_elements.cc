#include "corotational_elements.h"

#include <Eigen/LU>
#include <Eigen/SVD>

namespace tb {

Eigen::Matrix3d polar_rotation(const Eigen::Matrix3d& F) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d U = svd.matrixU();
  const Eigen::Matrix3d& V = svd.matrixV();
  // Singular values come sorted in decreasing order: column 2 is the smallest.
  if ((U * V.transpose()).determinant() < 0) U.col(2) *= -1;
  return U * V.transpose();
}

Eigen::Matrix3d polar_rotation_minus_identity(const Eigen::Matrix3d& H) {
  const Eigen::Matrix3d F = Eigen::Matrix3d::Identity() + H;
  const Eigen::Matrix3d R0 = polar_rotation(F);
  const Eigen::Matrix3d A0 = R0 - Eigen::Matrix3d::Identity();  // exact subtraction near I (Sterbenz)
  // Beyond small rotations the SVD's absolute error is already small relative to |R - I|.
  if (A0.norm() > 1e-2 || F.determinant() <= 0) return A0;
  // Skew part: one Newton step on skew(R^T F) = 0 from R0, with M - M^T for
  // M = R0^T F = R0^T + R0^T H summed from small terms.
  const Eigen::Matrix3d RtH = R0.transpose() * H;
  const Eigen::Matrix3d skew2 = (A0.transpose() - A0) + (RtH - RtH.transpose());
  const Eigen::Vector3d axial(skew2(2, 1), skew2(0, 2), skew2(1, 0));
  const Eigen::Matrix3d M = R0.transpose() * F;
  const Eigen::Matrix3d S = 0.5 * (M + M.transpose());
  const Eigen::Vector3d w = (S.trace() * Eigen::Matrix3d::Identity() - S).inverse() * axial;
  Eigen::Matrix3d W;  // [w]x
  W << 0, -w(2), w(1), w(2), 0, -w(0), -w(1), w(0), 0;
  const Eigen::Matrix3d A1 = A0 + R0 * W;
  // Symmetric part from orthogonality, (I + A)^T (I + A) = I: sym(A) = -A^T A / 2
  // (R0's own symmetric part carries its rounding, about 1e-16 absolute).
  const Eigen::Matrix3d K = 0.5 * (A1 - A1.transpose());
  Eigen::Matrix3d A = K;
  for (int i = 0; i < 3; ++i) A = K - 0.5 * A.transpose() * A;  // |A| <= 1e-2: error |K|^5 relative
  return A;
}

CorotationalElements::CorotationalElements(const TetMesh& mesh, double youngs_modulus, double poisson_ratio)
    : V_(mesh.V),
      T_(mesh.T),
      e_(p1_elements(mesh)),
      lame_(lame_parameters(youngs_modulus, poisson_ratio)),
      R_(mesh.T.rows(), 9),
      h_(e_.gradients),
      c_(Eigen::VectorXd::Zero(3 * mesh.V.rows())) {
  for (Eigen::Index t = 0; t < T_.rows(); ++t)
    Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(&R_(t, 0)).setIdentity();
}

Eigen::Matrix3d CorotationalElements::rotation(Eigen::Index t) const {
  return Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(&R_(t, 0));
}

void CorotationalElements::add_element(Eigen::Index t, const Eigen::Matrix<double, 3, 4>& p, Eigen::VectorXd& y) const {
  const Eigen::Map<const Eigen::Matrix<double, 3, 4>> h(&h_(t, 0));  // column k: R g_k
  add_stress(t, p * h.transpose(), y);                               // G = sum_b p_b h_b^T
}

void CorotationalElements::add_stress(Eigen::Index t, const Eigen::Matrix3d& G, Eigen::VectorXd& y) const {
  const Eigen::Map<const Eigen::Matrix<double, 3, 4>> h(&h_(t, 0));
  Eigen::Matrix3d sigma = lame_.mu * (G + G.transpose());
  sigma.diagonal().array() += lame_.lambda * G.trace();
  const Eigen::Matrix<double, 3, 4> f = e_.volumes(t) * sigma * h;
  for (int a = 0; a < 4; ++a) y.segment<3>(3 * T_(t, a)) += f.col(a);
}

void CorotationalElements::update_rotations(const Eigen::VectorXd& u) {
  c_.setZero();
  inverted_ = 0;
  for (Eigen::Index t = 0; t < T_.rows(); ++t) {
    const Eigen::Map<const Eigen::Matrix<double, 3, 4>> g(&e_.gradients(t, 0));
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();  // displacement gradient, F = I + H
    for (int b = 0; b < 4; ++b) H += u.segment<3>(3 * T_(t, b)) * g.col(b).transpose();
    inverted_ += (Eigen::Matrix3d::Identity() + H).determinant() <= 0;
    const Eigen::Matrix3d A = polar_rotation_minus_identity(H);  // R - I
    const Eigen::Matrix3d R = Eigen::Matrix3d::Identity() + A;
    Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(&R_(t, 0)) = R;
    Eigen::Map<Eigen::Matrix<double, 3, 4>>(&h_(t, 0)) = R * g;
    // c_e = R K_e (X - R^T X) = (R K_e R^T) (R X - X): in add_element's terms
    // G = sum_b (R X_b - X_b) h_b^T = (R - I) (sum_b X_b g_b^T) R^T = I - R^T,
    // as sum_b X_b g_b^T = I for P1 (the rest positions' gradient). Written
    // without X and from the accurate R - I, so that c is as accurate as the
    // rotation is small.
    add_stress(t, -A.transpose(), c_);
  }
}

void CorotationalElements::apply_stiffness(const Eigen::VectorXd& p, Eigen::VectorXd& y) const {
  if (y.size() != dofs()) y.resize(dofs());
  y.setZero();
  Eigen::Matrix<double, 3, 4> pe;
  for (Eigen::Index t = 0; t < T_.rows(); ++t) {
    for (int b = 0; b < 4; ++b) pe.col(b) = p.segment<3>(3 * T_(t, b));
    add_element(t, pe, y);
  }
}

void CorotationalElements::elastic_force(const Eigen::VectorXd& u, Eigen::VectorXd& f) const {
  apply_stiffness(u, f);
  f -= c_;
}

}  // namespace tb
