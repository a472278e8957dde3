// The coarse linear FEM the embedded and hybrid models are built on (paper 1.5,
// eq. 11 on the coarse tets): the coarse body clamped by the support box at its own
// nodes, each load at the coarse tet nearest its point (a coarse hull may lie inside
// a curved surface) or, as a study factor, at the nearest coarse node, each tool
// held at the coarse nodes nearest the surface vertices it holds
// (tool_placement.h), solved each frame by the strategy the model's coarse_*
// parameters choose (or the one its model makes: the real-time nonlinear steppers
// on the coarse mesh); with the reactions on each tool and the support, and the
// displacement at the probes (nearest coarse tet, extrapolated).
#pragma once

#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <vector>

#include "elastic_body.h"
#include "elastic_solve.h"
#include "elastic_solve_factory.h"
#include "load_placement.h"
#include "model.h"

namespace tb {

class CoarseFem {
 public:
  /// With `make_solve` empty, the strategy of the parameters coarse_solver and
  /// coarse_*. Throws std::invalid_argument (its message without the model's name).
  CoarseFem(const Problem& problem, PointInVolume point_rule, const ElasticSolveFactory& make_solve = {});

  /// One frame: the coarse displacement under the frame's loads and tools.
  void step(const FrameLoads& loads);

  const ElasticBody& body() const { return *body_; }
  const Eigen::VectorXd& displacement() const { return u_; }  ///< 3 #coarse nodes
  /// Each tool's reaction, then the support's (Model::reaction_forces).
  const std::vector<Eigen::Vector3d>& reactions() const { return reactions_; }
  const Points& probe_displacements() const { return probe_u_; }
  int last_iterations() const { return solve_->last_iterations(); }
  /// The solve's report and how far the first load was from the coarse mesh.
  void report(nlohmann::json& r) const;

 private:
  std::unique_ptr<ElasticBody> body_;
  std::unique_ptr<ElasticSolve> solve_;
  std::unique_ptr<BodyLoads> loads_;
  std::unique_ptr<ElasticFrame> frame_;
  std::vector<TetEmbedding> probes_;
  Eigen::VectorXd u_;
  Points probe_u_;
  std::vector<Eigen::Vector3d> reactions_;
  std::vector<std::pair<size_t, size_t>> group_of_tool_;  // (tool, prescribed group): the tools that hold nodes
  std::vector<Eigen::Vector3d> group_values_;
};

/// What ModelInfo says of a model built on CoarseFem: its tools, how it holds them,
/// how it measures reactions and probes.
void describe_coarse_fem(ModelInfo& info);

}  // namespace tb
