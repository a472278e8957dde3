// Element integrals of the distributed FEM (distributed_elasticity.cc and
// nonlinear_solve.cc) on cells of any degree, from the material laws of
// models/numerics/materials: the linear law's B^T D B entry (linear_elastic.h, the
// same coding the serial assembly uses) and, for any law of the table, the
// internal force and tangent from P(F) and dP/dF, and the consistent load of a body
// force. A deal.II header: include it
// only from the deal.II translation units.
#pragma once

#include <deal.II/base/tensor.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <Eigen/Core>
#include <cmath>
#include <vector>

#include "linear_elastic.h"
#include "material_laws.h"

namespace tb {

/// K^e = sum_q (B^T D B)(x_q) JxW_q (eq. 9) for isotropic D, entry by entry the
/// linear law's stiffness_entry(grad N_i, grad N_j, ci, cj):
///   K^e_ij = lambda d_ci N_i d_cj N_j + mu d_cj N_i d_ci N_j + [ci = cj] mu grad N_i . grad N_j
///   fe_values  reinit'ed on the cell, with update_gradients | update_JxW_values
///   component  #dofs_per_cell vector component of each shape function
///   Ke         #dofs_per_cell square, overwritten
/// With one quadrature point (P1) each entry is one product k * JxW, so adding Ke
/// into K gives the same bits as adding the products one by one.
template <int dim>
void linear_elastic_cell_matrix(const dealii::FEValues<dim>& fe_values, const std::vector<unsigned>& component,
                                const LinearElastic& law, dealii::FullMatrix<double>& Ke,
                                std::vector<dealii::Tensor<1, dim>>& grad) {
  const unsigned n = fe_values.dofs_per_cell;
  Ke.reinit(n, n);
  grad.resize(n);
  for (unsigned q = 0; q < fe_values.n_quadrature_points; ++q) {
    for (unsigned i = 0; i < n; ++i) grad[i] = fe_values.shape_grad(i, q);
    const double JxW = fe_values.JxW(q);
    for (unsigned i = 0; i < n; ++i) {
      const unsigned ci = component[i];
      for (unsigned j = 0; j < n; ++j)
        Ke(i, j) += law.stiffness_entry(grad[i], grad[j], static_cast<int>(ci), static_cast<int>(component[j])) * JxW;
    }
  }
}

/// Any law of the table (total Lagrangian, dead loads): at each quadrature point
/// F = I + grad u, P = law.first_piola(F), C = law.tangent(F) (deformation_gradient.h's
/// index convention: dP_ab/dF_cd at row a + 3 b, column c + 3 d), and with the
/// shape function dN_i = e_ci (x) g_i (g_i = grad N_i):
///   Re_i = sum_q P : dN_i JxW = sum_q sum_d P_{ci d} g_i,d JxW,
///   Ke_ij = sum_q dN_i : C[dN_j] JxW = sum_q sum_{d,l} C_{ci + 3 d, cj + 3 l} g_i,d g_j,l JxW.
///   u_cell    #dofs_per_cell coefficients of the displacement on the cell
///   Ke        the tangent (if non-null), overwritten; Re the internal force, overwritten
/// Returns false (and leaves Ke, Re unspecified) where the law is undefined: det F
/// <= 0 at a quadrature point and the law not defined_when_inverted.
template <int dim>
bool hyperelastic_cell(const dealii::FEValues<dim>& fe_values, const std::vector<unsigned>& component,
                       const dealii::Vector<double>& u_cell, const MaterialLawInfo& law, const LameParameters& lame,
                       dealii::FullMatrix<double>* Ke, dealii::Vector<double>& Re,
                       std::vector<dealii::Tensor<1, dim>>& grad) {
  static_assert(dim == 3, "the material laws are three-dimensional");
  const unsigned n = fe_values.dofs_per_cell;
  if (Ke) Ke->reinit(n, n);
  Re.reinit(n);
  grad.resize(n);
  for (unsigned q = 0; q < fe_values.n_quadrature_points; ++q) {
    Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
    for (unsigned i = 0; i < n; ++i) {
      grad[i] = fe_values.shape_grad(i, q);
      for (unsigned d = 0; d < dim; ++d) F(component[i], d) += u_cell[i] * grad[i][d];
    }
    if (!law.defined_when_inverted && !(F.determinant() > 0)) return false;
    const Eigen::Matrix3d P = law.first_piola(F, lame);
    const double JxW = fe_values.JxW(q);
    for (unsigned i = 0; i < n; ++i) {
      double r = 0;
      for (unsigned d = 0; d < dim; ++d) r += P(component[i], d) * grad[i][d];
      Re[i] += r * JxW;
    }
    if (!Ke) continue;
    const Matrix9d C = law.tangent(F, lame);
    for (unsigned i = 0; i < n; ++i) {
      const unsigned ci = component[i];
      for (unsigned j = 0; j < n; ++j) {
        const unsigned cj = component[j];
        double k = 0;
        for (unsigned d = 0; d < dim; ++d)
          for (unsigned l = 0; l < dim; ++l) k += C(ci + 3 * d, cj + 3 * l) * grad[i][d] * grad[j][l];
        (*Ke)(i, j) += k * JxW;
      }
    }
  }
  return true;
}

/// The consistent nodal forces of a uniform force density b (N/m^3: rho g) over the
/// cell in the reference configuration (a dead load, eq. 10 with a volume integral):
///   fe_i = sum_q b_{ci} N_i(x_q) JxW_q = int_e b_{ci} N_i dV,
/// exact with a rule of degree >= the element's (P1: rho g V / 4 per node; P2:
/// -rho g V / 20 per vertex, rho g V / 5 per edge midpoint).
///   fe_values  reinit'ed on the cell, with update_values | update_JxW_values
///   fe         #dofs_per_cell, overwritten
template <int dim>
void body_force_cell(const dealii::FEValues<dim>& fe_values, const std::vector<unsigned>& component,
                     const Eigen::Vector3d& b, dealii::Vector<double>& fe) {
  const unsigned n = fe_values.dofs_per_cell;
  fe.reinit(n);
  for (unsigned q = 0; q < fe_values.n_quadrature_points; ++q) {
    const double JxW = fe_values.JxW(q);
    for (unsigned i = 0; i < n; ++i) fe[i] += b[component[i]] * fe_values.shape_value(i, q) * JxW;
  }
}

}  // namespace tb
