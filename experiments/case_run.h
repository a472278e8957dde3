// One case of a scenario set up and stepped frame by frame, the runner's way: its
// model made from the registry and checked against the scenario's loads and tools
// before setup (check_supported), each frame's loads by the scenario's schedule
// (Scenario::loads_at), the step timed alone, then the surface checked for
// divergence and each sphere for tunnelling (sphere_guard.h), and a dynamic model's
// steady state tested. The runner (runner.cc) records and writes around it; the
// Python module's Run (python/run_binding.cc) steps it from Python. Both therefore
// stop a case for the same reasons with the same one-line messages.
#pragma once

#include <memory>

#include "model.h"
#include "scenario.h"
#include "sphere_guard.h"

namespace tb {

/// A copy of `scenario` with what it places relative to its mesh resolved
/// (resolve_on_mesh) and checked (check_on_mesh): what each of its cases runs on.
/// Throws std::invalid_argument naming the scenario key.
Scenario placed_on_mesh(const Scenario& scenario, const SurfaceMesh& surface);

class CaseRun {
 public:
  /// `scenario` (placed_on_mesh), `run` (one of its models) and `mesh` (built from its
  /// recipe) must outlive the CaseRun. Makes the model; throws std::invalid_argument
  /// when it does not take one of the scenario's loads or tools, before any setup.
  CaseRun(const Scenario& scenario, const ModelRun& run, const HybridMesh& mesh);
  CaseRun(const CaseRun&) = delete;
  CaseRun& operator=(const CaseRun&) = delete;

  /// The model's setup (assembly, factorisation ...), timed: setup_ms().
  void setup();
  /// Frame frames(): its loads, the model's step (timed: last_step_ms()), then the
  /// checks. Throws std::runtime_error, one line, when the surface displacement is not
  /// finite or beyond divergence_factor x the surface's bounding-box diagonal, or a
  /// sphere tunnelled; std::logic_error before setup() or once finished().
  void step();
  /// The frame budget is spent, or a dynamic model met the steady-state test.
  bool finished() const { return steady_frame_ >= 0 || frames_ >= budget_; }

  const ModelInfo& info() const { return info_; }
  const Model& model() const { return *model_; }
  const Problem& problem() const { return problem_; }
  /// Frames stepped so far.
  int frames() const { return frames_; }
  /// Frames at most: a dynamic model's frames.max (or its case's own max_frames), a
  /// static one's frames.static, at least the frames whose loads change.
  int budget() const { return budget_; }
  /// Frames during which a load's or tool's value changes (Scenario::changing_frames).
  int changing_frames() const { return changing_; }
  /// A dynamic model's first frame that met the steady-state test (max per-vertex
  /// change in the frame <= steady_tolerance x max displacement, after the changing
  /// frames); -1 before that and for a static model.
  int steady_frame() const { return steady_frame_; }
  double setup_ms() const { return setup_ms_; }
  double last_step_ms() const { return last_step_ms_; }
  /// m: the largest change of a surface vertex's displacement in the last frame.
  double last_change() const { return last_change_; }
  /// The sphere guard of the case's tools and how long its check of the last frame
  /// took (ms, outside the timed step; 0 when it is not active()).
  const SphereGuard& sphere_guard() const { return sphere_guard_; }
  double last_sphere_guard_ms() const { return last_sphere_guard_ms_; }

 private:
  const Scenario& scenario_;
  const ModelInfo& info_;
  Problem problem_;
  std::unique_ptr<Model> model_;
  SphereGuard sphere_guard_;  // holds problem_.load_case.tools
  const int changing_, budget_;
  const double divergence_bound_;  // m
  bool set_up_ = false;
  int frames_ = 0, steady_frame_ = -1;
  double setup_ms_ = 0, last_step_ms_ = 0, last_change_ = 0, last_sphere_guard_ms_ = 0;
  FrameLoads loads_;
  Displacements previous_;
};

}  // namespace tb
