// The large-deformation reference: a hyperelastic solid of any law of the table
// (numerics/materials: neo_hookean, neo_hookean_isochoric, stable_neo_hookean, with
// the Lame parameters of the scenario's E and nu) under dead loads and prescribed
// displacements (tools), the body force included (a dead load: rho g over the
// reference configuration, ramped with the other loads), solved by Newton's method with the consistent tangent,
// load increments from the previous solve's load and tool values to this one's, a
// backtracking line search on the residual, and increments halved when Newton
// fails (J <= 0 somewhere, no residual decrease, or too many iterations). Each
// Newton system is solved by CG with an AMG hierarchy of the current tangent (it
// is symmetric positive definite at stable equilibria).
//
// Prescribed displacements, as in deal.II's step-44 tutorial (Pelteret and McBride,
// "The deal.II tutorial step-44: Three-field formulation for non-linear solid
// mechanics", 2012, Solid::make_constraints): an increment's first Newton step is taken
// from the last converged state with the increment of the prescribed values as
// inhomogeneous constraints (du = their increment on the held dofs, the tangent's
// coupling K_fp du_p moved to the right-hand side), which lands the held dofs on
// their new values with the interior following to first order; every later step
// is homogeneous (du = 0 on every constrained dof). Moving the held dofs alone,
// without the interior, would crush the layer of cells under a plate.
#include <deal.II/base/mpi.h>
#include <deal.II/fe/fe_values.h>

#include <algorithm>
#include <chrono>
#include <sstream>
#include <stdexcept>

#include "distributed_elasticity_impl.h"

namespace tb {
using namespace dealii;

namespace {

using Impl = DistributedElasticity::Impl;

/// The internal force F_int(u) (virtual work: sum_e int P : grad N_i) and the
/// tangent d.K = dF_int/du over the locally owned cells, distributed with
/// `constraints`: f_int = F_int - K_fc g on the free rows (g the constraints'
/// inhomogeneities, 0 on the constrained rows), K with the constrained rows and
/// columns replaced by a diagonal entry. With `full_norm`, also |F_int| over every
/// dof (the reactions included). Returns false on every rank if J <= 0 at a
/// quadrature point on any rank.
bool assemble(Impl& d, const Impl::Vector& u, const AffineConstraints<double>& constraints, Impl::Vector& f_int,
              double* full_norm = nullptr) {
  const Impl::Vector u_ghosted = d.ghosted(u);
  const unsigned n = d.fe.n_dofs_per_cell();
  FEValues<3> fe_values(d.mapping, d.fe, d.quadrature, update_gradients | update_JxW_values);
  FullMatrix<double> Ke;
  dealii::Vector<double> Re(n), u_cell(n);
  std::vector<Tensor<1, 3>> grad;
  std::vector<types::global_dof_index> ids(n);
  Impl::Vector full;
  if (full_norm) full.reinit(d.owned, d.comm);
  f_int = 0;
  d.K = 0;
  int valid = 1;
  for (const auto& cell : d.dof_handler.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    fe_values.reinit(cell);
    cell->get_dof_values(u_ghosted, u_cell);
    if (!hyperelastic_cell(fe_values, d.component, u_cell, *d.law, d.lame, &Ke, Re, grad)) {
      valid = 0;
      break;
    }
    cell->get_dof_indices(ids);
    constraints.distribute_local_to_global(Ke, Re, ids, d.K, f_int);
    if (full_norm) full.add(ids, Re);
  }
  // Every rank reaches the collective calls, whatever it found.
  f_int.compress(VectorOperation::add);
  d.K.compress(VectorOperation::add);
  if (full_norm) {
    full.compress(VectorOperation::add);
    *full_norm = full.l2_norm();
  }
  return Utilities::MPI::min(valid, d.comm) == 1;
}

}  // namespace

void DistributedElasticity::Impl::solve_nonlinear(const Vector& f_new, const std::vector<Eigen::Vector3d>& values) {
  const auto start = std::chrono::steady_clock::now();
  Vector f(owned, comm), f_int(owned, comm), residual(owned, comm), du(owned, comm), u_try(owned, comm);
  stats.cg_iterations = stats.newton_iterations = stats.load_increments = stats.increment_halvings = 0;
  // An increment's first step: the held dofs' constraints, inhomogeneous (set per
  // increment), the support's homogeneous.
  AffineConstraints<double> first_step;
  if (!groups.empty()) first_step.copy_from(zero_constraints);

  // Newton at external force f from `state`, whose groups are at `from`, to the
  // groups at `to`; true if converged (state is then the solution). The tangent is
  // assembled with the internal force at every trial point of the line search, so
  // an accepted step's K and R are the next iteration's.
  auto newton = [&](Vector& state, const std::vector<Eigen::Vector3d>& from, const std::vector<Eigen::Vector3d>& to) {
    std::vector<Eigen::Vector3d> step_values(groups.size());
    bool moved = false;
    for (size_t g = 0; g < groups.size(); ++g) {
      step_values[g] = to[g] - from[g];
      for (unsigned c = 0; c < 3; ++c) moved |= groups[g].components[c] && step_values[g][c] != 0;
    }
    if (moved) {
      // The inhomogeneity is minus the step: distribute_local_to_global then adds
      // K_fp dp to f_int, and f - f_int = f - F_int - K_fp dp is the right-hand side
      // of K_ff du_f = -R_f - K_fp dp.
      for (const HeldDof& h : held_relevant)
        first_step.set_inhomogeneity(h.dof, -step_values[static_cast<size_t>(h.group)][h.component]);
      if (!assemble(*this, state, first_step, f_int)) return false;
      residual = f;
      residual -= f_int;
      build_amg();
      du = 0;
      ++stats.newton_iterations;
      // Solved to cg_tolerance, not inexactly: the right-hand side is mostly the held
      // dofs' coupling K_fp dp, at nu near 1/2 hundreds of times the forces in play,
      // and a residual of 1e-2 relative to it is as large as those forces. Measured
      // on the Truth Cube's first frame (P2, neo-Hookean, nu = 0.499, a coarse mesh
      // of 5220 tets): 1e-2 took 8 CG iterations here, then 11 Newton iterations
      // with line searches (1496 CG iterations in all); 1e-10 took 289, then 3 full
      // Newton steps (606 in all).
      stats.cg_iterations += cg(residual, du, settings.cg_tolerance);
      zero_constraints.distribute(du);
      set_held(du, &step_values);
      state += du;
      set_held(state, &to);  // exactly, not from + (to - from) in floating point
    }
    double full_norm = 0;
    if (!assemble(*this, state, zero_constraints, f_int, &full_norm)) return false;
    // The scale of the forces in play: the external ones, or (under prescribed
    // displacements) the internal ones the first state carries (newton_solve.cc).
    const double scale = std::max({f.l2_norm(), full_norm, 1e-300});
    for (int it = 0;; ++it) {
      residual = f_int;
      residual -= f;
      const double r_norm = residual.l2_norm();
      if (r_norm <= settings.newton_tolerance * scale) return true;
      if (it == settings.max_newton_iterations) return false;
      ++stats.newton_iterations;
      build_amg();
      residual *= -1;
      du = 0;
      // Inexact Newton (Eisenstat-Walker style): each step solved to a tenth of
      // the current relative residual, at most 1e-2, at least cg_tolerance; the
      // answer's accuracy is set by newton_tolerance on |R|, not by CG.
      stats.cg_iterations += cg(residual, du, std::clamp(0.1 * r_norm / scale, settings.cg_tolerance, 1e-2));
      zero_constraints.distribute(du);
      // Converged also when the step no longer moves u (as newton_solve.cc): near rest
      // a law's stress is a difference of terms of the size of mu, which leaves |R| a
      // round-off floor that a small load's tolerance can sit below, and where no
      // step lowers |R| (measured: a 1 mN disc load on the small test cube, on one
      // CPU and not on another).
      if (du.l2_norm() <= settings.newton_tolerance * state.l2_norm()) {
        state += du;
        return true;
      }
      // Backtracking: the largest step 2^-k (k < 8) that keeps J > 0 and lowers |R|.
      bool accepted = false;
      for (double step = 1; step > 1.0 / 256 && !accepted; step /= 2) {
        u_try = state;
        u_try.add(step, du);
        if (!assemble(*this, u_try, zero_constraints, f_int)) continue;
        residual = f_int;
        residual -= f;
        accepted = residual.l2_norm() < r_norm;
      }
      if (!accepted) return false;
      state = u_try;
    }
  };

  // Increments from the previous load and group values (converged state u) to these.
  auto values_at = [&](double t) {
    std::vector<Eigen::Vector3d> v(groups.size());
    for (size_t g = 0; g < groups.size(); ++g) v[g] = t == 1 ? values[g] : (1 - t) * group_values[g] + t * values[g];
    return v;
  };
  double done = 0, increment = 1.0 / std::max(1, settings.load_steps);
  Vector state(u);
  std::vector<Eigen::Vector3d> state_values = group_values;
  while (done < 1) {
    double target = done + increment;
    if (target > 1 - 1e-12) target = 1;  // no sliver of an increment from rounding
    f = f_previous;
    f.sadd(1 - target, target, f_new);  // (1 - t) f_previous + t f_new
    const std::vector<Eigen::Vector3d> target_values = values_at(target);
    if (newton(state, state_values, target_values)) {
      u = state;
      state_values = target_values;
      done = target;
      ++stats.load_increments;
    } else {
      state = u;
      increment /= 2;
      if (++stats.increment_halvings > settings.max_increment_halvings) {
        std::ostringstream msg;
        msg << settings.law << ": Newton failed at load fraction " << target << " after "
            << settings.max_increment_halvings << " halvings of the load increment (last increment " << 2 * increment
            << "); a point load's singularity makes this likely on fine meshes (use a disc load), and so does a "
               "tool's step much larger than the cells it holds (use more frames or load_steps)";
        throw std::runtime_error(msg.str());
      }
    }
  }
  f_previous = f_new;
  stats.solve_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace tb
