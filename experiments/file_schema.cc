#include "file_schema.h"

namespace tb {

const std::map<std::string, std::vector<std::string>>& file_schema() {
  static const std::map<std::string, std::vector<std::string>> schema = {
      // "extends" and "reference" are read before the strict reading (scenario.cc).
      {"scenario",
       {"extends", "reference", "name", "description", "mesh", "material", "support", "load", "loads", "tools",
        "probes", "frames", "observe", "output", "models"}},
      {"scenario.mesh",
       {"type", "side", "height", "nx", "ny", "nz", "symmetric_fine_volume", "shape", "resolution", "surface", "coarse",
        "unit_scale", "repair_self_intersections", "control_points", "build_fine_volume", "refine_levels",
        "fine_tetgen", "coarse_selection"}},
      {"scenario.mesh.fine_tetgen", {"radius_edge_ratio", "max_volume"}},
      {"scenario.mesh.coarse_selection",
       {"target_nodes", "spacing", "feature_angle_deg", "min_dihedral_deg", "seed", "include_points"}},
      {"scenario.material", {"youngs_modulus", "poisson_ratio", "density"}},
      {"scenario.support", {"min", "max", "lowest_fraction"}},
      {"scenario.load", {"at", "point", "force", "ramp_frames", "disc_radius"}},
      {"scenario.loads[]", {"type", "point", "radius", "force", "g", "ramp_frames", "path"}},
      {"scenario.tools[]", {"type", "point", "radius", "pad_stiffness", "pad_profile", "box", "mode", "normal", "displacement", "ramp_frames", "path"}},
      {"scenario.tools[].box", {"min", "max"}},
      {"scenario.probes", {"points", "file", "truth_cube"}},
      {"scenario.probes.truth_cube", {"table", "compare_at_strain"}},
      {"scenario.frames", {"max", "static", "steady_tolerance", "divergence_factor"}},
      {"scenario.observe", {"vertices", "top_tolerance"}},
      {"scenario.output", {"series_every"}},
      {"scenario.models[]", {"name", "model", "parameters", "max_frames"}},
      {"experiment", {"name", "description", "reference", "transient_reference", "law_references", "scenarios", "models", "sweep",
        "unsupported_cases"}},
      {"experiment.scenarios[]", {"file", "role", "models_add"}},
      {"experiment.sweep", {"mode", "cases", "factors"}},
      {"experiment.sweep.factors[]", {"key", "label", "values", "value_names", "role"}},
  };
  return schema;
}

}  // namespace tb
