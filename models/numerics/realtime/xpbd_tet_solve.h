// Volumetric XPBD with neo-Hookean tet constraints (Macklin and Mueller 2021, "A
// Constraint-based Formulation of Stable Neo-Hookean Materials", MIG 2021): per
// tet a deviatoric constraint C_D = sqrt(I1) with compliance 1 / (mu' V) and a
// hydrostatic one C_H = det F - alpha with compliance 1 / (lambda' V), whose
// energies sum to the xpbd_neo_hookean law (numerics/materials/xpbd_neo_hookean.h:
// the mapping of (E, nu) to mu', lambda' and the rest-stability shift alpha), each
// projected together by the XPBD update (Macklin, Mueller and Chentanez 2016,
// eqs. 17-18) written for the pair,
//   (S + diag(alpha~)) dlambda = -(C + alpha~ lambda),  alpha~ = alpha / h^2,
//   S_ij = sum_a w_a grad_a C_i . grad_a C_j,   x_a += w_a sum_i grad_a C_i dlambda_i,
// with grad_a C = (dC/dF) g_a,
// in sub-steps (Macklin, Storey, Lu, Terdiman, Chentanez, Jeschke and Mueller 2019,
// "Small Steps in Physics Simulation"), tets coloured so that a colour's tets
// (sharing no moving vertex) are projected in parallel. A held component has
// w = 0 and follows its tool linearly over the frame's sub-steps.
//
// Damping: v <- v / (1 + c h) per sub-step (mass-proportional, c in 1/s), so that a
// steady state exists; it does not change the steady state.
#pragma once

#include <memory>
#include <vector>

#include "elastic_solve.h"
#include "tet_time_stepping.h"

namespace tb {

struct XpbdTetSettings {
  TimeStepping stepping;
  int substeps = 20;    ///< sub-steps per frame
  int iterations = 1;   ///< sweeps over every tet colour per sub-step
  double damping = 20;  ///< c, 1/s
};

/// The model parameters of the XPBD tet solve (substeps, iterations, damping, and
/// time_step, threads).
std::vector<ParameterSpec> xpbd_tet_parameters();
XpbdTetSettings xpbd_tet_settings(const Parameters& p);

/// An XPBD tet solve on `body` (which outlives it), with the xpbd_neo_hookean law
/// of the body's material.
std::unique_ptr<ElasticSolve> make_xpbd_tet_solve(const ElasticBody& body, const XpbdTetSettings& settings);

}  // namespace tb
