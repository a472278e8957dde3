#include "submission_score.h"

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include "csv_reader.h"
#include "strict_json.h"

namespace tb {
namespace fs = std::filesystem;

namespace {

constexpr size_t kMaxAnswerBytes = size_t{256} << 20;

AnswerPoints read_answer_points(const std::string& file) {
  CsvReader r(file, kMaxAnswerBytes);
  AnswerPoints a;
  a.file = file;
  const int id = r.require_column("id");
  const int ux = r.column("ux"), uy = r.column("uy"), uz = r.column("uz"), row = r.column("table_row");
  const bool has_u = ux >= 0 && uy >= 0 && uz >= 0;
  if (!has_u && (ux >= 0 || uy >= 0 || uz >= 0)) r.fail("ux, uy and uz come together or not at all");
  std::vector<Eigen::Vector3d> u;
  while (r.next()) {
    a.ids.push_back(r.cell(id));
    if (has_u) u.emplace_back(r.number(ux), r.number(uy), r.number(uz));
    if (row >= 0) {
      a.table_rows.push_back(r.integer(row));
      if (a.table_rows.back() < 0) r.fail("table_row must not be negative");
    }
  }
  if (a.ids.empty()) r.fail("no points after the header");
  a.u.resize(static_cast<Eigen::Index>(u.size()), 3);
  for (size_t k = 0; k < u.size(); ++k) a.u.row(static_cast<Eigen::Index>(k)) = u[k].transpose();
  return a;
}

/// `values` (rows in `ids` order) in the order of `answers`' ids; throws naming the
/// answers' file unless both name the same points.
Points in_answer_order(const Points& values, const std::vector<std::string>& ids, const AnswerPoints& answers,
                       const std::string& package_file) {
  std::unordered_map<std::string, Eigen::Index> row;
  for (size_t k = 0; k < ids.size(); ++k) row.emplace(ids[k], static_cast<Eigen::Index>(k));
  if (ids.size() != answers.ids.size())
    throw std::runtime_error(answers.file + ": " + std::to_string(answers.ids.size()) + " points, the package's " +
                             package_file + " has " + std::to_string(ids.size()) + ": not the same points");
  Points out(values.rows(), 3);
  for (size_t k = 0; k < answers.ids.size(); ++k) {
    const auto it = row.find(answers.ids[k]);
    if (it == row.end())
      throw std::runtime_error(one_line(answers.file + ": point '" + answers.ids[k] + "' is not in the package's " +
                                        package_file + ": not the same points"));
    out.row(static_cast<Eigen::Index>(k)) = values.row(it->second);
  }
  return out;
}

Eigen::Vector3d vec3(const nlohmann::json& j) {
  return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()};
}

}  // namespace

ObservationAnswers read_observation_answers(const std::string& answers_dir, const std::string& role) {
  ObservationAnswers a;
  a.meta_file = (fs::path(answers_dir) / (role + ".json")).string();
  std::error_code ec;
  if (!fs::is_regular_file(a.meta_file, ec))
    throw std::runtime_error(one_line(a.meta_file + ": missing: no converged answers for role '" + role +
                                      "' (analysis/observation_points.py writes them; --answers names their folder)"));
  a.meta = read_json_file(a.meta_file);
  if (!a.meta.is_object()) throw std::runtime_error(a.meta_file + ": must be a JSON object");
  a.surface = read_answer_points((fs::path(answers_dir) / (role + ".csv")).string());
  const std::string interior = (fs::path(answers_dir) / (role + "_interior.csv")).string();
  if (fs::is_regular_file(interior, ec)) a.interior = read_answer_points(interior);
  return a;
}

double relative_l2(const Points& u, const Points& u_ref) {
  const double ref = u_ref.norm();
  return ref > 0 ? (u - u_ref).norm() / ref : std::nan("");
}

double rms_error_mm(const Points& u, const Points& u_ref) {
  return std::sqrt((u - u_ref).rowwise().squaredNorm().mean()) * 1000;
}

double bead_rms_mm(const TruthCubeTable& table, const nlohmann::json& meta, const std::vector<long>& rows,
                   const Points& u) {
  const nlohmann::json& f = meta.at("frame");
  TruthCubeFrame frame;
  frame.origin_mm = vec3(f.at("origin_mm"));
  frame.centre_m = vec3(f.at("centre_m"));
  frame.axes = vec3(f.at("axes"));
  const double strain = meta.at("compare_at_strain").get<double>();
  size_t column = 0;  // the first nearest, as Python's min() takes it
  for (size_t c = 1; c < table.strains.size(); ++c)
    if (std::abs(table.strains[c] - strain) < std::abs(table.strains[column] - strain)) column = c;
  double sum = 0;
  for (size_t i = 0; i < rows.size(); ++i) {
    const TruthCubeBead& bead = table.beads.at(static_cast<size_t>(rows[i]));
    const Eigen::Vector3d rest = frame.to_model(bead.positions_mm[0]);
    const Eigen::Vector3d measured = frame.to_model(bead.positions_mm[column]);
    sum += ((rest + u.row(static_cast<Eigen::Index>(i)).transpose() - measured) * 1000).squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(rows.size()));
}

ObservationScores score_observations(const ObservationAnswers& answers, const Points& values,
                                     const Points* probe_values, const DataDir& data) {
  ObservationScores s;
  try {
    if (const auto c = answers.meta.find("converged"); c != answers.meta.end() && c->is_object()) {
      s.converged_run = c->value("run", nlohmann::json());
      s.converged_error = c->value("estimated_error", nlohmann::json());
    }
    if (const auto n = answers.meta.find("note"); n != answers.meta.end() && n->is_string()) s.note = *n;
    if (answers.surface.u.rows() > 0) s.rel_l2_converged = relative_l2(values, answers.surface.u);
    if (!probe_values) return s;
    if (!answers.interior)
      throw std::runtime_error(answers.meta_file + ": the role has no interior points, but interior values were given");
    const AnswerPoints& interior = *answers.interior;
    if (interior.u.rows() > 0) s.probe_error_mm = rms_error_mm(*probe_values, interior.u);
    if (!interior.table_rows.empty()) {
      const std::string file = (fs::path(data.path) / "data" / "truthcube" / "uniaxial_positions.csv").string();
      const TruthCubeTable table = read_truth_cube_table(file);
      for (long row : interior.table_rows)
        if (static_cast<size_t>(row) >= table.beads.size())
          throw std::runtime_error(file + ": " + std::to_string(table.beads.size()) + " beads, " + interior.file +
                                   " names row " + std::to_string(row));
      s.bead_rms_mm = bead_rms_mm(table, answers.meta, interior.table_rows, *probe_values);
    }
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(one_line(answers.meta_file + ": " + e.what()));
  }
  return s;
}

nlohmann::json score_submission(const Submission& submission, const ProblemPackage& package,
                                const ScoreOptions& options) {
  const int frame = package.observation_frames.back();
  const Points& all = submission.displacements.at(static_cast<size_t>(submission.frame_index(frame)));
  const auto surface_rows = static_cast<Eigen::Index>(package.surface_ids.size());
  const Points surface = all.topRows(surface_rows);
  const Points interior = all.bottomRows(all.rows() - surface_rows);
  const nlohmann::json& meta = submission.meta;
  nlohmann::json out = {{"format", "tissuebench-score/1"},
                        {"submission", submission.dir},
                        {"package", package.dir},
                        {"scenario", package.scenario},
                        {"role", package.role},
                        {"method", meta["method"]},
                        {"resolution", meta["resolution"]},
                        {"frame", frame}};
  ObservationScores s;
  if (package.role.empty()) {
    s.note = "the package has no suite role: there is no converged answer to score against";
    out["answers"] = nullptr;
  } else {
    const ObservationAnswers answers = read_observation_answers(options.answers_dir, package.role);
    const Points values = in_answer_order(surface, package.surface_ids, answers.surface, "observation_points.csv");
    std::optional<Points> probes;
    if (!package.interior_ids.empty()) {
      if (!answers.interior)
        throw std::runtime_error(answers.meta_file + ": no " + package.role +
                                 "_interior.csv beside it, but the package has interior points");
      probes = in_answer_order(interior, package.interior_ids, *answers.interior, "observation_interior.csv");
    }
    s = score_observations(answers, values, probes ? &*probes : nullptr, options.data);
    out["answers"] = answers.meta_file;
  }
  out["rel_l2_converged"] = s.rel_l2_converged;
  out["probe_error_mm"] = s.probe_error_mm;
  out["bead_rms_mm"] = s.bead_rms_mm;
  out["converged_run"] = s.converged_run;
  out["converged_error"] = s.converged_error;
  out["note"] = s.note;

  const double theirs = meta["calibration"]["figure_ms"].get<double>();
  const double factor = options.machine_figure_ms / theirs;
  auto time = [&](const std::string& key) {
    const double reported = meta["timing"][key].get<double>();
    return nlohmann::json{{"reported", reported}, {"normalised", reported * factor}};
  };
  out["timing"] = {
      {"self_reported", true},
      {"normalised_as", "time * this machine's calibration figure / the submission's (tissuebench calibrate)"},
      {"calibration_ms", {{"submission", theirs}, {"this_machine", options.machine_figure_ms}}},
      {"factor", factor},
      {"frame_median_ms", time("frame_median_ms")},
      {"frame_p95_ms", time("frame_p95_ms")},
      {"setup_s", time("setup_s")}};
  out["peak_memory_mib"] = {{"self_reported", true}, {"reported", meta["peak_memory_mib"]}};
  out["threads"] = meta["threads"];
  out["machine"] = meta["machine"];
  out["this_machine"] = options.machine;
  if (!package.tools.empty()) {
    const Points& f = submission.forces.at(static_cast<size_t>(submission.frame_index(frame)));
    nlohmann::json forces = nlohmann::json::object();
    for (size_t k = 0; k < package.tools.size(); ++k) {
      const auto r = static_cast<Eigen::Index>(k);
      forces[package.tools[k]] = {f(r, 0), f(r, 1), f(r, 2)};
    }
    out["tool_forces_n"] = {{"self_reported", true}, {"not_scored", true}, {"at_frame", forces}};
  }
  return out;
}

std::string score_summary(const nlohmann::json& score) {
  auto number = [](const nlohmann::json& v, int digits) {
    if (!v.is_number() || !std::isfinite(v.get<double>())) return std::string("n/a");
    std::ostringstream s;
    s << std::setprecision(digits) << v.get<double>();
    return s.str();
  };
  const nlohmann::json& t = score["timing"];
  std::ostringstream o;
  o << "tissuebench score: " << score["method"].get<std::string>() << " on " << score["scenario"].get<std::string>()
    << " (role " << (score["role"].get<std::string>().empty() ? "none" : score["role"].get<std::string>())
    << "), frame " << score["frame"] << "\n";
  o << "  rel L2 vs converged  " << number(score["rel_l2_converged"], 4);
  if (score["converged_run"].is_string())
    o << "   (converged run " << score["converged_run"].get<std::string>() << ", its estimated error "
      << number(score["converged_error"], 2) << ")";
  o << "\n  probe RMS (mm)       " << number(score["probe_error_mm"], 4) << "\n";
  o << "  bead RMS (mm)        " << number(score["bead_rms_mm"], 4) << "\n";
  if (!score["note"].get<std::string>().empty()) o << "  note: " << score["note"].get<std::string>() << "\n";
  o << "  self-reported times, normalised to this machine (x" << number(t["factor"], 3) << ": calibration "
    << number(t["calibration_ms"]["this_machine"], 4) << " ms here, " << number(t["calibration_ms"]["submission"], 4)
    << " ms theirs):\n";
  for (const char* key : {"frame_median_ms", "frame_p95_ms", "setup_s"})
    o << "    " << std::left << std::setw(16) << key << number(t[key]["reported"], 4) << " reported, "
      << number(t[key]["normalised"], 4) << " normalised\n";
  o << "  peak memory " << number(score["peak_memory_mib"]["reported"], 4) << " MiB (self-reported), "
    << score["threads"] << " thread(s)\n";
  return o.str();
}

}  // namespace tb
