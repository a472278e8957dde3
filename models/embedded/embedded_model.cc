#include "embedded_model.h"

#include <stdexcept>

#include "coarse_embedding.h"
#include "coarse_fem.h"

namespace tb {
namespace {

class EmbeddedModel : public Model {
 public:
  void setup(const Problem& p) override {
    const HybridMesh& h = *p.mesh;
    if (h.coarse_volume.T.rows() == 0) throw std::invalid_argument("embedded: the scenario provides no coarse volume");
    try {
      coarse_ = std::make_unique<CoarseFem>(p, PointInVolume::Nearest);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("embedded: coarse mesh: ") + e.what());
    }
    embedding_ = embed_vertices(h.fine_surface.V, h.coarse_volume);
    u_ = Displacements::Zero(h.fine_surface.V.rows(), 3);
  }

  void step(const FrameLoads& loads) override {
    coarse_->step(loads);
    interpolate_embedded(embedding_, coarse_->body().mesh().T, coarse_->displacement(), u_);
  }

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
  std::unique_ptr<CoarseFem> coarse_;
  std::vector<ControlPoint> embedding_;
  Displacements u_;
};

}  // namespace

ModelInfo embedded_model_info() {
  std::vector<ParameterSpec> specs;
  for (ParameterSpec& s : elastic_solve_parameters("coarse_", "direct", "ic")) {
    s.description = "coarse mesh: " + s.description;
    specs.push_back(std::move(s));
  }
  ModelInfo m;
  m.name = "embedded";
  m.description =
      "Coarse linear FEM; every fine-surface vertex follows it by barycentric weights, no PBD (SOFA's barycentric "
      "mapping)";
  m.parameters = specs;
  m.create = [] { return std::make_unique<EmbeddedModel>(); };
  m.loads = {LoadKind::PointForce, LoadKind::SurfaceTraction, LoadKind::BodyForce};
  describe_coarse_fem(m);
  return m;
}

}  // namespace tb
