#include "corotational_elements.h"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <cmath>

namespace tb {

Eigen::Matrix3d polar_rotation(const Eigen::Matrix3d& F) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d U = svd.matrixU();
  const Eigen::Matrix3d& V = svd.matrixV();
  // Singular values come sorted in decreasing order: column 2 is the smallest.
  if ((U * V.transpose()).determinant() < 0) U.col(2) *= -1;
  return U * V.transpose();
}

namespace {

/// exp([w]x) - I (Rodrigues), without cancellation for small |w|.
Eigen::Matrix3d rotation_minus_identity(const Eigen::Vector3d& w) {
  const double t2 = w.squaredNorm(), t = std::sqrt(t2);
  double a, b;  // sin(t) / t and (1 - cos(t)) / t^2
  if (t < 1e-3) {
    a = 1 - t2 / 6 + t2 * t2 / 120;
    b = 0.5 - t2 / 24 + t2 * t2 / 720;
  } else {
    a = std::sin(t) / t;
    const double s = std::sin(t / 2);
    b = 2 * s * s / t2;
  }
  Eigen::Matrix3d W;  // [w]x
  W << 0, -w(2), w(1), w(2), 0, -w(0), -w(1), w(0), 0;
  return a * W + b * W * W;
}

}  // namespace

bool polar_rotation_minus_identity(const Eigen::Matrix3d& H, Eigen::Matrix3d& A) {
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  if ((I + H).determinant() > 0) {
    for (int it = 0; it < 8; ++it) {
      // M = R^T F = (I + A^T)(I + H); M - M^T summed from small terms.
      const Eigen::Matrix3d AtH = A.transpose() * H;
      const Eigen::Matrix3d D = (H - H.transpose()) + (A.transpose() - A) + (AtH - AtH.transpose());
      const Eigen::Vector3d axial(D(2, 1), D(0, 2), D(1, 0));
      const Eigen::Matrix3d N = H + A.transpose() + AtH;  // M - I
      const Eigen::Matrix3d S = I + 0.5 * (N + N.transpose());
      // tr(S) I - S positive definite, else too far from the solution: take the SVD's.
      const Eigen::Matrix3d J = S.trace() * I - S;
      if (!(J(0, 0) > 0 && J.topLeftCorner<2, 2>().determinant() > 0 && J.determinant() > 0)) break;
      const Eigen::Vector3d w = J.inverse() * axial;
      if (!w.allFinite() || w.norm() > 2) break;
      A += (I + A) * rotation_minus_identity(w);  // R <- R exp([w]x)
      // Quadratic: the remaining error is ~|w|^2. R^T F symmetric positive
      // definite singles out the polar rotation among the stationary points
      // (e.g. R turned half a turn) that a far warm start may reach.
      if (w.norm() <= 1e-9 * A.norm()) {
        const Eigen::Matrix3d Ns = H + A.transpose() + A.transpose() * H;
        const Eigen::Matrix3d Sn = I + 0.5 * (Ns + Ns.transpose());
        if (Sn(0, 0) > 0 && Sn.topLeftCorner<2, 2>().determinant() > 0 && Sn.determinant() > 0) return true;
        break;
      }
    }
  }
  A = polar_rotation(I + H) - I;
  return false;
}

CorotationalElements::CorotationalElements(const TetMesh& mesh, double youngs_modulus, double poisson_ratio)
    : V_(mesh.V),
      T_(mesh.T),
      e_(p1_elements(mesh)),
      lame_(lame_parameters(youngs_modulus, poisson_ratio)),
      A_(Eigen::MatrixXd::Zero(mesh.T.rows(), 9)),
      h_(e_.gradients),
      c_(Eigen::VectorXd::Zero(3 * mesh.V.rows())) {}

Eigen::Matrix3d CorotationalElements::rotation(Eigen::Index t) const {
  return Eigen::Matrix3d::Identity() + Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(&A_(t, 0));
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
  svd_fallbacks_ = 0;
  for (Eigen::Index t = 0; t < T_.rows(); ++t) {
    const Eigen::Map<const Eigen::Matrix<double, 3, 4>> g(&e_.gradients(t, 0));
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();  // displacement gradient, F = I + H
    for (int b = 0; b < 4; ++b) H += u.segment<3>(3 * T_(t, b)) * g.col(b).transpose();
    inverted_ += (Eigen::Matrix3d::Identity() + H).determinant() <= 0;
    // R - I, warm-started from the last update's.
    Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> Am(&A_(t, 0));
    Eigen::Matrix3d A = Am;
    svd_fallbacks_ += !polar_rotation_minus_identity(H, A);
    Am = A;
    const Eigen::Matrix3d R = Eigen::Matrix3d::Identity() + A;
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
