#include "condensed_model.h"

#include <chrono>
#include <stdexcept>

#include "elastic_body.h"
#include "load_mapping.h"
#include "precomputed_response.h"

namespace tb {
namespace {

class CondensedModel : public Model {
 public:
  void setup(const Problem& p) override {
    const HybridMesh& h = *p.mesh;
    if (h.fine_volume.T.rows() == 0)
      throw std::invalid_argument("condensed: the scenario provides no fine volume mesh");
    body_ = std::make_unique<ElasticBody>(h.fine_volume, p.material, p.support.clamp(h.fine_volume.V, "fine volume"));
    // Outputs: the fine-surface vertices, which are fine-volume nodes.
    response_ = std::make_unique<PrecomputedResponse>(*body_, h.fine_surface_to_volume);
    const auto t0 = std::chrono::steady_clock::now();
    if (p.parameters.choice("precompute") == "surface_vertices") response_->precompute(h.fine_surface_to_volume);
    precompute_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    u_ = Displacements::Zero(h.fine_surface.V.rows(), 3);
  }

  void step(const PointLoad& load) override {
    require_point_load(load, "condensed");
    const LoadStencil& stencil = stencil_.get(
        load.point, [&](const Eigen::Vector3d& x) { return containing_tet(body_->mesh(), x, "fine volume"); });
    response_->apply(stencil, load.force, u_);
  }

  const Displacements& surface_displacement() const override { return u_; }

  nlohmann::json report() const override {
    return {{"loaded_nodes_precomputed", response_->nodes_computed()},
            {"response_memory_mib", response_->memory_bytes() / (1024.0 * 1024.0)},
            {"precompute_ms", precompute_ms_}};
  }

 private:
  std::unique_ptr<ElasticBody> body_;
  std::unique_ptr<PrecomputedResponse> response_;
  PerLoadPoint<LoadStencil> stencil_;
  Displacements u_;
  double precompute_ms_ = 0;
};

}  // namespace

ModelInfo condensed_model_info() {
  return {"condensed",
          "Fine linear FEM condensed to the surface: precomputed responses to unit forces, superposed per frame "
          "(Bro-Nielsen and Cotin 1996; Cotin et al. 1999)",
          false,
          {ParameterSpec::choice("precompute", {"surface_vertices", "on_demand"}, "surface_vertices",
                                 "surface_vertices: in setup, the response to a unit force at every surface vertex "
                                 "(9 n^2 doubles for n surface vertices); on_demand: only the nodes a load reaches, "
                                 "the first time it does")},
          [] { return std::make_unique<CondensedModel>(); }};
}

}  // namespace tb
