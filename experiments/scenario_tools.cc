#include "scenario_tools.h"

#include "data_dir.h"
#include "truth_cube.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace tb {
namespace {

nlohmann::json vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

/// The value `key` with "ramp_frames", or a "path" of [frame, x, y, z] waypoints.
Schedule parse_schedule(StrictObject& o, const std::string& key) {
  Schedule s;
  if (o.has("path")) {
    if (o.has(key)) o.fail("path", "give either " + key + " (with ramp_frames) or path");
    if (o.has("ramp_frames")) o.fail("ramp_frames", "not used with a path (its waypoints say when)");
    const nlohmann::json& path = o.raw("path");
    if (!path.is_array() || path.empty()) o.fail("path", "must be a non-empty array of [frame, x, y, z]");
    for (size_t i = 0; i < path.size(); ++i) {
      const nlohmann::json& w = path[i];
      const std::string at = "path[" + std::to_string(i) + "]";
      if (!w.is_array() || w.size() != 4) o.fail(at, "must be [frame, x, y, z], found " + shown(w));
      for (const nlohmann::json& x : w)
        if (!x.is_number() || !std::isfinite(x.get<double>()))
          o.fail(at, "must hold finite numbers, found " + shown(w));
      const double frame = w[0].get<double>();
      if (frame < 0 || frame != std::floor(frame) || frame > 1e8) o.fail(at, "its frame must be a whole number >= 0");
      if (!s.path.empty() && frame <= s.path.back().first)
        o.fail(at, "frames must increase (" + std::to_string(static_cast<int>(frame)) + " after " +
                       std::to_string(s.path.back().first) + ")");
      s.path.emplace_back(static_cast<int>(frame),
                          Eigen::Vector3d(w[1].get<double>(), w[2].get<double>(), w[3].get<double>()));
    }
    s.value = s.path.back().second;
    return s;
  }
  s.value = o.vec3(key, std::nullopt);
  s.ramp_frames = o.integer("ramp_frames", 0, 0, 100000000);
  return s;
}

int axis_of(StrictObject& o, const std::string& key) {
  const std::string a = o.text(key, "z", {"x", "y", "z"});
  return a[0] - 'x';
}

}  // namespace

Eigen::Vector3d Schedule::at(int frame) const {
  if (!path.empty()) {
    if (frame <= path.front().first) return path.front().second;
    for (size_t k = 1; k < path.size(); ++k)
      if (frame <= path[k].first) {
        const double t = static_cast<double>(frame - path[k - 1].first) / (path[k].first - path[k - 1].first);
        return path[k - 1].second + t * (path[k].second - path[k - 1].second);
      }
    return path.back().second;
  }
  if (ramp_frames > 0 && frame < ramp_frames) return value * (static_cast<double>(frame + 1) / ramp_frames);
  return value;
}

int Schedule::settled_from() const { return path.empty() ? std::max(0, ramp_frames - 1) : path.back().first; }

nlohmann::json Schedule::to_json() const {
  if (path.empty()) return {{"value", vec(value)}, {"ramp_frames", ramp_frames}};
  nlohmann::json p = nlohmann::json::array();
  for (const auto& [frame, v] : path) p.push_back({frame, v.x(), v.y(), v.z()});
  return {{"path", p}};
}

std::vector<ScenarioLoad> parse_loads(StrictObject& scenario) {
  std::vector<ScenarioLoad> out;
  if (!scenario.has("loads")) return out;
  const nlohmann::json& loads = scenario.raw("loads");
  if (!loads.is_array()) scenario.fail("loads", "must be an array");
  for (size_t i = 0; i < loads.size(); ++i) {
    StrictObject o = scenario.item("loads", i);
    const std::string key = "loads[" + std::to_string(i) + "]";
    const std::string type = o.text("type", std::nullopt, {"point_force", "surface_traction", "gravity"});
    ScenarioLoad l;
    if (type == "gravity") {
      l.load = Load::body_force(key);
      l.schedule = parse_schedule(o, "g");
    } else {
      const Eigen::Vector3d point = o.vec3("point", std::nullopt);
      l.load = type == "point_force" ? Load::point_force(point, key)
                                     : Load::surface_traction(point, o.number("radius", std::nullopt, 1e-12, 1e9), key);
      l.schedule = parse_schedule(o, "force");
    }
    o.finish();
    out.push_back(l);
  }
  return out;
}

std::vector<ScenarioTool> parse_tools(StrictObject& scenario) {
  std::vector<ScenarioTool> out;
  if (!scenario.has("tools")) return out;
  const nlohmann::json& tools = scenario.raw("tools");
  if (!tools.is_array()) scenario.fail("tools", "must be an array");
  for (size_t i = 0; i < tools.size(); ++i) {
    StrictObject o = scenario.item("tools", i);
    const std::string key = "tools[" + std::to_string(i) + "]";
    const std::string type = o.text("type", std::nullopt, {"grasp", "compliant_grasp", "plate", "sphere"});
    ScenarioTool t;
    if (type == "sphere") {
      // Its value is its centre: a path of [frame, x, y, z] waypoints (a constant
      // centre: one waypoint).
      if (!o.has("path")) o.fail("path", "a sphere needs the path of its centre, [[frame, x, y, z], ...]");
      const double radius = o.number("radius", std::nullopt, 1e-12, 1e9);
      t.schedule = parse_schedule(o, "centre");
      t.tool = Tool::sphere(t.schedule.path.front().second, radius, key);
      o.finish();
      out.push_back(t);
      continue;
    }
    if (type == "grasp") {
      const Eigen::Vector3d point = o.vec3("point", std::nullopt);
      t.tool = Tool::grasp(point, o.number("radius", std::nullopt, 1e-12, 1e9), key);
    } else if (type == "compliant_grasp") {
      // The pads' stiffness kappa (Pa/m): about E_pad / thickness for a pad of
      // modulus E_pad; a tissue-soft pad 1 mm thick on 3 kPa tissue, 3e6.
      const Eigen::Vector3d point = o.vec3("point", std::nullopt);
      const double radius = o.number("radius", std::nullopt, 1e-12, 1e9);
      const double kappa = o.number("pad_stiffness", std::nullopt, 1e-12, 1e18);
      const bool smooth = o.text("pad_profile", "uniform", {"uniform", "smooth"}) == "smooth";
      t.tool = Tool::compliant_grasp(point, radius, kappa, key, smooth);
    } else {
      StrictObject box = o.object("box");
      SupportBox b;
      b.min = box.vec3("min", std::nullopt);
      b.max = box.vec3("max", std::nullopt);
      if ((b.min.array() > b.max.array()).any()) box.fail("min", "exceeds max");
      box.finish();
      const bool sliding = o.text("mode", "bonded", {"bonded", "sliding"}) == "sliding";
      t.tool = Tool::plate(b, sliding, axis_of(o, "normal"), key);
    }
    t.schedule = parse_schedule(o, "displacement");
    o.finish();
    out.push_back(t);
  }
  return out;
}

namespace {

// probes.truth_cube: the Truth Cube's beads at rest (truth_cube.h), on a cube mesh.
ScenarioProbes truth_cube_probes(StrictObject& probes, const std::string& base_dir, const DataDir& data,
                                 const MeshRecipe& mesh) {
  StrictObject o = probes.object("truth_cube");
  if (mesh.kind != MeshRecipe::Kind::Cube) o.fail("table", "the Truth Cube's beads need a mesh of type cube");
  const std::string reference = o.text("table", std::nullopt);
  std::string path = reference;
  if (is_data_reference(reference))
    path = resolve_data_file(reference, data, o.where() + ".table");
  else if (!std::filesystem::path(reference).is_absolute())
    path = (std::filesystem::path(o.directory_of("table", base_dir)) / reference).lexically_normal().string();
  TruthCubeTable table;
  try {
    table = read_truth_cube_table(path);
  } catch (const std::runtime_error& e) {
    o.fail("table", e.what());
  }
  const double strain = o.number("compare_at_strain", std::nullopt, 0, 1);
  bool listed = false;
  for (double s : table.strains) listed = listed || std::abs(s - strain) < 1e-9;
  if (!listed) {
    std::string known;
    for (size_t i = 1; i < table.strains.size(); ++i) known += (i > 1 ? ", " : "") + std::to_string(table.strains[i]);
    o.fail("compare_at_strain", "the table has no column at strain " + std::to_string(strain) + " (it has " + known + ")");
  }
  o.finish();
  const TruthCubeFrame frame = truth_cube_frame(table, mesh.cube.height);
  // The points are the third-party table's, moved: recorded by where they come
  // from and how they were moved, not copied (README, "Data").
  return {truth_cube_rest_points(table, frame), {{"truth_cube", {{"table", reference},
                                {"compare_at_strain", strain},
                                {"beads", table.beads.size()},
                                {"frame", frame.to_json()}}}}};
}

}  // namespace

ScenarioProbes parse_probes(StrictObject& scenario, const std::string& base_dir, const DataDir& data,
                            const MeshRecipe& mesh) {
  if (!scenario.has("probes")) return {};
  StrictObject o = scenario.object("probes");
  const int given = int(o.has("points")) + int(o.has("file")) + int(o.has("truth_cube"));
  if (given != 1) o.fail("points", "give one of points, file or truth_cube");
  if (o.has("truth_cube")) {
    ScenarioProbes out = truth_cube_probes(o, base_dir, data, mesh);
    o.finish();
    return out;
  }
  std::vector<Eigen::Vector3d> points;
  if (o.has("points")) {
    const nlohmann::json& p = o.raw("points");
    if (!p.is_array() || p.empty()) o.fail("points", "must be a non-empty array of [x, y, z]");
    for (size_t i = 0; i < p.size(); ++i) {
      const nlohmann::json& x = p[i];
      bool ok = x.is_array() && x.size() == 3;
      for (size_t k = 0; ok && k < 3; ++k) ok = x[k].is_number() && std::isfinite(x[k].get<double>());
      if (!ok) o.fail("points[" + std::to_string(i) + "]", "must be [x, y, z] of finite numbers, found " + shown(x));
      points.emplace_back(x[0].get<double>(), x[1].get<double>(), x[2].get<double>());
    }
  } else {
    const std::string name = o.text("file", std::nullopt);
    const std::filesystem::path path = std::filesystem::path(o.directory_of("file", base_dir)) / name;
    std::ifstream in(path);
    if (!in) o.fail("file", path.string() + ": cannot open file");
    std::string line;
    std::getline(in, line);  // header
    for (int n = 2; std::getline(in, line); ++n) {
      if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
      std::istringstream ls(line);
      Eigen::Vector3d x;
      char c1 = 0, c2 = 0;
      std::string rest;
      if (!(ls >> x(0) >> c1 >> x(1) >> c2 >> x(2)) || c1 != ',' || c2 != ',' || !x.allFinite() || (ls >> rest))
        o.fail("file", path.string() + ": line " + std::to_string(n) + ": expected x,y,z, found '" +
                           line.substr(0, 120) + (line.size() > 120 ? "...'" : "'"));
      points.push_back(x);
    }
    if (points.empty()) o.fail("file", path.string() + ": no points");
  }
  o.finish();
  Points out(static_cast<Eigen::Index>(points.size()), 3);
  for (size_t i = 0; i < points.size(); ++i) out.row(static_cast<Eigen::Index>(i)) = points[i].transpose();
  return {out, nlohmann::json::object()};
}

nlohmann::json to_json(const ScenarioLoad& l) {
  nlohmann::json j = {{"key", l.load.key}, {"type", name(l.load.kind)}, {"schedule", l.schedule.to_json()}};
  if (l.load.kind != LoadKind::BodyForce) j["point"] = vec(l.load.point);
  if (l.load.kind == LoadKind::SurfaceTraction) j["radius"] = l.load.radius;
  return j;
}

nlohmann::json to_json(const ScenarioTool& t) {
  nlohmann::json j = {{"key", t.tool.key}, {"type", name(t.tool.kind)}, {"schedule", t.schedule.to_json()}};
  if (t.tool.holds_a_disc()) {
    j["point"] = vec(t.tool.point);
    j["radius"] = t.tool.radius;
    if (t.tool.kind == ToolKind::CompliantGrasp) {
      j["pad_stiffness"] = t.tool.pad_stiffness;
      j["pad_profile"] = t.tool.smooth_pads ? "smooth" : "uniform";
    }
  } else if (t.tool.kind == ToolKind::Sphere) {
    j["radius"] = t.tool.radius;
  } else {
    j["box"] = {{"min", vec(t.tool.box.min)}, {"max", vec(t.tool.box.max)}};
    if (t.tool.kind == ToolKind::SlidingPlate)
      j["normal"] = std::string(1, static_cast<char>('x' + t.tool.normal_axis));
  }
  return j;
}

}  // namespace tb
