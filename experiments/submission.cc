#include "submission.h"

#include <algorithm>
#include <climits>
#include <filesystem>
#include <set>
#include <unordered_map>

#include "csv_reader.h"
#include "mesh_error.h"
#include "problem_package.h"  // kProblemFormat, kSubmissionFormat
#include "strict_json.h"

namespace tb {
namespace fs = std::filesystem;

namespace {

constexpr size_t kMaxPackageFileBytes = size_t{256} << 20;  ///< problem.json, the point files
constexpr size_t kMaxSubmissionJsonBytes = size_t{1} << 20;
constexpr size_t kBytesPerRow = 256;  ///< "frame,id,ux,uy,uz" of 17-digit numbers takes about 80

std::string path_in(const std::string& dir, const std::string& name) { return (fs::path(dir) / name).string(); }

/// The ids of a package's point file (its `id` column), each once.
std::vector<std::string> read_point_ids(const std::string& file) {
  CsvReader r(file, kMaxPackageFileBytes);
  const int id = r.require_column("id");
  std::vector<std::string> ids;
  std::set<std::string> seen;
  while (r.next()) {
    if (r.cell(id).empty()) r.fail("an empty id");
    if (!seen.insert(r.cell(id)).second) r.fail("id '" + detail::shown(r.cell(id)) + "' appears twice");
    ids.push_back(r.cell(id));
  }
  if (ids.empty()) r.fail("no points after the header");
  return ids;
}

/// observation.frames: a non-empty increasing list of frames of the scenario.
std::vector<int> read_observation_frames(StrictObject& observation, int frames) {
  const nlohmann::json& list = observation.raw("frames");
  if (!list.is_array() || list.empty()) observation.fail("frames", "must be a non-empty list of frames");
  std::vector<int> out;
  for (const nlohmann::json& f : list) {
    if (!f.is_number_integer() || f.get<long long>() < 0 || f.get<long long>() >= frames)
      observation.fail("frames", shown(f) + " is not a frame of the scenario (0.." + std::to_string(frames - 1) + ")");
    if (!out.empty() && f.get<int>() <= out.back()) observation.fail("frames", "must increase");
    out.push_back(f.get<int>());
  }
  return out;
}

/// Checks submission.json's keys and values against the contract and the package.
void check_submission_json(const nlohmann::json& j, const std::string& file, const ProblemPackage& package) {
  StrictObject o(j, file);
  o.text("format", std::nullopt, {kSubmissionFormat});
  if (const std::string s = o.text("scenario", std::nullopt); s != package.scenario)
    o.fail("scenario", "'" + s + "', but the package is scenario '" + package.scenario + "' (problem.json)");
  if (const std::string r = o.text("role", std::nullopt); r != package.role)
    o.fail("role", "'" + r + "', but the package's role is '" + package.role + "' (problem.json)");
  if (o.text("method", std::nullopt).empty()) o.fail("method", "must name the method");
  StrictObject resolution = o.object("resolution");
  resolution.text("description", std::nullopt);
  resolution.integer("surface_vertices", std::nullopt, 0, INT_MAX);
  resolution.integer("tets", std::nullopt, 0, INT_MAX);
  resolution.finish();
  // The units are required, and only the contract's: a time in seconds or a length
  // in millimetres would otherwise be scored a thousand times off.
  StrictObject units = o.object("units");
  units.text("length", std::nullopt, {"m"});
  units.text("force", std::nullopt, {"N"});
  units.text("time", std::nullopt, {"ms"});
  units.text("memory", std::nullopt, {"MiB"});
  units.finish();
  StrictObject timing = o.object("timing");
  const double median = timing.number("frame_median_ms", std::nullopt, 0, 1e12);
  if (timing.number("frame_p95_ms", std::nullopt, 0, 1e12) < median)
    timing.fail("frame_p95_ms", "below frame_median_ms");
  timing.number("setup_s", std::nullopt, 0, 1e12);
  timing.finish();
  o.number("peak_memory_mib", std::nullopt, 0, 1e12);
  o.integer("threads", std::nullopt, 1, 1 << 20);
  StrictObject machine = o.object("machine");
  machine.text("cpu", std::nullopt);
  machine.integer("cores", std::nullopt, 1, 1 << 20);
  machine.finish();
  StrictObject calibration = o.object("calibration");
  calibration.number("figure_ms", std::nullopt, 1e-6, 1e12);
  calibration.text("command", std::nullopt, {"tissuebench calibrate"});
  calibration.finish();
  o.text("provenance", std::nullopt);
  o.finish();
}

/// A CSV of `frame,<key>,<x>,<y>,<z>` rows: frames increasing, each in 0..frames-1,
/// each with one row per key of `keys` (any order). values[f] is #keys by 3.
struct FrameTable {
  std::vector<int> frames;
  std::vector<Points> values;
};

FrameTable read_frame_table(const std::string& file, size_t max_bytes, const std::vector<std::string>& header,
                            const std::vector<std::string>& keys, int frames, const std::string& key_what) {
  CsvReader r(file, max_bytes);
  r.expect_header(header);
  std::unordered_map<std::string, size_t> index;
  for (size_t k = 0; k < keys.size(); ++k) index.emplace(keys[k], k);
  FrameTable t;
  std::vector<bool> seen;
  size_t count = 0;
  auto check_complete = [&] {
    if (count == keys.size()) return;
    const size_t k = static_cast<size_t>(std::find(seen.begin(), seen.end(), false) - seen.begin());
    r.fail("frame " + std::to_string(t.frames.back()) + " has no row for " + key_what + " '" + keys[k] +
           "' (every one once a frame; " + std::to_string(keys.size() - count) + " missing)");
  };
  while (r.next()) {
    const long frame = r.integer(0);
    if (frame < 0 || frame >= frames)
      r.fail("frame " + std::to_string(frame) + " is not a frame of the scenario (0.." + std::to_string(frames - 1) +
             ", problem.json time.frames)");
    if (t.frames.empty() || frame != t.frames.back()) {
      if (!t.frames.empty()) {
        if (frame < t.frames.back())
          r.fail("frame " + std::to_string(frame) + " after frame " + std::to_string(t.frames.back()) +
                 ": frames must increase, each frame's rows together");
        check_complete();
      }
      t.frames.push_back(static_cast<int>(frame));
      t.values.push_back(Points::Zero(static_cast<Eigen::Index>(keys.size()), 3));
      seen.assign(keys.size(), false);
      count = 0;
    }
    const auto it = index.find(r.cell(1));
    if (it == index.end())
      r.fail(header[1] + " '" + detail::shown(r.cell(1)) + "' is not one of the package's " + key_what + "s");
    if (seen[it->second]) r.fail(key_what + " '" + it->first + "' twice in frame " + std::to_string(frame));
    seen[it->second] = true;
    ++count;
    for (int c = 0; c < 3; ++c) t.values.back()(static_cast<Eigen::Index>(it->second), c) = r.number(2 + c);
  }
  if (!t.frames.empty()) check_complete();
  return t;
}

std::string listed(const std::vector<int>& values) {
  std::string out;
  for (int v : values) out += (out.empty() ? "" : ", ") + std::to_string(v);
  return out;
}

}  // namespace

std::vector<std::string> ProblemPackage::point_ids() const {
  std::vector<std::string> ids = surface_ids;
  ids.insert(ids.end(), interior_ids.begin(), interior_ids.end());
  return ids;
}

ProblemPackage read_problem_package(const std::string& dir) {
  ProblemPackage p;
  p.dir = dir;
  const std::string file = path_in(dir, "problem.json");
  check_file_size(file, kMaxPackageFileBytes);
  StrictObject o(read_json_file(file), file);  // the keys score reads; the rest is the simulator's
  o.text("format", std::nullopt, {kProblemFormat});
  p.scenario = o.text("scenario", std::nullopt);
  p.role = o.text("role", std::string());
  StrictObject time = o.object("time");
  p.frames = time.integer("frames", std::nullopt, 1, INT_MAX);
  StrictObject observation = o.object("observation");
  p.observation_frames = read_observation_frames(observation, p.frames);
  p.surface_ids = read_point_ids(path_in(dir, observation.text("surface_points", std::nullopt)));
  const std::string interior = observation.text("interior_points", std::string());
  if (!interior.empty()) p.interior_ids = read_point_ids(path_in(dir, interior));
  std::set<std::string> ids(p.surface_ids.begin(), p.surface_ids.end());
  for (const std::string& id : p.interior_ids)
    if (ids.count(id)) throw MeshError(path_in(dir, interior), "id '" + id + "' is a surface point's id too");
  const nlohmann::json& tools = o.raw("tools");
  if (!tools.is_null() && !tools.is_array()) o.fail("tools", "must be a list");
  for (size_t k = 0; k < tools.size(); ++k) {
    StrictObject tool = o.item("tools", k);
    p.tools.push_back(tool.text("name", std::nullopt));
    if (std::count(p.tools.begin(), p.tools.end(), p.tools.back()) > 1) tool.fail("name", "repeated");
  }
  return p;
}

int Submission::frame_index(int frame) const {
  const auto it = std::find(frames.begin(), frames.end(), frame);
  return it == frames.end() ? -1 : static_cast<int>(it - frames.begin());
}

std::vector<std::string> submission_files(const ProblemPackage& package) {
  std::vector<std::string> files{"submission.json", "displacements.csv"};
  if (!package.tools.empty()) files.push_back("forces.csv");
  return files;
}

size_t submission_file_bound(const ProblemPackage& package, const std::string& file) {
  if (file == "submission.json") return kMaxSubmissionJsonBytes;
  const size_t per_frame = file == "forces.csv" ? package.tools.size() : package.point_ids().size();
  return (static_cast<size_t>(package.frames) * per_frame + 1) * kBytesPerRow + (size_t{64} << 10);
}

Submission read_submission(const std::string& dir, const ProblemPackage& package) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw MeshError(dir, "not a folder (a submission is a folder of files)");
  const std::vector<std::string> files = submission_files(package);
  std::string holds;
  for (const std::string& f : files) holds += (holds.empty() ? "" : ", ") + f;
  std::vector<std::string> present;
  for (const auto& entry : fs::directory_iterator(dir, ec)) present.push_back(entry.path().filename().string());
  std::sort(present.begin(), present.end());
  for (const std::string& name : present)
    if (name != "score.json" && std::find(files.begin(), files.end(), name) == files.end())
      throw MeshError(path_in(dir, name), std::string("unexpected file: a submission holds ") + holds +
                                              (package.tools.empty() ? " (the scenario has no tools)" : "") +
                                              " and nothing else");
  for (const std::string& name : files)
    if (std::find(present.begin(), present.end(), name) == present.end())
      throw MeshError(path_in(dir, name), "missing: a submission holds " + holds);

  Submission s;
  s.dir = dir;
  const std::string json_file = path_in(dir, "submission.json");
  check_file_size(json_file, submission_file_bound(package, "submission.json"));
  s.meta = read_json_file(json_file);
  check_submission_json(s.meta, json_file, package);

  const std::string displacements = path_in(dir, "displacements.csv");
  FrameTable u =
      read_frame_table(displacements, submission_file_bound(package, "displacements.csv"),
                       {"frame", "id", "ux", "uy", "uz"}, package.point_ids(), package.frames, "observation point");
  for (int f : package.observation_frames)
    if (std::find(u.frames.begin(), u.frames.end(), f) == u.frames.end())
      throw MeshError(displacements, "no rows for frame " + std::to_string(f) +
                                         ", an observation frame of the package (problem.json observation.frames: " +
                                         listed(package.observation_frames) + ")");
  s.frames = std::move(u.frames);
  s.displacements = std::move(u.values);
  if (!package.tools.empty()) {
    const std::string forces = path_in(dir, "forces.csv");
    FrameTable f = read_frame_table(forces, submission_file_bound(package, "forces.csv"),
                                    {"frame", "tool", "fx", "fy", "fz"}, package.tools, package.frames, "tool");
    if (f.frames != s.frames)
      throw MeshError(forces, "frames " + detail::shown(listed(f.frames)) + ", but displacements.csv reports " +
                                  detail::shown(listed(s.frames)) + ": a force for every reported frame");
    s.forces = std::move(f.values);
  }
  return s;
}

}  // namespace tb
