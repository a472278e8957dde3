// Projective Dynamics (Bouaziz, Martin, Liu, Kavan and Pauly 2014, "Projective
// dynamics: fusing constraint projections for fast simulation", ACM TOG 33(4) 154)
// and its quasi-Newton extension to any hyperelastic law (Liu, Bouaziz and Kavan
// 2017, "Quasi-Newton methods for real-time simulation of hyperelastic materials",
// ACM TOG 36(3) 23) on a body's P1 tets: each frame one implicit-Euler step, the
// minimiser of the incremental potential
//   E(x) = 1/(2 h^2) |x - y|_M^2 + sum_t V_t W(F_t(x)),   y = x_n + h v_n + h^2 M^-1 f,
// (the variational implicit Euler both papers start from) with the lumped mass M
// and the held components of the tools and the support fixed (Dirichlet).
//
// The global matrix of Bouaziz et al.'s global step, factorised once in setup:
//   A = M / h^2 + sum_t w V_t G_t^T G_t,
// G_t the tet's deformation-gradient operator (tet_element.h). G_t^T G_t acts on
// each coordinate alike, so A = (M/h^2 + L_w) (x) I_3 with L_w the scalar weighted
// Laplacian of the tets, and the held components only remove rows: A is three
// decoupled n-by-n systems, one per coordinate, each restricted to that
// coordinate's free nodes. One CHOLMOD factor serves every coordinate whose free
// nodes are the same (a clamp or a grasp holds all three; a sliding plate holds one,
// and gets a factor of its own): a third of the dofs, about a ninth of the 3n
// system's factor nonzeros, and each solve a ninth of its work.
//
// Both modes iterate x <- x + alpha d with d from A^-1 and the gradient
//   grad E = M / h^2 (x - y) + sum_t V_t G_t^T vec(P(F_t))   (free components),
// which is the PD global step written as a correction: for an energy of PD's form,
// W = sum_i w_i/2 |F - p_i(F)|^2, grad E = A x - b(p(x)), so x - A^-1 grad E(x) =
// A^-1 b(p(x)), Bouaziz et al.'s global solve after the local projections p (the
// observation Liu et al. 2017 build on: PD is a quasi-Newton method with the
// constant Hessian approximation A); written so, the held components need no lifting.
//   - local_global: alpha = 1, d = -A^-1 grad E, the law `arap_volume`
//     (numerics/materials/arap_volume.h), whose energy is exactly PD's: per tet the
//     projection onto the rotations (weight 2 mu) and onto det F = 1 (weight
//     3 lambda), A's weight w their sum, so the iteration is Bouaziz et al.'s local
//     and global steps, which decrease E monotonically (Bouaziz et al. 2014).
//   - quasi_newton: L-BFGS (Liu et al. 2017; the two-loop recursion of Nocedal and
//     Wright 2006, Algorithm 7.4) with A^-1 as the initial inverse Hessian and `history` pairs,
//     a backtracking line search on E (Armijo, c = 1e-4, halving); any law of the
//     table; for a law undefined at det F <= 0 (neo_hookean) E is +infinity there,
//     so every accepted iterate keeps every tet positive; where the tools' move
//     alone would invert a tet, the held nodes advance in stages, each relaxed
//     (TetTimeStepper::move_held_in_stages, as VBD). A's weight w is a
//     parameter (`weight`): 2 mu (the shear stiffness), 2 mu + lambda (the
//     P-wave modulus, the default) or 2 mu + 3 lambda (a dilatation's stiffness).
// Both stop early when |grad E| over the free components falls below `tolerance`
// times its value at the frame's first iterate, or below its rounding floor (1e-14
// of w sqrt(3) times the nodes' sums of V_t |grad N|: else, at rest, L-BFGS pairs
// made of rounding noise would move the body).
//
// The per-tet stress and energy (the local step) and the per-node gradient run on
// the thread team (one class of all tets, then one of all nodes; each item writes
// its own slot and a node sums its tets in a fixed order), the energy is summed
// over the tets in order, the solves and the L-BFGS products are serial: the
// answer does not depend on the thread count.
#pragma once

#include <memory>
#include <string>

#include "elastic_solve.h"
#include "tet_time_stepping.h"

namespace tb {

enum class PdMode { LocalGlobal, QuasiNewton };

/// What A's weight w is per unit volume (quasi_newton; local_global takes its law's).
enum class PdWeight {
  Shear,       ///< 2 mu, Bouaziz et al. 2014's ARAP weight
  Longitudinal,  ///< 2 mu + lambda, the P-wave modulus: a uniaxial strain's stiffness at rest
  Volume,      ///< 2 mu + 3 lambda, a dilatation's stiffness at rest (arap_volume's w)
};

struct PdSettings {
  TimeStepping stepping;
  PdMode mode = PdMode::QuasiNewton;
  std::string law = "neo_hookean";
  int iterations = 10;      ///< global solves (each with its local step) per frame, at most
  int history = 5;          ///< L-BFGS pairs (quasi_newton)
  double tolerance = 1e-6;  ///< stop when |grad E| <= tolerance |grad E at the frame's first iterate|
  PdWeight weight = PdWeight::Longitudinal;  ///< the fastest of the three on the small cube (docs/realtime_nonlinear.md)
};

/// The model parameters of a PD solve (solve, material_law, iterations, history,
/// tolerance, weight, and time_step, threads).
std::vector<ParameterSpec> pd_parameters();
PdSettings pd_settings(const Parameters& p);

/// A PD solve on `body` (which outlives it). Throws std::invalid_argument, "pd: "
/// and the parameter, for an unusable setting (local_global with a law other than
/// arap_volume); its solve() throws std::runtime_error when the tools' positions
/// leave a tet the law cannot take even in 64 stages.
std::unique_ptr<ElasticSolve> make_pd_solve(const ElasticBody& body, const PdSettings& settings);

}  // namespace tb
