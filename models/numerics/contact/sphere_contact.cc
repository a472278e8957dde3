#include "sphere_contact.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace tb {
namespace {

/// A surface node joins when it is deeper than this fraction of the radius.
constexpr double kGapTolerance = 1e-9;
/// An active node counts as on its sphere within this fraction of the radius (the
/// normal re-linearised until then). The linearised constraint puts the node on the
/// sphere's tangent plane, outside the sphere, so this bounds how far above it the
/// node may sit, not a penetration. The re-linearisation converges linearly, by the
/// ratio of the node's tangential sliding to r each iteration (0.93 for a single
/// node pressed into the coarse L-block of the contact experiment): 1e-9 r took more
/// than 100 iterations there, 1e-6 r about 40.
constexpr double kOnSphereTolerance = 1e-6;

}  // namespace

SphereContact::SphereContact(const ElasticBody& body, ElasticSolve& solve, std::vector<int> surface_nodes)
    : body_(body), solve_(solve), surface_nodes_(std::move(surface_nodes)) {
  if (!solve_.linear())
    throw std::invalid_argument("a sphere needs a linear elastic solve (direct or iterative), not a nonlinear one");
}

void SphereContact::build_flexibility() {
  const int n = static_cast<int>(candidates_.size());
  G_.resize(3 * n, 3 * n);
  f_free_ = Eigen::VectorXd::Zero(body_.free_dofs());
  column_ = Eigen::VectorXd::Zero(body_.dofs());
  // G's row/column 3 j + a (candidate j's dof a) as a free dof, or -1 where a group
  // holds it (a sliding plate's component: fixed by its group, no flexibility).
  std::vector<int> free_dof(static_cast<size_t>(3 * n));
  for (int j = 0; j < 3 * n; ++j)
    free_dof[static_cast<size_t>(j)] =
        body_.free_index(3 * surface_nodes_[static_cast<size_t>(candidates_[static_cast<size_t>(j / 3)])] + j % 3);
  if (solve_.factorised()) {
    // The unit forces kBlock at a time, each block one back-substitution of many
    // right-hand sides (solve_columns: the factor read once per block).
    constexpr int kBlock = 96;
    Eigen::MatrixXd F, U;
    for (int begin = 0; begin < 3 * n; begin += kBlock) {
      const int width = std::min(kBlock, 3 * n - begin);
      F.setZero(body_.free_dofs(), width);
      for (int j = begin; j < begin + width; ++j)
        if (free_dof[static_cast<size_t>(j)] >= 0) F(free_dof[static_cast<size_t>(j)], j - begin) = 1;
      solve_.solve_columns(F, U);
      for (int j = begin; j < begin + width; ++j) {
        const bool free_column = free_dof[static_cast<size_t>(j)] >= 0;
        flexibility_solves_ += free_column;
        for (int i = 0; i < 3 * n; ++i) {
          const int f = free_dof[static_cast<size_t>(i)];
          G_(i, j) = free_column && f >= 0 ? U(f, j - begin) : 0;
        }
      }
    }
  } else {
    std::vector<int> row(1);
    for (int j = 0; j < n; ++j)
      for (int a = 0; a < 3; ++a) {
        const int f = free_dof[static_cast<size_t>(3 * j + a)];
        if (f < 0) {
          G_.col(3 * j + a).setZero();
          continue;
        }
        f_free_(f) = 1;
        row[0] = f;
        column_.setZero();
        solve_.solve(f_free_, &row, column_);
        f_free_(f) = 0;
        ++flexibility_solves_;
        for (int i = 0; i < n; ++i)
          G_.block<3, 1>(3 * i, 3 * j + a) =
              column_.segment<3>(3 * surface_nodes_[static_cast<size_t>(candidates_[static_cast<size_t>(i)])]);
      }
  }
  G_ = 0.5 * (G_ + G_.transpose()).eval();  // symmetric up to the solve's rounding
}

void SphereContact::solve(const Eigen::MatrixX3d& centres, const Eigen::VectorXd& radii, Eigen::VectorXd& u) {
  const size_t spheres = static_cast<size_t>(centres.rows());
  const Points& X = body_.mesh().V;
  const auto node_of = [&](int vertex) { return surface_nodes_[static_cast<size_t>(vertex)]; };
  const auto free_node = [&](int node) {
    return body_.free_index(3 * node) >= 0 || body_.free_index(3 * node + 1) >= 0 || body_.free_index(3 * node + 2) >= 0;
  };
  const auto position = [&](const Eigen::VectorXd& uu, int node) -> Eigen::Vector3d {
    return X.row(node).transpose() + uu.segment<3>(3 * node);
  };
  const Eigen::VectorXd u0 = u;
  force_.assign(spheres, Eigen::Vector3d::Zero());
  contact_.assign(spheres, {});
  depth_.assign(spheres, 0);
  iterations_ = 0;

  // Candidates: surface nodes with a free component near a sphere without contact, within margin_ r
  // plus depth_factor_ times the deepest penetration (0.1 r and twice by default); a node found inside
  // later is added and G rebuilt.
  std::vector<int> wanted;
  for (size_t k = 0; k < spheres; ++k) {
    const Eigen::Vector3d c = centres.row(static_cast<Eigen::Index>(k)).transpose();
    const double r = radii(static_cast<Eigen::Index>(k));
    double deepest = 0;
    for (size_t v = 0; v < surface_nodes_.size(); ++v)
      deepest = std::max(deepest, r - (position(u0, node_of(static_cast<int>(v))) - c).norm());
    for (size_t v = 0; v < surface_nodes_.size(); ++v)
      if (free_node(node_of(static_cast<int>(v))) &&
          (position(u0, node_of(static_cast<int>(v))) - c).norm() < r + margin_ * r + depth_factor_ * deepest)
        wanted.push_back(static_cast<int>(v));
  }
  std::sort(wanted.begin(), wanted.end());
  wanted.erase(std::unique(wanted.begin(), wanted.end()), wanted.end());

  for (int round = 0;; ++round) {
    if (wanted != candidates_) {
      // Keep the previous frame's active pairs that are still candidates (a warm start).
      std::vector<std::pair<int, int>> kept;
      for (const auto& [i, k] : active_) {
        const auto it = std::lower_bound(wanted.begin(), wanted.end(), candidates_[static_cast<size_t>(i)]);
        if (it != wanted.end() && *it == candidates_[static_cast<size_t>(i)] && static_cast<size_t>(k) < spheres)
          kept.emplace_back(static_cast<int>(it - wanted.begin()), k);
      }
      candidates_ = wanted;
      active_ = kept;
      build_flexibility();
    }
    const int n = static_cast<int>(candidates_.size());
    Eigen::VectorXd u0c(3 * n), uc(3 * n);
    for (int i = 0; i < n; ++i) u0c.segment<3>(3 * i) = u0.segment<3>(3 * node_of(candidates_[static_cast<size_t>(i)]));
    uc = u0c;
    if (n == 0) active_.clear();
    std::vector<std::pair<int, int>> active = active_;
    for (auto& p : active)
      if (static_cast<size_t>(p.second) >= spheres) p.second = 0;
    Eigen::VectorXd lambda;
    std::vector<Eigen::Vector3d> normal;
    const auto candidate_position = [&](int i) -> Eigen::Vector3d {
      return X.row(node_of(candidates_[static_cast<size_t>(i)])).transpose() + uc.segment<3>(3 * i);
    };
    bool settled = false;
    for (int it = 0; it < kMaxIterations && !settled; ++it) {
      ++iterations_;
      // Normals at the current positions (Wriggers 2006: the closest-point projection).
      const size_t m = active.size();
      normal.resize(m);
      Eigen::VectorXd g(static_cast<Eigen::Index>(m));
      for (size_t a = 0; a < m; ++a) {
        const auto [i, k] = active[a];
        const Eigen::Vector3d c = centres.row(k).transpose();
        Eigen::Vector3d d = candidate_position(i) - c;
        if (d.norm() == 0) d = Eigen::Vector3d::UnitZ();
        normal[a] = d.normalized();
        const Eigen::Vector3d Xi = X.row(node_of(candidates_[static_cast<size_t>(i)])).transpose();
        g(static_cast<Eigen::Index>(a)) = normal[a].dot(c + radii(k) * normal[a] - Xi) - normal[a].dot(u0c.segment<3>(3 * i));
      }
      Eigen::MatrixXd S(m, m);
      for (size_t a = 0; a < m; ++a)
        for (size_t b = 0; b < m; ++b)
          S(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b)) =
              normal[a].dot(G_.block<3, 3>(3 * active[a].first, 3 * active[b].first) * normal[b]);
      lambda = m ? Eigen::VectorXd(S.ldlt().solve(g)) : Eigen::VectorXd();
      uc = u0c;
      for (size_t b = 0; b < m; ++b)
        uc += G_.middleCols<3>(3 * active[b].first) * (normal[b] * lambda(static_cast<Eigen::Index>(b)));
      // The new set: tensile multipliers leave, penetrating candidates join.
      std::vector<std::pair<int, int>> next;
      double off = 0;  // how far an active node is from its sphere after the solve
      for (size_t a = 0; a < m; ++a)
        if (lambda(static_cast<Eigen::Index>(a)) >= 0) {
          next.push_back(active[a]);
          const auto [i, k] = active[a];
          off = std::max(off, std::abs((candidate_position(i) - centres.row(k).transpose()).norm() - radii(k)) / radii(k));
        }
      for (int i = 0; i < n; ++i)
        for (size_t k = 0; k < spheres; ++k) {
          const double depth = radii(static_cast<Eigen::Index>(k)) -
                               (candidate_position(i) - centres.row(static_cast<Eigen::Index>(k)).transpose()).norm();
          if (depth > kGapTolerance * radii(static_cast<Eigen::Index>(k)) &&
              std::find(next.begin(), next.end(), std::pair<int, int>{i, static_cast<int>(k)}) == next.end())
            next.emplace_back(i, static_cast<int>(k));
        }
      std::sort(next.begin(), next.end());
      std::vector<std::pair<int, int>> sorted = active;
      std::sort(sorted.begin(), sorted.end());
      settled = next == sorted && off <= kOnSphereTolerance;
      if (!settled) active = next;
    }
    if (!settled)
      throw std::runtime_error("sphere contact: the active set did not settle in " + std::to_string(kMaxIterations) +
                               " iterations (" + std::to_string(active.size()) + " nodes active)");
    active_ = active;
    // The whole body under the contact forces lambda_i n_i on the active nodes.
    f_free_.setZero();
    node_forces_.clear();
    std::vector<int> rows;
    for (size_t a = 0; a < active.size(); ++a) {
      const auto [i, k] = active[a];
      const int node = node_of(candidates_[static_cast<size_t>(i)]);
      const Eigen::Vector3d f = lambda(static_cast<Eigen::Index>(a)) * normal[a];
      for (int c = 0; c < 3; ++c) {
        const int free = body_.free_index(3 * node + c);
        if (free < 0) continue;  // a held component: its share goes to the tool holding it
        f_free_(free) += f(c);
        rows.push_back(free);
      }
      node_forces_.emplace_back(node, f);
      force_[static_cast<size_t>(k)] -= f;  // the body pushes the sphere back
      contact_[static_cast<size_t>(k)].push_back(candidates_[static_cast<size_t>(i)]);
    }
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
    w_ = Eigen::VectorXd::Zero(body_.dofs());
    if (!rows.empty()) solve_.solve(f_free_, &rows, w_);
    u = u0 + w_;
    for (auto& list : contact_) std::sort(list.begin(), list.end());
    // Any free surface node inside a sphere that was not a candidate: add it, again.
    bool missed = false;
    for (size_t k = 0; k < spheres; ++k) {
      const Eigen::Vector3d c = centres.row(static_cast<Eigen::Index>(k)).transpose();
      const double r = radii(static_cast<Eigen::Index>(k));
      depth_[k] = 0;
      for (size_t v = 0; v < surface_nodes_.size(); ++v) {
        const int node = node_of(static_cast<int>(v));
        const double depth = r - (position(u, node) - c).norm();
        depth_[k] = std::max(depth_[k], depth);
        if (depth > kGapTolerance * r && free_node(node) &&
            !std::binary_search(candidates_.begin(), candidates_.end(), static_cast<int>(v))) {
          wanted.push_back(static_cast<int>(v));
          missed = true;
        }
      }
    }
    if (!missed || round >= 3) break;
    std::sort(wanted.begin(), wanted.end());
    wanted.erase(std::unique(wanted.begin(), wanted.end()), wanted.end());
    force_.assign(spheres, Eigen::Vector3d::Zero());
    contact_.assign(spheres, {});
  }
  max_iterations_seen_ = std::max(max_iterations_seen_, iterations_);
  candidate_count_max_ = std::max(candidate_count_max_, static_cast<int>(candidates_.size()));
}

nlohmann::json SphereContact::report() const {
  return {{"method", "active set of Lagrange multipliers on the factorised K (docs/equations.md)"},
          {"max_iterations", kMaxIterations},
          {"last_frame_iterations", iterations_},
          {"largest_frame_iterations", max_iterations_seen_},
          {"largest_candidate_count", candidate_count_max_},
          {"flexibility_solves", flexibility_solves_}};
}

}  // namespace tb
