#include "pbd_solver.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "constraints.h"
#include "domain_partition.h"
#include "mesh_checks.h"
#include "xpbd_compliance.h"

namespace tb::pbd {
namespace {

/// The rows of vertices ordered domain by domain (by vertex within a domain):
/// result[v] is vertex v's row.
std::vector<int> rows_by_domain(const std::vector<int>& domain) {
  std::vector<int> vertices(domain.size());
  std::iota(vertices.begin(), vertices.end(), 0);
  std::stable_sort(vertices.begin(), vertices.end(),
                   [&](int a, int b) { return domain[static_cast<size_t>(a)] < domain[static_cast<size_t>(b)]; });
  std::vector<int> row(domain.size());
  for (size_t r = 0; r < vertices.size(); ++r) row[static_cast<size_t>(vertices[r])] = static_cast<int>(r);
  return row;
}

/// inverse_mass, checked to have one entry per vertex before the constraint
/// batches index it.
const Eigen::VectorXd& one_per_vertex(const Eigen::VectorXd& inverse_mass, Eigen::Index vertex_count) {
  if (inverse_mass.size() != vertex_count) throw std::invalid_argument("inverse masses: one per vertex expected");
  return inverse_mass;
}

/// The domains' work per vertex: 1 for a free vertex, 0 for a fixed one (the
/// constraints among fixed vertices are dropped, so they cost nothing).
std::vector<double> free_vertices(const Eigen::VectorXd& inverse_mass) {
  std::vector<double> work(static_cast<size_t>(inverse_mass.size()));
  for (Eigen::Index v = 0; v < inverse_mass.size(); ++v) work[static_cast<size_t>(v)] = inverse_mass(v) > 0 ? 1 : 0;
  return work;
}

}  // namespace

std::vector<ParameterSpec> parameter_specs() {
  using P = ParameterSpec;
  const Settings d;  // each default stated once, in Settings
  auto name_of = [](bool first, const char* a, const char* b) { return first ? a : b; };
  std::vector<ParameterSpec> specs = {
      P::number("time_step", d.time_step, 1e-6, 1.0, "time step per frame, s"),
      P::whole_number("substeps", d.substeps, 1, 1000,
                      "sub-steps per frame (Macklin et al. 2019): each frame runs this many steps of "
                      "time_step / substeps, each with eqs. (31)-(35) and `iterations` sweeps (pinned control points "
                      "held at the frame's positions); 1: the paper's step"),
      P::whole_number("iterations", d.iterations, 1, 1000, "Gauss-Seidel projection sweeps per (sub)step"),
  };
  for (const ConstraintKind* kind : surface_constraint_kinds())
    specs.push_back(P::number(kind->stiffness_parameter(), Settings::kDefaultStiffness, 0.0, 1.0,
                              std::string(kind->name) + " constraint stiffness k in [0, 1]"));
  const std::vector<ParameterSpec> rest = {
      P::choice("stiffness_correction", {"mueller2007", "none"}, name_of(d.correct_stiffness, "mueller2007", "none"),
                "mueller2007: per-iteration stiffness 1-(1-k)^(1/n); none: k as given"),
      P::number("damping", d.damping, 0.0, 1.0,
                "fraction of each vertex velocity removed per (sub)step, after eq. (31) adds the force (a steady "
                "state applies (1 - damping) f whatever substeps is)"),
      P::choice("bending_angle", {"unsigned", "signed"},
                name_of(d.bending_angle == BendingAngle::Unsigned, "unsigned", "signed"),
                "unsigned: the paper's eq. (19), arccos(n1.n2) - phi0 (kinked where a pair passes through flat); "
                "signed: theta - theta0, smooth there"),
      P::choice("load_spread", {"nearest_vertex", "surface_triangle"},
                name_of(d.load_spread == LoadSpread::NearestVertex, "nearest_vertex", "surface_triangle"),
                "where eq. (31) applies the load: nearest_vertex, the surface vertex nearest the load point (the "
                "paper); surface_triangle, the nearest surface point, the force shared by its triangle's vertices "
                "by barycentric weights (as the FEM's P1 load)"),
      P::choice(
          "kernels", {"simd", "reference"}, name_of(d.kernels == Kernels::Simd, "simd", "reference"),
          "simd: the batched vector kernels (projection_kernels.h); reference: the scalar projections written "
          "from eqs. (14)-(30) (reference_projections.h), one constraint at a time in the same order, one thread"),
      P::whole_number("threads", d.threads, 1, 64,
                      "threads sweeping each colour's constraints (the result does not depend on it)"),
      P::whole_number("domains", d.domains, 1, 64,
                      "spatial domains of the sweep order: 1, every constraint coloured (the paper's tables); n, the "
                      "surface bisected into n domains, each swept whole by one thread, then the constraints across "
                      "domains colour by colour: far fewer barriers (use with threads > 1). Changes the Gauss-Seidel "
                      "order, and with it the unconverged PBD steady state (by how much: docs/scaling.md)"),
      P::choice("precision", {"double", "single"}, name_of(d.precision == Precision::Double, "double", "single"),
                "the sweep's numbers: double; or single (floats, twice the lanes per vector; the steady state differs "
                "from double's by rounding, docs/scaling.md)"),
      P::choice("instruction_set", {"auto", "sse2", "avx", "avx512vl", "avx512"}, "auto",
                "the sweep's vector instructions; auto: avx512vl (256-bit vectors, 32 registers) where the CPU has "
                "it, else avx, else sse2 (avx512, 512-bit, measured slower on "
                "this project's AMD EPYC: only when asked); double precision gives the same numbers on every one"),
      P::choice(
          "constraint_solve", {"pbd", "xpbd"}, name_of(d.constraint_solve == ConstraintSolve::Pbd, "pbd", "xpbd"),
          "pbd: the paper's projections with stretch_stiffness and bending_stiffness in [0, 1]; xpbd: Macklin, "
          "Mueller, Chentanez 2016, compliance per constraint from the material (stretch k = E h A_e / L_e^2, "
          "bending k = 3 D L_e^2 / A_e with D = E h^3 / (12 (1 - nu^2)); models/numerics/pbd/xpbd_compliance.h) and "
          "Lagrange multipliers accumulated over the frame's iterations; needs kernels 'reference', "
          "bending_angle 'signed' and the stiffnesses at 1"),
      P::number("shell_thickness", d.shell_thickness, 0.0, 10.0,
                "xpbd: thickness h of the shell the surface stands for, m; 0: the body's enclosed volume / surface "
                "area (a shell holding the body's volume; 1/6 of the side of a cube)"),
  };
  specs.insert(specs.end(), rest.begin(), rest.end());
  return specs;
}

double Settings::stiffness_of(const std::string& kind) const {
  const auto found = stiffness.find(kind);
  return found == stiffness.end() ? kDefaultStiffness : found->second;
}

Settings Settings::from(const Parameters& p) {
  Settings s;
  s.time_step = p.number("time_step");
  s.substeps = p.integer("substeps");
  s.iterations = p.integer("iterations");
  for (const ConstraintKind* kind : surface_constraint_kinds())
    s.stiffness[kind->name] = p.number(kind->stiffness_parameter());
  s.correct_stiffness = p.choice("stiffness_correction") == "mueller2007";
  s.damping = p.number("damping");
  s.bending_angle = p.choice("bending_angle") == "signed" ? BendingAngle::Signed : BendingAngle::Unsigned;
  s.load_spread =
      p.choice("load_spread") == "surface_triangle" ? LoadSpread::SurfaceTriangle : LoadSpread::NearestVertex;
  s.kernels = p.choice("kernels") == "reference" ? Kernels::Reference : Kernels::Simd;
  s.threads = p.integer("threads");
  s.domains = p.integer("domains");
  s.precision = p.choice("precision") == "single" ? Precision::Single : Precision::Double;
  const std::string& isa = p.choice("instruction_set");
  if (isa != "auto")
    for (InstructionSet candidate : kInstructionSets)
      if (isa == name(candidate)) s.instruction_set = candidate;
  if (s.kernels == Kernels::Reference && s.threads != 1)
    throw std::invalid_argument(
        "PBD parameters: kernels 'reference' runs on one thread (threads = " + std::to_string(s.threads) + " given)");
  if (s.kernels == Kernels::Reference && s.precision != Precision::Double)
    throw std::invalid_argument("PBD parameters: kernels 'reference' runs in double precision");
  s.constraint_solve = p.choice("constraint_solve") == "xpbd" ? ConstraintSolve::Xpbd : ConstraintSolve::Pbd;
  s.shell_thickness = p.number("shell_thickness");
  if (s.constraint_solve == ConstraintSolve::Xpbd) {
    if (s.kernels != Kernels::Reference)
      throw std::invalid_argument(
          "PBD parameters: constraint_solve 'xpbd' is implemented in the scalar reference projections only: "
          "set kernels 'reference' (the SIMD kernels have no XPBD update)");
    // The multiplier of C = |theta| - |theta0| changes meaning when theta changes
    // sign within a frame: on the paper cube (flat pairs at rest) the unsigned angle
    // reached no steady state where the signed one did (docs/xpbd.md).
    if (s.bending_angle != BendingAngle::Signed)
      throw std::invalid_argument(
          "PBD parameters: constraint_solve 'xpbd' needs bending_angle 'signed' (its multipliers accumulate "
          "over a frame, and |theta| flips its gradient where a pair passes through flat)");
    std::string stiffnesses;  // "stretch_stiffness and bending_stiffness"
    bool all_one = true;
    for (const ConstraintKind* kind : surface_constraint_kinds()) {
      stiffnesses += (stiffnesses.empty() ? "" : " and ") + kind->stiffness_parameter();
      all_one = all_one && s.stiffness_of(kind->name) == 1;
    }
    if (!all_one)
      throw std::invalid_argument("PBD parameters: constraint_solve 'xpbd' derives its stiffness from the material: " +
                                  stiffnesses + " must stay 1 (set shell_thickness or the material instead)");
  } else if (s.shell_thickness != 0) {
    throw std::invalid_argument("PBD parameters: shell_thickness applies to constraint_solve 'xpbd' only");
  }
  return s;
}

Settings Settings::from(const Parameters& p, const Material& material) {
  Settings s = from(p);
  s.material = material;
  return s;
}

Eigen::VectorXd lumped_surface_masses(const SurfaceMesh& s, double density) {
  Eigen::VectorXd area = Eigen::VectorXd::Zero(s.V.rows());
  double total_area = 0;
  for (Eigen::Index t = 0; t < s.F.rows(); ++t) {
    const Eigen::Vector3d a = s.V.row(s.F(t, 0)), b = s.V.row(s.F(t, 1)), c = s.V.row(s.F(t, 2));
    const double A = 0.5 * (b - a).cross(c - a).norm();
    for (int k = 0; k < 3; ++k) area(s.F(t, k)) += A / 3;
    total_area += A;
  }
  return area * (density * enclosed_volume(s) / total_area);
}

Solver::Solver(const SurfaceMesh& rest, const Eigen::VectorXd& inverse_mass, const Settings& settings,
               const KindTable& kinds)
    : rest_(rest.V),
      x_(rest.V),
      v_(Points::Zero(rest.V.rows(), 3)),
      p_(settings.precision == Precision::Single ? 0 : rest.V.rows()),
      q_(settings.precision == Precision::Single ? rest.V.rows() : 0),
      w_(one_per_vertex(inverse_mass, rest.V.rows())),
      c_(build_constraints(rest, kinds)),
      s_(settings),
      isa_(s_.instruction_set.value_or(best_instruction_set())),
      domain_(bisect_into_domains(rest.V, s_.domains, free_vertices(w_))),
      row_of_(s_.domains > 1 ? rows_by_domain(domain_) : std::vector<int>{}),
      batches_(pack_batches(batch_width(isa_, s_.precision))) {
  if (!cpu_supports(isa_))
    throw std::invalid_argument(std::string("PBD solver: instruction_set ") + name(isa_) + " is not on this CPU");
  for (const KindConstraints& kind : c_.kinds) {
    const double k = s_.stiffness_of(kind.kind->name);
    k_.push_back(s_.correct_stiffness ? stiffness_per_iteration(k, s_.iterations) : k);
  }
  if (s_.threads < 1) throw std::invalid_argument("PBD solver: threads must be at least 1");
  if (s_.substeps < 1)
    throw std::invalid_argument("PBD solver: substeps must be at least 1 (" + std::to_string(s_.substeps) + " given)");
  if (s_.kernels == Kernels::Reference && (s_.threads != 1 || s_.precision != Precision::Double))
    throw std::invalid_argument("PBD solver: the reference kernels run on one thread in double precision");
  if (s_.threads > 1) team_ = std::make_unique<ThreadTeam>(s_.threads);
  if (s_.constraint_solve == ConstraintSolve::Xpbd) {
    if (s_.kernels != Kernels::Reference || s_.bending_angle != BendingAngle::Signed)
      throw std::invalid_argument("PBD solver: XPBD runs with the reference kernels and the signed bending angle");
    thickness_ = s_.shell_thickness > 0 ? s_.shell_thickness : volume_preserving_thickness(rest);
    const double h = s_.time_step / s_.substeps, h2 = h * h;
    const ShellMaterial shell{s_.material.youngs_modulus, s_.material.poisson_ratio, thickness_};
    for (const KindConstraints& kind : c_.kinds) {
      alpha_.push_back(kind.kind->compliance(rest, kind, shell));
      alpha_tilde_.push_back(alpha_.back() / h2);             // XPBD eq. (4): alpha~ = alpha / dt^2, dt the sub-step h
      lambda_.push_back(Eigen::VectorXd::Zero(kind.size()));  // allocated here, reset each sub-step
    }
  } else {
    alpha_.resize(c_.kinds.size());
    lambda_.resize(c_.kinds.size());
  }
}

void Solver::set_loads(std::vector<NodalWeights> loads) {
  for (const NodalWeights& l : loads)
    for (Eigen::Index k = 0; k < l.size(); ++k)
      if (l.nodes(k) < 0 || l.nodes(k) >= rest_.rows())
        throw std::invalid_argument("PBD load on vertex " + std::to_string(l.nodes(k)) + ", outside the surface's " +
                                    std::to_string(rest_.rows()) + " vertices");
  loads_ = std::move(loads);
}

void Solver::step(const std::vector<Eigen::Vector3d>& load_values, const std::vector<int>& pinned,
                  const Points& pinned_positions) {
  if (load_values.size() != loads_.size())
    throw std::invalid_argument("PBD step: " + std::to_string(load_values.size()) + " load values for " +
                                std::to_string(loads_.size()) + " loads");
  projection_ms_ = integration_ms_ = 0;
  // Sub-stepping (Macklin et al. 2019): n steps of h = time_step / n. With n = 1,
  // h is time_step exactly and the frame is the paper's step, bit for bit.
  const double h = s_.time_step / s_.substeps;
  const size_t spheres = sphere_force_.size();
  if (spheres > 0) {
    // The vertices each sphere may reach this step: those whose rest position is within
    // r + margin of its centre, the margin the largest displacement from rest so far
    // plus twice the largest speed times the step, and a tenth of r (the candidates
    // are tested one by one in every sweep; the others are not).
    double vmax = 0;
    for (Eigen::Index v = 0; v < v_.rows(); ++v) vmax = std::max(vmax, v_.row(v).squaredNorm());
    const double margin = max_displacement_ + 2 * std::sqrt(vmax) * s_.time_step;
    for (size_t k = 0; k < spheres; ++k) {
      const double r = sphere_radius_(static_cast<Eigen::Index>(k));
      grid_->query(sphere_centre_.row(static_cast<Eigen::Index>(k)).transpose(), r + margin + 0.1 * r,
                   sphere_candidates_[k]);
      sphere_force_[k].setZero();
    }
  }
  for (CorrectionRecord& r : records_) std::fill(r.sum.begin(), r.sum.end(), Vec3::Zero());
  for (int k = 0; k < s_.substeps; ++k) substep(h, load_values, pinned, pinned_positions);
  if (!group_force_.empty()) {
    for (Eigen::Vector3d& f : group_force_) f.setZero();
    for (const CorrectionRecord& r : records_)
      for (size_t i = 0; i < r.sum.size(); ++i) group_force_[static_cast<size_t>(r.group[i])] += r.sum[i];
    for (Eigen::Vector3d& f : group_force_) f /= -(h * h * s_.substeps);
    for (size_t l = 0; l < loads_.size(); ++l)  // a load's share on a held vertex goes to its holder
      for (Eigen::Index k = 0; k < loads_[l].size(); ++k) {
        const int g = group_of_vertex_[static_cast<size_t>(loads_[l].nodes(k))];
        if (g >= 0) group_force_[static_cast<size_t>(g)] += loads_[l].weights(k) * load_values[l];
      }
  }
  if (spheres > 0) {
    max_displacement_ = 0;
    for (Eigen::Index v = 0; v < x_.rows(); ++v)
      max_displacement_ = std::max(max_displacement_, (x_.row(v) - rest_.row(v)).squaredNorm());
    max_displacement_ = std::sqrt(max_displacement_);
    for (size_t k = 0; k < spheres; ++k) {
      sphere_force_[k] /= -(h * h * s_.substeps);  // the surface's force on the sphere, averaged over the sub-steps
      const Eigen::Vector3d c = sphere_centre_.row(static_cast<Eigen::Index>(k)).transpose();
      const double r = sphere_radius_(static_cast<Eigen::Index>(k));
      // The contacts at the end of the frame: the tested vertices on the sphere (within
      // kSphereContactTolerance r of its surface) or inside it, whether or not the last
      // sweep moved them (docs/equations.md, "Contact with a rigid sphere").
      double depth = 0;
      sphere_contact_[k].clear();
      for (int v : sphere_candidates_[k]) {
        const double gap = (x_.row(v).transpose() - c).norm() - r;
        depth = std::max(depth, -gap);
        if (gap <= kSphereContactTolerance * r) sphere_contact_[k].push_back(v);
      }
      std::sort(sphere_contact_[k].begin(), sphere_contact_[k].end());
      sphere_depth_[k] = depth;
    }
  }
}

void Solver::set_reaction_groups(const std::vector<int>& group_of_vertex, int groups) {
  if (group_of_vertex.size() != static_cast<size_t>(rest_.rows()))
    throw std::invalid_argument("PBD solver: one reaction group per vertex expected");
  for (size_t v = 0; v < group_of_vertex.size(); ++v) {
    if (group_of_vertex[v] < -1 || group_of_vertex[v] >= groups)
      throw std::invalid_argument("PBD solver: reaction group " + std::to_string(group_of_vertex[v]) + " of vertex " +
                                  std::to_string(v) + " outside [-1, " + std::to_string(groups) + ")");
    if (group_of_vertex[v] >= 0 && w_(static_cast<Eigen::Index>(v)) != 0)
      throw std::invalid_argument("PBD solver: vertex " + std::to_string(v) + " of a reaction group is not pinned");
  }
  group_of_vertex_ = group_of_vertex;
  group_force_.assign(static_cast<size_t>(groups), Eigen::Vector3d::Zero());
  record_groups();
}

void Solver::record_groups() {
  records_.clear();
  if (group_of_vertex_.empty()) return;
  records_ = batches_.record_corrections(c_, w_, group_of_vertex_);
  bool any = false;
  for (const CorrectionRecord& r : records_) any = any || !r.empty();
  if (!any) records_.clear();  // nothing to sum: the plain sweeps
}

void Solver::set_spheres(const Points& centres, const Eigen::VectorXd& radii) {
  const size_t n = static_cast<size_t>(centres.rows());
  if (radii.size() != centres.rows() || centres.cols() != 3)
    throw std::invalid_argument("PBD solver: one radius per sphere centre");
  for (Eigen::Index k = 0; k < radii.size(); ++k)
    if (!(std::isfinite(radii(k)) && radii(k) > 0) || !centres.row(k).allFinite())
      throw std::invalid_argument("PBD solver: a sphere needs a finite centre and a positive radius");
  if (sphere_force_.size() != n) {  // set-up: allocate for every vertex once
    if (!grid_) {
      // Cells of about the mean edge length of a surface of this size: a few points a cell.
      const double diagonal = (rest_.colwise().maxCoeff() - rest_.colwise().minCoeff()).norm();
      grid_ = std::make_unique<PointGrid>(rest_, std::max(1e-12, diagonal / std::cbrt(std::max<double>(rest_.rows(), 1))));
    }
    sphere_centre_.resize(static_cast<Eigen::Index>(n), 3);
    sphere_radius_.resize(static_cast<Eigen::Index>(n));
    sphere_candidates_.assign(n, {});
    sphere_contact_.assign(n, {});
    for (size_t k = 0; k < n; ++k) {
      sphere_candidates_[k].reserve(static_cast<size_t>(rest_.rows()));
      sphere_contact_[k].reserve(static_cast<size_t>(rest_.rows()));
    }
    sphere_force_.assign(n, Eigen::Vector3d::Zero());
    sphere_dp_.assign(n, Eigen::Vector3d::Zero());
    sphere_depth_.assign(n, 0);
  }
  sphere_centre_ = centres;
  sphere_radius_ = radii;
}

template <class S>
void Solver::project_spheres(S* rows) {
  // C(p) = |p - c| - r >= 0 (Mueller et al. 2007, sec. 3.5): a vertex inside is moved
  // to the nearest point of the sphere, along the normal, by its whole violation
  // (a collision constraint has stiffness 1); a fixed vertex (w = 0) is not moved.
  for (size_t k = 0; k < sphere_force_.size(); ++k) {
    const Eigen::Vector3d c = sphere_centre_.row(static_cast<Eigen::Index>(k)).transpose();
    const double r = sphere_radius_(static_cast<Eigen::Index>(k));
    for (int v : sphere_candidates_[k]) {
      if (w_(v) == 0) continue;
      S* q = rows + row(v) * kPositionStride;
      const Eigen::Vector3d p(q[0], q[1], q[2]);
      const Eigen::Vector3d d = p - c;
      const double len = d.norm();
      if (len >= r || len == 0) continue;
      const Eigen::Vector3d to = c + d * (r / len);
      for (int i = 0; i < 3; ++i) q[i] = static_cast<S>(to(i));
      const Eigen::Vector3d moved = Eigen::Vector3d(q[0], q[1], q[2]) - p;
      sphere_dp_[k] += moved / w_(v);  // mass x correction
    }
  }
}

void Solver::substep(double dt, const std::vector<Eigen::Vector3d>& load_values, const std::vector<int>& pinned,
                     const Points& pinned_positions) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  for (size_t l = 0; l < loads_.size(); ++l) {  // eq. (31), each force shared by its vertices
    const NodalWeights& load = loads_[l];
    for (Eigen::Index k = 0; k < load.size(); ++k)
      if (load.weights(k) != 0)
        v_.row(load.nodes(k)) += (dt * w_(load.nodes(k)) * load.weights(k)) * load_values[l].transpose();
  }
  // Damping (per (sub)step: the steady state applies (1 - damping) f for any
  // substeps) and eq. (32), fixed vertices having v = 0, written straight into the
  // rows the sweep moves: float rows for a single-precision sweep (the same
  // numbers as rounding double rows), vertices shared out over the team.
  const double keep = 1 - s_.damping;
  const bool single = s_.kernels == Kernels::Simd && s_.precision == Precision::Single;
  for_vertex_ranges([&](Eigen::Index begin, Eigen::Index end) {
    for (Eigen::Index v = begin; v < end; ++v) {
      v_.row(v) *= keep;
      const Eigen::RowVector3d p = x_.row(v) + dt * v_.row(v);
      if (single)
        q_.matrix().row(row(v)).head<3>() = p.cast<float>();
      else
        p_.matrix().row(row(v)).head<3>() = p;
    }
  });
  const auto t1 = Clock::now();
  for (size_t k = 0; k < pinned.size(); ++k) {  // eq. (33)
    const Eigen::Index r = row(pinned[k]);
    const auto at = pinned_positions.row(static_cast<Eigen::Index>(k));
    if (single)
      q_.matrix().row(r).head<3>() = at.cast<float>();
    else
      p_.matrix().row(r).head<3>() = at;
  }
  // Sweeping alternately forward and backward (symmetric Gauss-Seidel) removes
  // most of the bias a fixed constraint order leaves in the steady state.
  const ProjectionOptions options{s_.bending_angle};
  if (!sphere_force_.empty()) {
    // With spheres: each sweep, then each sphere's collision projection (the same
    // symmetric order as below, one sweep at a time on this thread).
    for (Eigen::Vector3d& dp : sphere_dp_) dp.setZero();
    const bool xpbd = s_.constraint_solve == ConstraintSolve::Xpbd;
    if (xpbd && s_.kernels == Kernels::Reference)
      for (Eigen::VectorXd& lambda : lambda_) lambda.setZero();
    for (int it = 0; it < s_.iterations; ++it) {
      if (single) {
        batches_.sweep(q_.data(), it % 2 == 1, k_, options, isa_, records());
        project_spheres(q_.data());
      } else if (s_.kernels == Kernels::Simd) {
        batches_.sweep(p_.data(), it % 2 == 1, k_, options, isa_, records());
        project_spheres(p_.data());
      } else {
        scalar_sweep(it % 2 == 1, xpbd);
        project_spheres(p_.data());
      }
    }
    for (size_t k = 0; k < sphere_force_.size(); ++k) sphere_force_[k] += sphere_dp_[k];
  } else if (single) {
    batches_.project(q_.data(), s_.iterations, k_, options, isa_, team_.get(), records());
  } else if (s_.kernels == Kernels::Simd) {
    batches_.project(p_.data(), s_.iterations, k_, options, isa_, team_.get(), records());
  } else {
    const bool xpbd = s_.constraint_solve == ConstraintSolve::Xpbd;
    if (xpbd)
      for (Eigen::VectorXd& lambda : lambda_) lambda.setZero();  // XPBD: the multipliers start from 0 each (sub)step
    for (int it = 0; it < s_.iterations; ++it) scalar_sweep(it % 2 == 1, xpbd);
  }
  const auto t2 = Clock::now();
  for_vertex_ranges([&](Eigen::Index begin, Eigen::Index end) {  // eqs. (35) and (34)
    for (Eigen::Index v = begin; v < end; ++v) {
      const Eigen::RowVector3d p = single ? Eigen::RowVector3d(q_.matrix().row(row(v)).head<3>().cast<double>())
                                          : Eigen::RowVector3d(p_.matrix().row(row(v)).head<3>());
      v_.row(v) = (p - x_.row(v)) / dt;
      x_.row(v) = p;
    }
  });
  const auto t3 = Clock::now();
  using Ms = std::chrono::duration<double, std::milli>;
  projection_ms_ += Ms(t2 - t1).count();
  integration_ms_ += Ms(t1 - t0).count() + Ms(t3 - t2).count();
}

template <class RangeBody>
void Solver::for_vertex_ranges(RangeBody&& body) {
  const Eigen::Index n = x_.rows();
  if (!team_) return body(Eigen::Index{0}, n);
  const Eigen::Index members = team_->size();
  auto task = [&](int member) { body(n * member / members, n * (member + 1) / members); };
  team_->run(task);
}

nlohmann::json Solver::details() const {
  const bool reference = s_.kernels == Kernels::Reference;
  nlohmann::json d = {{"instruction_set", reference ? "scalar" : name(isa_)},
                      {"lanes", reference ? 1 : batches_.width()},
                      {"precision", name(s_.precision)},
                      {"threads", s_.threads},
                      {"domains", s_.domains},
                      {"constraint_solve", s_.constraint_solve == ConstraintSolve::Xpbd ? "xpbd" : "pbd"}};
  if (s_.constraint_solve == ConstraintSolve::Xpbd) {
    d["shell_thickness_m"] = thickness_;
    // k = 1 / alpha: N/m for stretch, N m for bending
    for (size_t k = 0; k < c_.kinds.size(); ++k)
      if (alpha_[k].size() > 0)
        d[std::string(c_.kinds[k].kind->name) + "_stiffness_" + c_.kinds[k].kind->stiffness_unit] = {
            1 / alpha_[k].maxCoeff(), 1 / alpha_[k].minCoeff()};
  }
  return d;
}

void Solver::use_instruction_set(InstructionSet isa) {
  if (batch_width(isa, s_.precision) != batches_.width()) {
    batches_ = pack_batches(batch_width(isa, s_.precision));
    record_groups();  // the records name batches and lanes of the packing
  }
  isa_ = isa;
}

ConstraintBatches Solver::pack_batches(int width) const {
  if (row_of_.empty()) return ConstraintBatches(c_, w_, width, s_.precision);
  // The same constraints (rows, order, colours: the numbers do not change) on rows of p_.
  ConstraintSet on_rows = c_;
  for (KindConstraints& kind : on_rows.kinds)
    for (Eigen::Index i = 0; i < kind.vertices.size(); ++i) kind.vertices.data()[i] = row(kind.vertices.data()[i]);
  Eigen::VectorXd w_of_row(w_.size());
  std::vector<int> domain_of_row(domain_.size());
  for (Eigen::Index v = 0; v < w_.size(); ++v) {
    w_of_row(row(v)) = w_(v);
    domain_of_row[static_cast<size_t>(row(v))] = domain_[static_cast<size_t>(v)];
  }
  return ConstraintBatches(on_rows, w_of_row, width, s_.precision, domain_of_row);
}

void Solver::scalar_sweep(bool reverse, bool xpbd) {
  const int* row_of = row_of_.empty() ? nullptr : row_of_.data();
  for (size_t k = 0; k < c_.kinds.size(); ++k) {
    if (!xpbd && !(k_[k] > 0)) continue;
    const KindConstraints& kind = c_.kinds[k];
    const ScalarPass pass{p_.data(),
                          row_of,
                          w_,
                          kind,
                          batches_.kinds()[k].order,
                          {s_.bending_angle},
                          k_[k],
                          xpbd ? &alpha_tilde_[k] : nullptr,
                          &lambda_[k],
                          records_.empty() || records_[k].empty() ? nullptr : &records_[k]};
    (xpbd ? kind.kind->xpbd_pass : kind.kind->reference_pass)(pass, reverse);
  }
}

size_t Solver::kind_index(const std::string& name) const {
  for (size_t k = 0; k < c_.kinds.size(); ++k)
    if (name == c_.kinds[k].kind->name) return k;
  throw std::invalid_argument("PBD solver: no constraint kind '" + name + "'");
}

}  // namespace tb::pbd

namespace tb::pbd {

Eigen::VectorXd inverse_masses(const SurfaceMesh& surface, double density, const std::vector<char>& fixed) {
  const Eigen::VectorXd m = lumped_surface_masses(surface, density);
  Eigen::VectorXd w(m.size());
  for (Eigen::Index v = 0; v < m.size(); ++v) w(v) = fixed[static_cast<size_t>(v)] ? 0.0 : 1.0 / m(v);
  return w;
}

}  // namespace tb::pbd
