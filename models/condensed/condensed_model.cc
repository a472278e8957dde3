#include "condensed_model.h"

#include <chrono>
#include <stdexcept>

#include "elastic_body.h"
#include "load_placement.h"
#include "precomputed_response.h"

namespace tb {
namespace {

class CondensedModel : public Model {
 public:
  void setup(const Problem& p) override {
    const HybridMesh& h = *p.mesh;
    if (h.fine_volume.T.rows() == 0)
      throw std::invalid_argument("condensed: the scenario provides no fine volume mesh");
    try {
      body_ = std::make_unique<ElasticBody>(h.fine_volume, p.material,
                                            p.load_case.support.clamp(h.fine_volume.V, "fine volume"));
      loads_ = std::make_unique<BodyLoads>(
          *body_, place_on_volume(p.load_case.loads, {&h.fine_volume, "fine volume", &h.fine_surface,
                                                      &h.fine_surface_to_volume, p.material.density}));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("condensed: ") + e.what());
    }
    // Outputs: the fine-surface vertices, which are fine-volume nodes.
    response_ = std::make_unique<PrecomputedResponse>(*body_, h.fine_surface_to_volume);
    const auto t0 = std::chrono::steady_clock::now();
    if (p.parameters.choice("precompute") == "surface_vertices") response_->precompute(h.fine_surface_to_volume);
    response_->prepare(*loads_);  // the columns the scenario's loads need beyond those
    precompute_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    u_ = Displacements::Zero(h.fine_surface.V.rows(), 3);
  }

  void step(const FrameLoads& loads) override { response_->apply(*loads_, loads.values, u_); }

  const Displacements& surface_displacement() const override { return u_; }

  nlohmann::json report() const override {
    return {{"loaded_nodes_precomputed", response_->nodes_computed()},
            {"response_memory_mib", response_->memory_bytes() / (1024.0 * 1024.0)},
            {"precompute_ms", precompute_ms_}};
  }

 private:
  std::unique_ptr<ElasticBody> body_;
  std::unique_ptr<BodyLoads> loads_;
  std::unique_ptr<PrecomputedResponse> response_;
  Displacements u_;
  double precompute_ms_ = 0;
};

}  // namespace

ModelInfo condensed_model_info() {
  ModelInfo m;
  m.name = "condensed";
  m.description =
      "Fine linear FEM condensed to the surface: precomputed responses to unit forces, superposed per frame "
      "(Bro-Nielsen and Cotin 1996; Cotin et al. 1999)";
  m.parameters = {ParameterSpec::choice(
      "precompute", {"surface_vertices", "on_demand"}, "surface_vertices",
      "surface_vertices: in setup, the response to a unit force at every surface vertex (9 n^2 doubles for n "
      "surface vertices), so a point force anywhere on the surface costs no new solve; on_demand: only the nodes "
      "the scenario's loads reach. Either way a load spread over many nodes (a traction, gravity) gets the "
      "response to its own nodal forces, three solves in setup")};
  m.create = [] { return std::make_unique<CondensedModel>(); };
  m.loads = {LoadKind::PointForce, LoadKind::SurfaceTraction, LoadKind::BodyForce};
  return m;
}

}  // namespace tb
