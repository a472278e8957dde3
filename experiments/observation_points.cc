#include "observation_points.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <regex>
#include <stdexcept>

#include "csv_reader.h"
#include "data_dir.h"
#include "runner.h"
#include "strict_json.h"

namespace tb {
namespace fs = std::filesystem;

std::string default_observation_points_dir() {
  return (fs::path(source_dir()) / "results" / "observation_points").string();
}

std::string shown_path(const std::string& path) {
  const fs::path relative = fs::absolute(path).lexically_normal().lexically_relative(source_dir());
  return !relative.empty() && *relative.begin() != ".." ? relative.string() : path;
}

namespace {

/// The most a role's observation file may hold: the largest role has a few thousand rows.
constexpr size_t kMaxObservationFileBytes = size_t{64} << 20;

/// The rows of `file` (a header naming `id` and, for surface points, `patch`): their
/// ids and patches, and their rest positions: x, y, z, or the row of `by_index` (#N by
/// 3) that `index_column` names where the file gives that column instead.
struct PointRows {
  std::vector<std::string> id, patch;
  Points X = Points(0, 3);
};
PointRows read_points(const std::string& file, bool with_patch, const std::string& index_column, const Points& by_index,
                      const std::string& what) {
  CsvReader csv(file, kMaxObservationFileBytes);
  const int id = csv.require_column("id");
  const int patch = with_patch ? csv.require_column("patch") : -1;
  const int x = csv.column("x"), y = csv.column("y"), z = csv.column("z"), index = csv.column(index_column);
  const bool xyz = x >= 0 && y >= 0 && z >= 0;
  if (!xyz && index < 0) csv.fail("the header has neither x,y,z nor " + index_column);
  PointRows out;
  std::vector<Eigen::Vector3d> rows;
  while (csv.next()) {
    out.id.push_back(csv.cell(id));
    if (with_patch) out.patch.push_back(csv.cell(patch));
    if (xyz) {
      rows.emplace_back(csv.number(x), csv.number(y), csv.number(z));
      continue;
    }
    const long k = csv.integer(index);
    if (k < 0 || k >= by_index.rows())
      csv.fail(index_column + " " + std::to_string(k) + " is outside " + what + " (" + std::to_string(by_index.rows()) +
               " rows)");
    rows.emplace_back(by_index.row(k).transpose());
  }
  out.X.resize(static_cast<Eigen::Index>(rows.size()), 3);
  for (size_t r = 0; r < rows.size(); ++r) out.X.row(static_cast<Eigen::Index>(r)) = rows[r].transpose();
  return out;
}

void check_count(const std::string& file, const nlohmann::json& meta, const std::string& key, size_t count,
                 const std::string& json_file) {
  if (meta.contains(key) && meta[key].is_number_integer() && meta[key].get<long>() != static_cast<long>(count))
    throw std::runtime_error(file + ": " + std::to_string(count) + " points, " + json_file + " says " + key + " " +
                             meta[key].dump());
}

}  // namespace

std::string observation_role(const std::string& dir, const std::string& role) {
  const auto has_files = [&](const std::string& r) { return fs::exists(fs::path(dir) / (r + ".json")); };
  if (has_files(role)) return role;
  static const std::regex finer_study(R"((.+)_\d+k)");
  std::smatch m;
  if (std::regex_match(role, m, finer_study) && has_files(m[1].str())) return m[1].str();
  return role;
}

ObservationPoints read_observation_points(const std::string& dir, const Scenario& s, const SurfaceMesh& surface) {
  if (s.role.empty())
    throw std::runtime_error(s.file + ": scenario '" + s.name + "' has no role: observation points are per suite role");
  ObservationPoints out;
  out.role = observation_role(dir, s.role);
  const fs::path base = fs::path(dir) / out.role;
  const std::string json_file = base.string() + ".json", csv_file = base.string() + ".csv";
  const nlohmann::json meta = read_json_file(json_file);
  if (!meta.is_object()) throw std::runtime_error(json_file + ": not a JSON object");
  PointRows surface_rows = read_points(csv_file, true, "source_vertex", surface.V, "the built fine surface's vertices");
  out.surface_id = std::move(surface_rows.id);
  out.surface_patch = std::move(surface_rows.patch);
  out.surface = std::move(surface_rows.X);
  check_count(csv_file, meta, "surface_points", out.surface_id.size(), json_file);
  out.source = {{"surface_points", shown_path(csv_file)}, {"description", shown_path(json_file)}};
  for (const char* key : {"patch", "patch_description"})
    if (meta.contains(key)) out.source[key] = meta[key];
  const long interior = meta.value("interior_points", 0L);
  if (interior > 0) {
    const std::string file = base.string() + "_interior.csv";
    PointRows rows = read_points(file, false, "table_row", s.probes, "the scenario's probes");
    out.interior_id = std::move(rows.id);
    out.interior = std::move(rows.X);
    check_count(file, meta, "interior_points", out.interior_id.size(), json_file);
    out.source["interior_points"] = shown_path(file);
  }
  return out;
}

ObservationPoints scenario_observation_points(const Scenario& s, const SurfaceMesh& surface) {
  ObservationPoints out;
  const std::vector<int> observed = observed_vertices(s, surface.V);
  const std::string patch = s.observed == "all" ? "whole_surface" : "top_face";
  out.surface.resize(static_cast<Eigen::Index>(observed.size()), 3);
  for (size_t k = 0; k < observed.size(); ++k) {
    out.surface_id.push_back("s" + std::to_string(observed[k]));
    out.surface_patch.push_back(patch);
    out.surface.row(static_cast<Eigen::Index>(k)) = surface.V.row(observed[k]);
  }
  out.interior = s.probes;
  for (Eigen::Index p = 0; p < s.probes.rows(); ++p) out.interior_id.push_back("p" + std::to_string(p));
  out.source = {{"surface_points", "the scenario's observed vertices (observe.vertices " + s.observed + ")"},
                {"patch", patch}};
  if (s.probes.rows() > 0) out.source["interior_points"] = "the scenario's probes";
  return out;
}

}  // namespace tb
