#include "coarse_embedded.h"

#include <chrono>
#include <stdexcept>

#include "coarse_embedding.h"

namespace tb {
namespace {

class CoarseEmbedded : public Model {
 public:
  CoarseEmbedded(std::string name, ElasticSolveFactory make_solve)
      : name_(std::move(name)), make_solve_(std::move(make_solve)) {}

  void setup(const Problem& p) override {
    const HybridMesh& h = *p.mesh;
    if (h.coarse_volume.T.rows() == 0) throw std::invalid_argument(name_ + ": the scenario provides no coarse volume");
    try {
      coarse_ = std::make_unique<CoarseFem>(p, PointInVolume::Nearest, make_solve_);
    } catch (const std::invalid_argument& e) {
      const std::string what = e.what();  // a stepper's own errors already name the model
      throw std::invalid_argument(what.rfind(name_ + ": ", 0) == 0 ? what : name_ + ": coarse mesh: " + what);
    }
    embedding_ = embed_vertices(h.fine_surface.V, h.coarse_volume);
    u_ = Displacements::Zero(h.fine_surface.V.rows(), 3);
  }

  void step(const FrameLoads& loads) override {
    using Clock = std::chrono::steady_clock;
    using Ms = std::chrono::duration<double, std::milli>;
    const auto t0 = Clock::now();
    coarse_->step(loads);
    const auto t1 = Clock::now();
    interpolate_embedded(embedding_, coarse_->body().mesh().T, coarse_->displacement(), u_);
    phases_[0].ms = Ms(t1 - t0).count();
    phases_[1].ms = Ms(Clock::now() - t1).count();
  }
  const std::vector<PhaseTime>& last_phase_times() const override { return phases_; }

  const Displacements& surface_displacement() const override { return u_; }
  const std::vector<Eigen::Vector3d>* reaction_forces() const override { return &coarse_->reactions(); }
  const Points* probe_displacements() const override { return &coarse_->probe_displacements(); }
  int last_iterations() const override { return coarse_->last_iterations(); }
  // How far vertices lie outside the coarse mesh is the mesh's summary.json
  // "max_embedding_distance" (written beside every result as run.json "mesh").
  nlohmann::json report() const override {
    nlohmann::json r = nlohmann::json::object();
    coarse_->report(r);
    return r;
  }

 private:
  std::string name_;
  ElasticSolveFactory make_solve_;
  std::unique_ptr<CoarseFem> coarse_;
  std::vector<ControlPoint> embedding_;
  Displacements u_;
  std::vector<PhaseTime> phases_{{phase::kCoarseSolve}, {phase::kMapping}};  ///< the coarse step; the embedding
};

}  // namespace

std::unique_ptr<Model> make_coarse_embedded(const std::string& model_name, ElasticSolveFactory make_solve) {
  return std::make_unique<CoarseEmbedded>(model_name, std::move(make_solve));
}

}  // namespace tb
