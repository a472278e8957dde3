// Element integrals of the fine FEM, written once for every assembly that uses
// them: the serial P1 stiffness (stiffness_assembly.cc, the real-time path) and
// the distributed P1/P2 solver (distributed_elasticity.cc, the reference). A
// deal.II header: include it only from the deal.II translation units.
#pragma once

#include <deal.II/base/tensor.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <cmath>
#include <vector>

#include "stiffness_assembly.h"  // Lame

namespace tb {

/// K^e = sum_q (B^T D B)(x_q) JxW_q (eq. 9) for isotropic D, as in deal.II step-8:
///   K^e_ij = lambda d_ci N_i d_cj N_j + mu d_cj N_i d_ci N_j + [ci = cj] mu grad N_i . grad N_j
///   fe_values  reinit'ed on the cell, with update_gradients | update_JxW_values
///   component  #dofs_per_cell vector component of each shape function
///   Ke         #dofs_per_cell square, overwritten
/// With one quadrature point (P1) each entry is one product k * JxW, so adding Ke
/// into K gives the same bits as adding the products one by one.
template <int dim>
void linear_elastic_cell_matrix(const dealii::FEValues<dim>& fe_values, const std::vector<unsigned>& component,
                                const Lame& lame, dealii::FullMatrix<double>& Ke,
                                std::vector<dealii::Tensor<1, dim>>& grad) {
  const unsigned n = fe_values.dofs_per_cell;
  Ke.reinit(n, n);
  grad.resize(n);
  for (unsigned q = 0; q < fe_values.n_quadrature_points; ++q) {
    for (unsigned i = 0; i < n; ++i) grad[i] = fe_values.shape_grad(i, q);
    const double JxW = fe_values.JxW(q);
    for (unsigned i = 0; i < n; ++i) {
      const unsigned ci = component[i];
      for (unsigned j = 0; j < n; ++j) {
        const unsigned cj = component[j];
        double k = grad[i][ci] * grad[j][cj] * lame.lambda + grad[i][cj] * grad[j][ci] * lame.mu;
        if (ci == cj) k += grad[i] * grad[j] * lame.mu;
        Ke(i, j) += k * JxW;
      }
    }
  }
}

/// Compressible neo-Hookean (total Lagrangian, dead loads): stored energy
///   W(F) = mu/2 (tr(F^T F) - 3) - mu ln J + lambda/2 (ln J)^2,   J = det F,
/// first Piola-Kirchhoff stress P = mu (F - F^-T) + lambda ln J F^-T and its
/// derivative dP[dF] = mu dF + (mu - lambda ln J) F^-T dF^T F^-T
///                     + lambda (F^-T : dF) F^-T.
/// At F = I the tangent is the linear D of eq. (9) with the same lambda and mu, so
/// the law reduces to linear elasticity at small strain.
///   u_cell    #dofs_per_cell coefficients of the displacement on the cell
///   Ke        tangent sum_q dN_i : dP[dN_j] JxW (if non-null), overwritten
///   Re        internal force sum_q P : dN_i JxW, overwritten
/// Returns false (and leaves Ke, Re unspecified) if J <= 0 at a quadrature point.
template <int dim>
bool neo_hookean_cell(const dealii::FEValues<dim>& fe_values, const std::vector<unsigned>& component,
                      const dealii::Vector<double>& u_cell, const Lame& lame, dealii::FullMatrix<double>* Ke,
                      dealii::Vector<double>& Re, std::vector<dealii::Tensor<1, dim>>& grad) {
  using dealii::Tensor;
  const unsigned n = fe_values.dofs_per_cell;
  if (Ke) Ke->reinit(n, n);
  Re.reinit(n);
  grad.resize(n);
  for (unsigned q = 0; q < fe_values.n_quadrature_points; ++q) {
    Tensor<2, dim> F;
    for (unsigned i = 0; i < n; ++i) {
      grad[i] = fe_values.shape_grad(i, q);
      for (unsigned d = 0; d < dim; ++d) F[component[i]][d] += u_cell[i] * grad[i][d];
    }
    for (unsigned d = 0; d < dim; ++d) F[d][d] += 1;
    const double J = dealii::determinant(F);
    if (!(J > 0)) return false;
    const Tensor<2, dim> F_inv_T = dealii::transpose(dealii::invert(F));
    const double ln_J = std::log(J);
    const Tensor<2, dim> P = lame.mu * (F - F_inv_T) + lame.lambda * ln_J * F_inv_T;
    const double JxW = fe_values.JxW(q);
    // dN_i = e_ci (x) grad N_i: P : dN_i = P[ci] . grad N_i.
    for (unsigned i = 0; i < n; ++i) Re[i] += P[component[i]] * grad[i] * JxW;
    if (!Ke) continue;
    const double c1 = lame.mu - lame.lambda * ln_J;
    for (unsigned j = 0; j < n; ++j) {
      // dN_j = e_cj (x) g_j (g_j = grad N_j), so with a = F^-T g_j:
      //   (F^-T dN_j^T F^-T)_{rd} = a_r (F^-T)_{cj d},   F^-T : dN_j = (F^-T)_{cj} . g_j
      const unsigned cj = component[j];
      const Tensor<1, dim> a = F_inv_T * grad[j];
      const double trace = F_inv_T[cj] * grad[j];
      for (unsigned i = 0; i < n; ++i) {
        // dN_i : dP[dN_j] = lambda (F^-T : dN_j)(F^-T : dN_i) + c1 a_ci ((F^-T)_cj . g_i) + [ci = cj] mu g_i . g_j
        const unsigned ci = component[i];
        double k = lame.lambda * trace * (F_inv_T[ci] * grad[i]) + c1 * a[ci] * (F_inv_T[cj] * grad[i]);
        if (ci == cj) k += lame.mu * (grad[i] * grad[j]);
        (*Ke)(i, j) += k * JxW;
      }
    }
  }
  return true;
}

}  // namespace tb
