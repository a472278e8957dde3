// Corotational linear elasticity on P1 tets: stiffness warping with one rotation
// per element (Mueller and Gross 2004, "Interactive Virtual Materials", GI 2004;
// the paper is not in the repository, so its equation numbers are not cited here).
// Each tet's rotation R_e is the rotational factor of the polar decomposition of
// its deformation gradient; the element then acts as the linear element of
// eq. (9) in its rotated frame:
//   f_e(x) = R_e K_e (R_e^T x_e - X_e)                     elastic force of tet e
//          = R_e K_e R_e^T u_e - R_e K_e (X_e - R_e^T X_e)    (x = X + u)
// so that, with R held fixed, the equilibrium sum_e f_e = f is the linear system
//   K_R u = f + c,  K_R = sum_e R_e K_e R_e^T,  c = sum_e R_e K_e (X_e - R_e^T X_e).
// K_R is never assembled: for isotropic D, R K^e_ab R^T is K^e_ab with the shape
// gradients rotated (h = R g), and applying it is a stress times a gradient:
//   y_a = V sigma h_a,  G = sum_b p_b h_b^T,  sigma = lambda tr(G) I + mu (G + G^T).
// Stateless math in free functions, the per-element state in a thin class.
#pragma once

#include <Eigen/Core>

#include "mesh_types.h"
#include "lame_parameters.h"
#include "stiffness_assembly.h"

namespace tb {

/// The rotation of the polar decomposition F = R S (S symmetric), from the SVD
/// F = U Sigma V^T: R = U V^T. An inverted or flat element (det F <= 0) would make
/// U V^T a reflection; then the singular vector of the smallest singular value
/// is flipped, R = U diag(1, 1, -1) V^T (Irving, Teran and Fedkiw 2004), so R is
/// always a proper rotation (det R = +1), the one nearest F.
Eigen::Matrix3d polar_rotation(const Eigen::Matrix3d& F);

/// R - I for the polar rotation R of F = I + H (H the displacement gradient),
/// accurate relative to |R - I| however small the rotation (polar_rotation(F) - I
/// has an absolute error of about 1e-16, relative 1e-16 / |R - I|, which at small
/// loads would set the corotational residual's floor). Newton's iteration on the
/// polar condition skew(R^T F) = 0, warm-started from A, written in small terms:
///   R <- R exp([w]x),  (tr(S) I - S) w = axial(M - M^T),  M = R^T F, S = sym(M)
/// (quadratic near the solution; two steps from the last update's rotation are
/// typical). Falls back to polar_rotation (the SVD) when det F <= 0, when
/// tr(S) I - S is not positive definite or a step exceeds 2 radians (too far
/// from the solution), when it converges to R with R^T F not positive definite
/// (another stationary point) or has not converged in 8 steps.
///   H  3 by 3, F = I + H
///   A  3 by 3: in, R - I of a nearby F (0: start from the identity); out, R - I
/// Returns false when the SVD was used.
bool polar_rotation_minus_identity(const Eigen::Matrix3d& H, Eigen::Matrix3d& A);

class CorotationalElements {
 public:
  /// Element gradients and volumes from p1_elements(mesh) (the ones the linear K
  /// is assembled from); every rotation the identity.
  CorotationalElements(const TetMesh& mesh, double youngs_modulus, double poisson_ratio);

  /// R_e of every tet from F_e = I + sum_k u_k g_k^T at the displacement u, and
  /// the offset c. No allocation.
  ///   u  3 #V, dof 3 * node + component
  void update_rotations(const Eigen::VectorXd& u);

  /// y = K_R p (rotations of the last update). No allocation when y has the size.
  ///   p, y  3 #V
  void apply_stiffness(const Eigen::VectorXd& p, Eigen::VectorXd& y) const;
  /// c = sum_e R_e K_e (X_e - R_e^T X_e), 3 #V (zero before the first update).
  const Eigen::VectorXd& offset() const { return c_; }
  /// f = K_R u - c = sum_e R_e K_e (R_e^T x_e - X_e): the elastic force at u with
  /// the rotations of the last update (update at u first for the force at u).
  void elastic_force(const Eigen::VectorXd& u, Eigen::VectorXd& f) const;

  /// R_e (3 by 3) of tet t.
  Eigen::Matrix3d rotation(Eigen::Index t) const;
  /// Tets with det F <= 0 (inverted or flat) at the last update.
  int inverted_elements() const { return inverted_; }
  /// Tets whose rotation the SVD gave at the last update (polar_rotation_minus_identity).
  int svd_fallbacks() const { return svd_fallbacks_; }
  Eigen::Index dofs() const { return 3 * V_.rows(); }

 private:
  /// y_a += V_t sigma(G) h_a for the four nodes a of tet t, G = sum_b p_b h_b^T:
  /// the rotated element matrix R K^e R^T applied to the element's p.
  void add_element(Eigen::Index t, const Eigen::Matrix<double, 3, 4>& p, Eigen::VectorXd& y) const;
  /// y_a += V_t sigma(G) h_a for a given G (3 by 3, the rotated displacement gradient).
  void add_stress(Eigen::Index t, const Eigen::Matrix3d& G, Eigen::VectorXd& y) const;

  Points V_;      ///< #V by 3 rest positions X
  Tetrahedra T_;  ///< #T by 4
  P1Elements e_;  ///< g and V per tet
  LameParameters lame_;
  Eigen::Matrix<double, Eigen::Dynamic, 9, Eigen::RowMajor> A_;   ///< #T by 9: R_e - I row-major
  Eigen::Matrix<double, Eigen::Dynamic, 12, Eigen::RowMajor> h_;  ///< #T by 12: R_e g_k, k = 0..3
  Eigen::VectorXd c_;
  int inverted_ = 0, svd_fallbacks_ = 0;
};

}  // namespace tb
