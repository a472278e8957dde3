// Vertex Block Descent (Chen, Liu, Yang and Yuksel 2024, "Vertex Block Descent",
// ACM TOG 43(4) 116): each frame one implicit-Euler step, the incremental
// potential
//   G(x) = sum_i m_i / (2 h^2) |x_i - y_i|^2 + sum_t V_t W(F_t(x)),
//   y_i = x_n,i + h v_n,i + h^2 f_i / m_i,
// minimised by block coordinate descent: vertex by vertex, one Newton step on the
// vertex's own 3x3 block with the others held (their section 3, "local system"),
//   H_i dx_i = -(m_i / h^2 (x_i - y_i) + sum_{t at i} V_t P(F_t) g_t,i),
//   H_i = m_i / h^2 I + sum_{t at i} V_t node_stiffness(F_t, g_t,i),
// vertices coloured so that a colour's vertices (sharing no tet) move in parallel.
// A fixed point of the sweeps is the step's minimiser, so, for a start that is x_n
// once the body is at rest (the last positions; the adaptive start), the steady state
// is the static equilibrium of the law whatever the iteration count; iterations decide
// how close a frame gets to the implicit-Euler step (docs/realtime_nonlinear.md). From
// the inertial target the sweeps must carry the iterate back to x_n, and the steady
// state is off the equilibrium by what `iterations` sweeps leave unconverged.
// Optional damping (VbdSettings::damping) vanishes at rest and leaves that unchanged.
//
// The law is any of numerics/materials (the VBD paper uses stable neo-Hookean). For
// a law undefined at det F <= 0 (neo_hookean) a vertex's step is halved until its
// tets stay positive, so a frame that starts valid stays valid; where the tools'
// move would invert a tet beside a held node, the held nodes advance in stages, each
// followed by the sweeps (vbd_solve.cc, move_held_in_stages).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "elastic_solve.h"
#include "tet_time_stepping.h"

namespace tb {

/// How a frame's iterate starts (Chen et al. 2024, "initialization").
enum class VbdStart {
  Previous,  ///< x_n
  Inertial,  ///< y, the inertial target
  Adaptive,  ///< x_n + h v_n + h^2 a~, a~ the last step's acceleration along the external one, clamped (the paper's)
};

/// How a vertex's tets are summed: four at a time in vector lanes (vbd_visit_blocks.h)
/// with AVX2 and FMA or with SSE2, or one at a time. Auto: the lanes with the best of
/// the two this CPU has, for a law that offers them (lane_node_terms: neo_hookean),
/// else one at a time.
enum class VbdKernels { Auto, Avx2, Sse2, Scalar };

struct VbdSettings {
  TimeStepping stepping;
  std::string law = "neo_hookean";
  int iterations = 20;       ///< sweeps over every colour per frame
  double chebyshev_rho = 0;  ///< > 0: Chebyshev semi-iterative acceleration with this spectral radius estimate
  /// k_d (s): Chen et al. 2024's damping ("Damping"), the vertex's elastic block H_e
  /// as a force -(k_d / h) H_e (x - x_n) and a stiffness (k_d / h) H_e in its Newton
  /// system. Zero at rest (x = x_n), so the steady state is unchanged; the block is
  /// the vertex's own only, so it also resists a rigid motion of the vertex's tets.
  double damping = 0;
  VbdStart start = VbdStart::Adaptive;
  VbdKernels kernels = VbdKernels::Auto;
};

/// The model parameters of a VBD solve (material_law, iterations, chebyshev_rho,
/// start, kernels, and time_step, threads).
std::vector<ParameterSpec> vbd_parameters();
VbdSettings vbd_settings(const Parameters& p);

/// The kernels a solve runs: `asked`, or for Auto the best that `cpu_has_avx2` (AVX2
/// and FMA) and the law allow (`law_has_lanes`: the law offers lane node terms and
/// the solve keeps det F positive, as the lanes' kernel assumes). Throws
/// std::invalid_argument, naming `law`, for lanes the CPU or the law does not have.
/// A function of its arguments alone, so the no-AVX2 path is testable on any CPU.
VbdKernels choose_vbd_kernels(VbdKernels asked, bool law_has_lanes, const std::string& law, bool cpu_has_avx2);

/// A VBD solve on `body` (which outlives it). Throws std::invalid_argument for an
/// unusable setting; its solve() throws std::runtime_error when the tools' positions
/// leave a tet the law cannot take even in 64 stages (a tool moved a node through
/// a clamped one).
std::unique_ptr<ElasticSolve> make_vbd_solve(const ElasticBody& body, const VbdSettings& settings);

}  // namespace tb
