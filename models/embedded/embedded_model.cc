#include "embedded_model.h"

#include <stdexcept>

#include "coarse_embedding.h"
#include "elastic_body.h"
#include "elastic_solve.h"
#include "load_mapping.h"

namespace tb {
namespace {

class EmbeddedModel : public Model {
 public:
  void setup(const Problem& p) override {
    const HybridMesh& h = *p.mesh;
    if (h.coarse_volume.T.rows() == 0) throw std::invalid_argument("embedded: the scenario provides no coarse volume");
    try {
      coarse_body_ = std::make_unique<ElasticBody>(h.coarse_volume, p.material,
                                                   p.support.clamp(h.coarse_volume.V, "coarse volume"));
      coarse_ = make_elastic_solve(*coarse_body_, p.parameters, "coarse_", nullptr);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("embedded: coarse mesh: ") + e.what());
    }
    embedding_ = embed_vertices(h.fine_surface.V, h.coarse_volume);
    coarse_u_ = Eigen::VectorXd::Zero(coarse_body_->dofs());
    u_ = Displacements::Zero(h.fine_surface.V.rows(), 3);
  }

  void step(const PointLoad& load) override {
    require_point_load(load, "embedded");
    const LoadStencil& coarse_load = coarse_load_.get(load.point, [&](const Eigen::Vector3d& x) {
      return nearest_tet(coarse_body_->mesh(), x);
    });  // the coarse hull may lie inside a curved surface
    coarse_->solve(coarse_load, load.force, coarse_u_);
    interpolate_embedded(embedding_, coarse_body_->mesh().T, coarse_u_, u_);
  }

  const Displacements& surface_displacement() const override { return u_; }
  int last_iterations() const override { return coarse_->last_iterations(); }
  // How far vertices lie outside the coarse mesh is the mesh's summary.json
  // "max_embedding_distance" (written beside every result as run.json "mesh").
  nlohmann::json report() const override {
    nlohmann::json r = {{"coarse_solve", coarse_->report()}};
    if (const LoadStencil* l = coarse_load_.last()) r["load_distance_to_coarse_mesh_m"] = l->distance;
    return r;
  }

 private:
  std::unique_ptr<ElasticBody> coarse_body_;
  std::unique_ptr<ElasticSolve> coarse_;
  std::vector<ControlPoint> embedding_;
  Eigen::VectorXd coarse_u_;
  Displacements u_;
  PerLoadPoint<LoadStencil> coarse_load_;
};

}  // namespace

ModelInfo embedded_model_info() {
  std::vector<ParameterSpec> specs;
  for (ParameterSpec& s : elastic_solve_parameters("coarse_", "direct", "ic")) {
    s.description = "coarse mesh: " + s.description;
    specs.push_back(std::move(s));
  }
  return {"embedded",
          "Coarse linear FEM; every fine-surface vertex follows it by barycentric weights, no PBD (SOFA's barycentric "
          "mapping)",
          false, specs, [] { return std::make_unique<EmbeddedModel>(); }};
}

}  // namespace tb
