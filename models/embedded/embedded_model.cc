#include "embedded_model.h"

#include <stdexcept>

#include "coarse_embedding.h"
#include "elastic_body.h"
#include "elastic_solve.h"
#include "load_placement.h"

namespace tb {
namespace {

class EmbeddedModel : public Model {
 public:
  void setup(const Problem& p) override {
    const HybridMesh& h = *p.mesh;
    if (h.coarse_volume.T.rows() == 0) throw std::invalid_argument("embedded: the scenario provides no coarse volume");
    try {
      coarse_body_ = std::make_unique<ElasticBody>(h.coarse_volume, p.material,
                                                   p.load_case.support.clamp(h.coarse_volume.V, "coarse volume"));
      coarse_ = make_elastic_solve(*coarse_body_, p.parameters, "coarse_");
      // The loads where the coarse mesh is: the nearest tet (its hull may lie inside
      // a curved surface), extrapolated, as the surface vertices are embedded.
      coarse_loads_ = std::make_unique<BodyLoads>(
          *coarse_body_, place_on_volume(p.load_case.loads, {&h.coarse_volume, "coarse volume", &h.fine_surface, nullptr,
                                                             p.material.density, PointInVolume::Nearest}));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("embedded: coarse mesh: ") + e.what());
    }
    embedding_ = embed_vertices(h.fine_surface.V, h.coarse_volume);
    coarse_u_ = Eigen::VectorXd::Zero(coarse_body_->dofs());
    u_ = Displacements::Zero(h.fine_surface.V.rows(), 3);
  }

  void step(const FrameLoads& loads) override {
    coarse_->solve(*coarse_loads_, loads.values, coarse_u_);
    interpolate_embedded(embedding_, coarse_body_->mesh().T, coarse_u_, u_);
  }

  const Displacements& surface_displacement() const override { return u_; }
  int last_iterations() const override { return coarse_->last_iterations(); }
  // How far vertices lie outside the coarse mesh is the mesh's summary.json
  // "max_embedding_distance" (written beside every result as run.json "mesh").
  nlohmann::json report() const override {
    nlohmann::json r = {{"coarse_solve", coarse_->report()}};
    if (coarse_loads_->size() > 0) r["load_distance_to_coarse_mesh_m"] = coarse_loads_->load(0).distance;
    return r;
  }

 private:
  std::unique_ptr<ElasticBody> coarse_body_;
  std::unique_ptr<ElasticSolve> coarse_;
  std::unique_ptr<BodyLoads> coarse_loads_;
  std::vector<ControlPoint> embedding_;
  Eigen::VectorXd coarse_u_;
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
  return m;
}

}  // namespace tb
