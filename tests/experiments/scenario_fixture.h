// A test fixture shared by the experiments tests: a temporary folder, a small
// valid cube scenario, and helpers to write scenario files and expect errors.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "runner.h"
#include "strict_json.h"
#include "test_support.h"

namespace tb {

class Scenarios : public ::testing::Test {
 protected:
  const tb::testing::TempFolder tmp{"scenarios"};
  const std::filesystem::path dir = tmp.path;

  /// A small valid cube scenario (coarse divisions so it runs in a second).
  static nlohmann::json small_cube() {
    return nlohmann::json::parse(R"({
      "name": "small",
      "mesh": {"type": "cube", "nx": 4, "ny": 4, "nz": 4, "fine_tetgen": {"max_volume": 2e-6},
               "coarse_selection": {"target_nodes": 30}},
      "support": {"min": [-1, -1, -1e-9], "max": [1, 1, 1e-9]},
      "load": {"point": [0, 0, 0.1], "force": [0, 0, 0.1], "ramp_frames": 5},
      "frames": {"max": 300, "static": 5, "steady_tolerance": 1e-4},
      "models": [{"name": "fem-direct", "model": "fem"}, {"model": "pbd"}, {"model": "hybrid"}]
    })");
  }
  /// small_cube() pressed by a sliding plate on its top instead of loaded (pbd
  /// takes no sliding plate: a pin holds all three components).
  static nlohmann::json pressed_small_cube() {
    nlohmann::json pressed = small_cube();
    pressed["name"] = "pressed";
    pressed.erase("load");
    pressed["tools"] = nlohmann::json::parse(
        R"([{"type": "plate", "box": {"min": [-1, -1, 0.0999], "max": [1, 1, 1]}, "mode": "sliding",
             "displacement": [0, 0, -0.002]}])");
    return pressed;
  }
  /// small.json (small_cube()) and pressed.json (pressed_small_cube()), each run by
  /// the direct fem alone, "fem-direct".
  void write_loaded_and_pressed() {
    for (auto [name, scenario] : {std::pair{"small.json", small_cube()}, std::pair{"pressed.json", pressed_small_cube()}}) {
      scenario["models"] = nlohmann::json::array();
      scenario["models"].push_back({{"name", "fem-direct"}, {"model", "fem"}});
      write(name, scenario);
    }
  }
  std::string write(const std::string& name, const nlohmann::json& j) {
    const std::string p = (dir / name).string();
    std::ofstream(p) << j.dump(2);
    return p;
  }
  void expect_error(const nlohmann::json& j, const std::string& message) { expect_error_in(j, "bad.json", message); }
  /// Loading `j` written as `file` is an error naming the file and `message`.
  void expect_error_in(const nlohmann::json& j, const std::string& file, const std::string& message) {
    const std::string p = write(file, j);
    try {
      load_experiment(p);
      FAIL() << "accepted: " << message;
    } catch (const ScenarioError& e) {
      EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  }
};

}  // namespace tb
