#include "truth_cube.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include "mesh_error.h"
#include "text_parsing.h"

namespace tb {
namespace {

using detail::split_commas;

constexpr int kHeaderLines = 7;
constexpr int kStrainLabelLine = 6;  // "bead nominal location,,,no strain,,,5% strain,..."
constexpr int kGrid = 7;

bool parse_number(const std::string& text, double& value) {
  if (text.empty()) return false;
  char* end = nullptr;
  value = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size() && std::isfinite(value);
}

// The strains named by the label line: "no strain" is 0, "12.5% strain" 0.125.
std::vector<double> parse_strain_labels(const std::string& line, const std::string& where) {
  std::vector<double> strains;
  for (const std::string& cell : split_commas(line)) {
    if (cell == "no strain") {
      strains.push_back(0);
    } else if (const auto percent = cell.find("% strain"); percent != std::string::npos) {
      double value = 0;
      if (!parse_number(cell.substr(0, percent), value) || value <= 0 || value >= 100)
        throw std::runtime_error(where + ": cannot read the strain of '" + cell + "'");
      strains.push_back(value / 100);
    }
  }
  if (strains.size() < 2 || strains[0] != 0)
    throw std::runtime_error(where + ": expected 'no strain' then one or more '<p>% strain' labels, found '" + line +
                             "'");
  return strains;
}

TruthCubeTable read_table(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file + ": cannot open the Truth Cube table");
  TruthCubeTable table;
  table.file = file;
  std::string line;
  int n = 0;
  for (; n < kHeaderLines && std::getline(in, line); ++n)
    if (n + 1 == kStrainLabelLine) table.strains = parse_strain_labels(line, file + ": line " + std::to_string(n + 1));
  if (n < kHeaderLines) throw std::runtime_error(file + ": ends within its " + std::to_string(kHeaderLines) +
                                                 " header lines; not a Truth Cube table");
  const size_t columns = 3 + 3 * table.strains.size();
  std::set<std::array<int, 3>> seen;
  while (std::getline(in, line)) {
    ++n;
    const std::string where = file + ": line " + std::to_string(n);
    if (line.find_first_not_of(" ,\r") == std::string::npos) continue;
    const std::vector<std::string> cells = split_commas(line);
    if (cells.size() < columns)
      throw std::runtime_error(where + ": expected " + std::to_string(columns) + " numbers (i, j, k, then x, y, z at " +
                               std::to_string(table.strains.size()) + " strains), found " +
                               std::to_string(cells.size()));
    std::vector<double> v(columns);
    for (size_t c = 0; c < columns; ++c)
      if (!parse_number(cells[c], v[c]))
        throw std::runtime_error(where + ": column " + std::to_string(c + 1) + ": '" + cells[c] +
                                 "' is not a finite number");
    TruthCubeBead bead;
    for (int a = 0; a < 3; ++a) {
      if (v[a] != std::floor(v[a]) || v[a] < 1 || v[a] > kGrid)
        throw std::runtime_error(where + ": grid index " + cells[a] + " is not a whole number in 1.." +
                                 std::to_string(kGrid));
      bead.grid[a] = static_cast<int>(v[a]);
    }
    if (!seen.insert(bead.grid).second)
      throw std::runtime_error(where + ": bead (" + cells[0] + ", " + cells[1] + ", " + cells[2] + ") appears twice");
    for (size_t s = 0; s < table.strains.size(); ++s)
      bead.positions_mm.emplace_back(v[3 + 3 * s], v[4 + 3 * s], v[5 + 3 * s]);
    table.beads.push_back(std::move(bead));
  }
  if (table.beads.empty()) throw std::runtime_error(file + ": no bead rows after the header");
  return table;
}

}  // namespace

TruthCubeTable read_truth_cube_table(const std::string& file) {
  try {
    return read_table(file);
  } catch (const std::runtime_error& e) {
    // The messages quote the file's cells and lines, which may hold a carriage
    // return or control bytes: one line (mesh_error.h), as tests/fuzz requires.
    throw std::runtime_error(one_line(e.what()));
  }
}

Eigen::Vector3d TruthCubeFrame::to_model(const Eigen::Vector3d& table_mm) const {
  return centre_m + (axes.array() * (table_mm - origin_mm).array()).matrix() / 1000.0;
}

nlohmann::json TruthCubeFrame::to_json() const {
  return {{"origin_mm", {origin_mm.x(), origin_mm.y(), origin_mm.z()}},
          {"centre_m", {centre_m.x(), centre_m.y(), centre_m.z()}},
          {"axes", {axes.x(), axes.y(), axes.z()}},
          {"rule", "model = centre_m + axes * (table - origin_mm) / 1000 (mm to m, half a turn about x)"}};
}

TruthCubeFrame truth_cube_frame(const TruthCubeTable& table, double cube_height) {
  TruthCubeFrame frame;
  frame.origin_mm.setZero();
  for (const TruthCubeBead& b : table.beads) frame.origin_mm += b.positions_mm[0];
  frame.origin_mm /= static_cast<double>(table.beads.size());
  frame.centre_m = Eigen::Vector3d(0, 0, cube_height / 2);
  frame.axes = Eigen::Vector3d(1, -1, -1);
  return frame;
}

Points truth_cube_rest_points(const TruthCubeTable& table, const TruthCubeFrame& frame) {
  Points out(static_cast<Eigen::Index>(table.beads.size()), 3);
  for (size_t b = 0; b < table.beads.size(); ++b)
    out.row(static_cast<Eigen::Index>(b)) = frame.to_model(table.beads[b].positions_mm[0]).transpose();
  return out;
}

}  // namespace tb
