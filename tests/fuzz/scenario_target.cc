// The fuzz target of the scenario and experiment loader (fuzz_targets.h), apart from
// the mesh readers' so that those link without the models.
#include "fuzz_targets.h"
#include "scenario.h"
#include "truth_cube.h"

namespace tb::fuzz {

Target scenario_target() {
  // The workspace holds the companions the seeds name (tests/fuzz/corpus/scenario_aux/):
  // base.json to extend, scenario.json for experiments, probes.csv, surface.obj, and
  // data/ as the data directory.
  Target t{"scenario",
           "scenario and experiment JSON (load_experiment: extends, sweeps, loads, tools, probes), then what "
           "'tissuebench resolve' prints",
           [](const std::string& bytes, const Workspace& w) {
             const std::string p = w.write("input.json", bytes);
             const Experiment e = load_experiment(p, DataDir{w.path("data"), "the fuzz workspace"});
             nlohmann::json j = e.to_json();
             for (const Scenario& s : e.scenarios) j["scenarios"].push_back(s.to_json_with_models());
             (void)j.dump();
           },
           {"input.json", "base.json", "scenario.json", "probes.csv", "surface.obj"},
           {},
           true};
  t.dictionary = {"\"extends\": \"base.json\"",
                  "\"extends\": \"input.json\"",
                  "\"extends\": \"scenario.json\"",
                  "\"loads\"",
                  "\"tools\"",
                  "\"probes\"",
                  "\"sweep\"",
                  "\"factors\"",
                  "\"values\"",
                  "\"value_names\"",
                  "\"mode\": \"grid\"",
                  "\"path\": [[0, 0, 0, 1], [10, 0, 0, 2]]",
                  "\"ramp_frames\"",
                  "\"models\"",
                  "\"models_add\"",
                  "\"role\"",
                  "\"key\": \"models.*.parameters.iterations\"",
                  "\"key\": \"mesh.nx\"",
                  "\"file\": \"probes.csv\"",
                  "\"surface\": \"data:meshes/surface.obj\"",
                  "\"surface\": \"surface.obj\"",
                  "\"type\": \"files\"",
                  "\"type\": \"grasp\"",
                  "\"type\": \"plate\"",
                  "\"type\": \"gravity\"",
                  "\"type\": \"surface_traction\"",
                  "\"mode\": \"sliding\"",
                  "null",
                  "true",
                  "[]",
                  "{}",
                  "\"\\n\"",
                  "\"\\u0000\"",
                  "\"a\\nb\"",
                  "\"lowest_fraction\": 0.1",
                  "\"at\": \"highest_surface_vertex\"",
                  "\"reference\": \"fem\"",
                  "\"cases\": [\"fem\"]",
                  "[[[[[[[[",
                  "\"value_names\": [\"a\", \"b\"]",
                  "1e400",
                  "\"scenarios\": [\"scenario.json\"]"};
  return t;
}

Target probes_target() {
  // The input is probes.csv, which the companion scenario.json (tests/fuzz/corpus/
  // scenario_aux/) names as its "probes" file: the loader's CSV reader.
  return {"probes_csv",
          "probe-point CSV of a scenario's \"probes\": {\"file\"} (load_experiment of a scenario naming it)",
          [](const std::string& bytes, const Workspace& w) {
            w.write("probes.csv", bytes);
            load_experiment(w.path("scenario.json"), DataDir{w.path("data"), "the fuzz workspace"});
          },
          {"probes.csv"},
          {"x,y,z\n", ",", "\r\n", "\n", " ", "1e400", "nan", "-0", "0.05"},
          true};
}

Target truth_cube_target() {
  // The Truth Cube's bead table (experiments/truth_cube.h), as a scenario's
  // probes.truth_cube reads it from the data directory; the seeds are tables written by
  // make_seeds.py in its layout (7 header lines, then i, j, k and x, y, z per strain).
  return {"truth_cube_csv",
          "Truth Cube bead table CSV (read_truth_cube_table)",
          [](const std::string& bytes, const Workspace& w) { read_truth_cube_table(w.write("beads.csv", bytes)); },
          {"beads.csv"},
          {",", "\n", "\r\n", "no strain", "5% strain", "12.5% strain", "% strain", ",,,", "7", "8", "0", "nan"}};
}

}  // namespace tb::fuzz
