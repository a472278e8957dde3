// The PBD time step of paper 1.4-1.5 on a triangle surface: state (positions,
// velocities, inverse masses) and the constraint set of every kind of the table
// (constraint_kinds.h), projected by the batched SIMD sweep (constraint_batches.h)
// or one at a time by the kinds' reference projections. Shared by the pure PBD and
// the hybrid models.
#pragma once

#include <Eigen/Core>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "aligned_rows.h"
#include "constraint_batches.h"
#include "constraint_kinds.h"
#include "constraints.h"
#include "instruction_set.h"
#include "load_mapping.h"
#include "material.h"
#include "mesh_types.h"
#include "parameters.h"
#include "point_grid.h"
#include "thread_team.h"

namespace tb::pbd {

/// The PBD parameters common to the pbd and hybrid models, declared once; a
/// stiffness "<kind>_stiffness" for each kind of surface_constraint_kinds().
std::vector<ParameterSpec> parameter_specs();

/// Which implementation projects the constraints: the batched SIMD kernels
/// (projection_kernels.h) or the scalar reference written from the equations
/// (reference_projections.h), one constraint at a time in the same order.
enum class Kernels { Simd, Reference };

/// Where eq. (31) applies the load: the surface vertex nearest the load point (the
/// paper, section 1.4), or the nearest surface point, the force shared by its
/// triangle's vertices by barycentric weights (as the FEM's P1 load is).
enum class LoadSpread { NearestVertex, SurfaceTriangle };

/// How a frame's constraints are solved: PBD's projections with stiffnesses in
/// [0, 1] (paper 1.4), or XPBD (Macklin, Mueller, Chentanez 2016): a compliance per
/// constraint derived from the material (xpbd_compliance.h) and a Lagrange
/// multiplier per constraint accumulated over the (sub)step's iterations (reset each
/// sub-step), whose steady state does not depend on the iteration count. XPBD runs
/// with the reference kernels only.
enum class ConstraintSolve { Pbd, Xpbd };

struct Settings {
  double time_step = 0.01;  ///< s, per frame
  /// Sub-steps per frame (Macklin et al. 2019, "Small steps in physics simulation"):
  /// a frame runs `substeps` time steps of time_step / substeps, each with eqs.
  /// (31)-(35) and `iterations` sweeps. 1: the paper's step.
  int substeps = 1;
  int iterations = 10;  ///< Gauss-Seidel sweeps per (sub)step
  /// Each kind's stiffness in [0, 1] by kind name (parameter <name>_stiffness); a
  /// kind not named here has kDefaultStiffness. A kind with stiffness 0 is not swept.
  std::map<std::string, double> stiffness;
  static constexpr double kDefaultStiffness = 1;
  double stiffness_of(const std::string& kind) const;
  bool correct_stiffness = true;  ///< Mueller 2007: 1 - (1 - k)^(1/n)
  /// Fraction of velocity removed per (sub)step, after eq. (31) adds the force: a
  /// steady state applies (1 - damping) f whatever `substeps` is; a frame keeps
  /// (1 - damping)^substeps of its velocity.
  double damping = 0.05;
  BendingAngle bending_angle = BendingAngle::Unsigned;  ///< eq. (19) as in the paper
  LoadSpread load_spread = LoadSpread::NearestVertex;
  Kernels kernels = Kernels::Simd;
  int threads = 1;  ///< members sweeping each colour (Simd); the result does not depend on it
  /// Spatial domains of the sweep's order (domain_partition.h): 1, the colouring
  /// of every constraint (the paper's tables); more, each domain's constraints
  /// coloured, then the interface's, so that threads sweep whole domains between
  /// two barriers. Changes the Gauss-Seidel order, and with it PBD's steady state
  /// (10 sweeps do not converge; by how much: docs/scaling.md); the result still
  /// does not depend on the thread count.
  int domains = 1;
  /// The sweep's numbers (Simd): double, or single (the rest of the step stays double).
  Precision precision = Precision::Double;
  /// The sweep's vector instructions; none: best_instruction_set().
  std::optional<InstructionSet> instruction_set;
  ConstraintSolve constraint_solve = ConstraintSolve::Pbd;
  /// XPBD: the thickness h of the shell the surface stands for (m); 0: enclosed
  /// volume / area (volume_preserving_thickness).
  double shell_thickness = 0;
  /// XPBD: Young's modulus and Poisson's ratio of the compliances (density is not used here).
  Material material;
  static Settings from(const Parameters& p);
  /// from(p), with the material XPBD derives its compliances from.
  static Settings from(const Parameters& p, const Material& material);
};

/// Lumped masses: total mass = density x enclosed volume, shared among vertices in
/// proportion to one third of the area of their incident triangles.
///   returns #V masses (kg)
Eigen::VectorXd lumped_surface_masses(const SurfaceMesh& surface, double density);

class Solver {
 public:
  /// inverse_mass #V (0 = fixed: the clamped support and, in the hybrid, the
  /// control points, which the projection never moves); the constraints of each
  /// kind of `kinds`, projected in its order.
  Solver(const SurfaceMesh& rest, const Eigen::VectorXd& inverse_mass, const Settings& settings,
         const KindTable& kinds = surface_constraint_kinds());

  /// The external loads (eq. 31), each spread over vertices: vertex nodes(k) of
  /// load l receives weights(k) times load l's value. A set-up call; none by default.
  void set_loads(std::vector<NodalWeights> loads);
  const std::vector<NodalWeights>& loads() const { return loads_; }

  /// One frame: Settings::substeps steps of h = time_step / substeps, each: the
  /// loads' forces (set_loads, with these values): eq. (31) velocities, damping, eq.
  /// (32) prediction, then positions of `pinned` vertices set to `pinned_positions`
  /// (eq. 33; may be empty; the same positions in every sub-step), the Gauss-Seidel
  /// projection (XPBD: the multipliers start from 0), and eqs. (34)-(35).
  ///   load_values       #loads values (N, or m/s^2 for a load weighted by masses)
  ///   pinned            #P vertex indices (must have inverse mass 0)
  ///   pinned_positions  #P by 3 positions for this frame
  void step(const std::vector<Eigen::Vector3d>& load_values, const std::vector<int>& pinned,
            const Points& pinned_positions);

  /// Rigid spheres the surface may not enter during the following step()s: a
  /// collision constraint C(p) = |p - c| - r >= 0 per surface vertex (Mueller et al.
  /// 2007, "Position based dynamics", sec. 3.5), projected after every Gauss-Seidel
  /// sweep on the vertices a grid query returns near each sphere (docs/equations.md,
  /// "Contact with a rigid sphere"). With a sphere the sweeps run on this thread, one
  /// at a time. No allocation once the number of spheres is set.
  ///   centres  #S by 3 (m), radii #S (m)
  void set_spheres(const Points& centres, const Eigen::VectorXd& radii);
  /// After step(), per sphere: the force the surface exerts on it (N), -sum_v m_v
  /// dp_v / h^2 over the vertices v it moved, dp_v the vertex's total collision
  /// correction in a sub-step of h, averaged over the frame's sub-steps: the force
  /// that would change the vertices' momentum by what the projection changed it.
  const std::vector<Eigen::Vector3d>& sphere_forces() const { return sphere_force_; }
  /// A vertex is in contact with a sphere of radius r at the end of a frame when it
  /// is within this fraction of r of the sphere's surface, or inside it.
  static constexpr double kSphereContactTolerance = 0.01;
  /// After step(), per sphere: the vertices in contact at the end of the frame (those
  /// the grid query returned within kSphereContactTolerance r of its surface or
  /// inside; not only those the last sweep moved), ascending, and how deep the
  /// deepest vertex is inside it (m).
  const std::vector<std::vector<int>>& sphere_contacts() const { return sphere_contact_; }
  const std::vector<double>& sphere_penetration() const { return sphere_depth_; }
  /// The vertices the last step() tested against each sphere (the grid query).
  const std::vector<std::vector<int>>& sphere_candidates() const { return sphere_candidates_; }

  /// Measures, in the following step()s, the force the surface exerts on groups of
  /// pinned vertices (a tool's, the support's): group_of_vertex[v] in [0, groups)
  /// for a vertex of a group (it must have inverse mass 0), -1 for the others. A
  /// set-up call (allocates); no cost to a step when no group has a constraint
  /// reaching a free vertex.
  void set_reaction_groups(const std::vector<int>& group_of_vertex, int groups);
  /// After step(), per group: the force the surface exerts on its pinned vertices
  /// (N), F_g = -sum_c sum_j m_j dp_cj / h^2 + f_g: the momentum every constraint c
  /// joining the group to free vertices j gave them over the frame's Gauss-Seidel
  /// sweeps (the pinned vertex took the opposite; Newton's third law, the
  /// constraints being translation invariant), per sub-step of h and averaged over
  /// the sub-steps, plus f_g, the loads' shares on the group's own vertices (which
  /// the pins hold). At rest the sweeps undo exactly what the loads predicted,
  /// (1 - damping) h^2 f / m per free vertex, so the groups' forces sum to
  /// (1 - damping) times the loads on free vertices plus f_g: PBD's damping takes
  /// its share of the load (docs/equations.md, "Reactions in PBD").
  const std::vector<Eigen::Vector3d>& group_forces() const { return group_force_; }

  const Points& positions() const { return x_; }
  const Points& rest_positions() const { return rest_; }
  const ConstraintSet& constraints() const { return c_; }
  /// The vector instructions the projection runs with (the results do not depend on it).
  InstructionSet instruction_set() const { return isa_; }
  /// Run the projection with `isa` instead of the best this CPU has (repacks the
  /// batches when their width changes: a set-up call, it allocates).
  void use_instruction_set(InstructionSet isa);
  const Settings& settings() const { return s_; }
  /// Time (ms) the last step() spent in the projection (eq. 33 and the sweeps) and
  /// in the rest of the time step (eqs. 31-32, 34-35), summed over its sub-steps.
  double last_projection_ms() const { return projection_ms_; }
  double last_integration_ms() const { return integration_ms_; }
  /// What the projection ran with, for run.json: {"instruction_set": "avx512" | "avx512vl" |
  /// "avx" | "sse2" | "scalar" (reference kernels), "lanes": per batch, "precision",
  /// "threads", "constraint_solve": "pbd" | "xpbd"}, and with xpbd
  /// "shell_thickness_m" (as used) and the stiffness range of each kind
  /// ("<kind>_stiffness_<unit>": stretch N_per_m, bending N_m).
  nlohmann::json details() const;
  /// XPBD: the per-constraint compliances alpha of the kind named `kind` (stretch
  /// m/N, bending 1/(N m)), one per row of its constraints, and its Lagrange
  /// multipliers of the last (sub)step; empty for PBD.
  const Eigen::VectorXd& compliance(const std::string& kind) const { return alpha_[kind_index(kind)]; }
  const Eigen::VectorXd& multipliers(const std::string& kind) const { return lambda_[kind_index(kind)]; }
  /// XPBD: the shell thickness the compliances were derived with (m); 0 for PBD.
  double shell_thickness() const { return thickness_; }

 private:
  Points rest_, x_, v_;
  std::vector<NodalWeights> loads_;  // set_loads
  // The predicted positions the projection moves, in double (p_) or, for a
  // single-precision sweep, in float (q_); the other one is empty.
  PaddedPositions p_;
  PaddedRows<float> q_;
  Eigen::VectorXd w_;
  ConstraintSet c_;
  Settings s_;
  InstructionSet isa_;
  std::vector<int> domain_;  // each vertex's sweep domain (Settings::domains; all 0 for one)
  /// Each vertex's row in p_ and q_: domain by domain, so that the domains a thread
  /// sweeps are contiguous in memory (interleaved rows put cache lines under two
  /// threads' writes: measured slower on two threads than on one). Empty: row = vertex.
  std::vector<int> row_of_;
  ConstraintBatches batches_;         // c_ ordered and packed for the sweep, on rows of p_
  std::vector<double> k_;             // each kind's stiffness per iteration (Mueller 2007), in c_'s order
  std::unique_ptr<ThreadTeam> team_;  // null with one thread
  double projection_ms_ = 0, integration_ms_ = 0;
  // XPBD (empty for PBD), per kind of c_ and constraint row: compliances, alpha / h^2
  // (h the sub-step), and the multipliers.
  std::vector<Eigen::VectorXd> alpha_, alpha_tilde_, lambda_;
  double thickness_ = 0;
  // Spheres (set_spheres): a grid of the rest positions (built on the first call),
  // the largest displacement from rest after the last step (widens the query), and
  // per sphere its candidates, contacts, force and depth.
  Points sphere_centre_;
  Eigen::VectorXd sphere_radius_;
  std::unique_ptr<PointGrid> grid_;
  double max_displacement_ = 0;
  std::vector<std::vector<int>> sphere_candidates_, sphere_contact_;
  std::vector<Eigen::Vector3d> sphere_force_, sphere_dp_;
  std::vector<double> sphere_depth_;
  // Reaction groups (set_reaction_groups): each vertex's group, each kind's records
  // for the current packing (empty: none), each group's force after a step.
  std::vector<int> group_of_vertex_;
  std::vector<CorrectionRecord> records_;
  std::vector<Eigen::Vector3d> group_force_;
  /// records_ for batches_ (after a repacking), or none when no kind has one.
  void record_groups();
  /// What a sweep sums: records_, or null when there is none.
  std::vector<CorrectionRecord>* records() { return records_.empty() ? nullptr : &records_; }
  /// Every sphere's projection on its candidates (positions S: double or float
  /// rows); `dp` accumulates each sphere's total correction x mass.
  template <class S>
  void project_spheres(S* rows);
  /// The position of the kind named `kind` in c_ (std::invalid_argument if none).
  size_t kind_index(const std::string& kind) const;
  /// c_ and w_ on rows of p_ (row_of_), ordered and packed in `width` lanes.
  ConstraintBatches pack_batches(int width) const;
  /// The row of p_ holding vertex v.
  Eigen::Index row(Eigen::Index v) const { return row_of_.empty() ? v : row_of_[static_cast<size_t>(v)]; }
  /// One time step of h (eqs. 31-35), timed into projection_ms_ and integration_ms_.
  void substep(double h, const std::vector<Eigen::Vector3d>& load_values, const std::vector<int>& pinned,
               const Points& pinned_positions);
  /// body(begin, end) on vertex ranges covering [0, #V), one per team member (in
  /// parallel), or once over all of them without a team. The per-vertex work must
  /// not depend on the range, so that the result does not depend on the thread count.
  template <class RangeBody>
  void for_vertex_ranges(RangeBody&& body);
  /// One scalar Gauss-Seidel sweep in the batches' order (reversed if asked), kind by
  /// kind: the kinds' reference projections (PBD; a kind with stiffness 0 skipped)
  /// or their XPBD updates (every kind).
  void scalar_sweep(bool reverse, bool xpbd);
};

}  // namespace tb::pbd

namespace tb::pbd {

/// Inverse masses from lumped_surface_masses, 0 where `fixed` is set.
///   fixed  #V flags
Eigen::VectorXd inverse_masses(const SurfaceMesh& surface, double density, const std::vector<char>& fixed);

}  // namespace tb::pbd
