// The large-deformation reference: a hyperelastic solid of any law of the table
// (numerics/materials: neo_hookean, neo_hookean_isochoric, stable_neo_hookean, with
// the Lame parameters of the scenario's E and nu) under dead loads, solved by Newton's method
// with the consistent tangent, load increments from the previous solve's load to
// this one, a backtracking line search on the residual, and increments halved
// when Newton fails (J <= 0 somewhere, no residual decrease, or too many
// iterations). Each Newton system is solved by CG with an AMG hierarchy of the
// current tangent (it is symmetric positive definite at stable equilibria).
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

/// Internal force F_int(u) (virtual work: sum_e int P : grad N_i) and the
/// tangent d.K = dF_int/du, over the locally owned cells. Returns false on every
/// rank if J <= 0 at a quadrature point on any rank.
bool assemble(DistributedElasticity::Impl& d, const DistributedElasticity::Impl::Vector& u,
              DistributedElasticity::Impl::Vector& f_int) {
  DistributedElasticity::Impl::Vector u_ghosted(d.owned, d.relevant, d.comm);
  u_ghosted = u;
  const unsigned n = d.fe.n_dofs_per_cell();
  FEValues<3> fe_values(d.mapping, d.fe, d.quadrature, update_gradients | update_JxW_values);
  FullMatrix<double> Ke;
  dealii::Vector<double> Re(n), u_cell(n);
  std::vector<Tensor<1, 3>> grad;
  std::vector<types::global_dof_index> ids(n);
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
    d.zero_constraints.distribute_local_to_global(Ke, Re, ids, d.K, f_int);
  }
  // Every rank reaches the collective calls, whatever it found.
  f_int.compress(VectorOperation::add);
  d.K.compress(VectorOperation::add);
  return Utilities::MPI::min(valid, d.comm) == 1;
}

}  // namespace

void DistributedElasticity::Impl::solve_nonlinear(const std::vector<LoadPoint>& load, const Eigen::Vector3d& force) {
  const auto start = std::chrono::steady_clock::now();
  Vector f_new(owned, comm);
  add_load(load, force, f_new);
  Vector f(owned, comm), f_int(owned, comm), residual(owned, comm), du(owned, comm), u_try(owned, comm);
  stats.cg_iterations = stats.newton_iterations = stats.load_increments = stats.increment_halvings = 0;

  // Newton at external force f from `state`; true if converged (state is then
  // the solution). The tangent is assembled with the internal force at every
  // trial point of the line search, so an accepted step's K and R are the next
  // iteration's.
  auto newton = [&](Vector& state) {
    const double f_norm = f.l2_norm();
    if (!assemble(*this, state, f_int)) return false;
    for (int it = 0;; ++it) {
      residual = f_int;
      residual -= f;
      const double r_norm = residual.l2_norm();
      if (r_norm <= settings.newton_tolerance * f_norm) return true;
      if (it == settings.max_newton_iterations) return false;
      ++stats.newton_iterations;
      build_amg();
      residual *= -1;
      du = 0;
      // Inexact Newton (Eisenstat-Walker style): each step solved to a tenth of
      // the current relative residual, at most 1e-2, at least cg_tolerance; the
      // answer's accuracy is set by newton_tolerance on |R|, not by CG.
      const double relative = f_norm > 0 ? r_norm / f_norm : 1.0;
      stats.cg_iterations += cg(residual, du, std::clamp(0.1 * relative, settings.cg_tolerance, 1e-2));
      zero_constraints.distribute(du);
      // Backtracking: the largest step 2^-k (k < 8) that keeps J > 0 and lowers |R|.
      bool accepted = false;
      for (double step = 1; step > 1.0 / 256 && !accepted; step /= 2) {
        u_try = state;
        u_try.add(step, du);
        if (!assemble(*this, u_try, f_int)) continue;
        residual = f_int;
        residual -= f;
        accepted = residual.l2_norm() < r_norm;
      }
      if (!accepted) return false;
      state = u_try;
    }
  };

  // Increments from the previous load (converged state u) to this one.
  double done = 0, increment = 1.0 / std::max(1, settings.load_steps);
  Vector state(u);
  while (done < 1) {
    double target = done + increment;
    if (target > 1 - 1e-12) target = 1;  // no sliver of an increment from rounding
    f = f_previous;
    f.sadd(1 - target, target, f_new);  // (1 - t) f_previous + t f_new
    if (newton(state)) {
      u = state;
      done = target;
      ++stats.load_increments;
    } else {
      state = u;
      increment /= 2;
      if (++stats.increment_halvings > settings.max_increment_halvings) {
        std::ostringstream msg;
        msg << settings.law << ": Newton failed at load fraction " << target << " after " << settings.max_increment_halvings
            << " halvings of the load increment (last increment " << 2 * increment
            << "); a point load's singularity makes this likely on fine meshes: use a disc load";
        throw std::runtime_error(msg.str());
      }
    }
  }
  f_previous = f_new;
  stats.solve_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace tb
