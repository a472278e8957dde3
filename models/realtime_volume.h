// Where a real-time nonlinear model (vbd, xpbd_neo, pd) runs its stepper: on the
// fine tet volume (fine_fem.h: every fine-surface vertex a volume node), or on the
// coarse tet volume with the fine surface embedded by barycentric weights
// (coarse_embedded.h: the embedded model's support, loads, tools, reactions and
// probes). The parameter `volume` chooses; the stepper is the same ElasticSolve on
// either body. Why a parameter of these models rather than coarse_solver strategies
// of the embedded model: docs/architecture.md, "A real-time stepper on the coarse
// mesh".
#pragma once

#include <memory>
#include <string>

#include "fine_fem.h"
#include "model.h"

namespace tb {

/// The parameter `volume`: fine (default) or coarse_embedded.
ParameterSpec volume_parameter();

/// A model running `make_solve`'s stepper on the volume its parameter `volume`
/// names; its errors begin with `model_name`, its report() says which volume.
std::unique_ptr<Model> make_on_volume(const std::string& model_name, ElasticSolveFactory make_solve);

/// ModelInfo of a real-time stepper model: loads, tools, and how it holds tools,
/// measures reactions and gives probes on either volume; `fine_tools_how` and
/// `reactions` say how the stepper holds a node and what it measures there (the
/// same on either volume), `sphere_how` how it meets a sphere (fine volume only),
/// `pads_how` how it holds a compliant grasp's pads (fine volume only; empty: the
/// stepper takes none). Its check_case refuses a sphere and pads on volume
/// coarse_embedded; `info.name` must be set before.
void describe_on_volume(ModelInfo& info, const std::string& fine_tools_how, const std::string& reactions,
                        const std::string& sphere_how, const std::string& pads_how = "");

}  // namespace tb
