// Small helpers the text mesh readers share: a line cursor that reports line
// numbers, and number parsing that names the file and line when it fails.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "mesh_error.h"

namespace tb::detail {

/// Splits on whitespace.
std::vector<std::string> split_whitespace(const std::string& line);

/// Walks the lines of a text file, skipping blank lines and those starting with
/// `comment` (if non-zero), and throws "truncated" when asked past the end.
class LineCursor {
 public:
  LineCursor(std::string file, const std::string& text, char comment);
  /// Next non-blank, non-comment line split into tokens; throws MeshError
  /// "<file>: truncated file (expected <what>)" at end of input.
  std::vector<std::string> next(const std::string& what);
  bool at_end();
  int line_number() const { return line_no_; }
  const std::string& file() const { return file_; }
  [[noreturn]] void fail(const std::string& problem) const;

 private:
  std::string file_;
  std::istringstream in_;
  char comment_;
  int line_no_ = 0;
  std::vector<std::string> peeked_;
  bool has_peeked_ = false;
};

double to_double(const LineCursor& c, const std::string& token);
long to_long(const LineCursor& c, const std::string& token);

}  // namespace tb::detail

namespace tb::detail {

/// Points and cells of one VTK cell type read from an ASCII .vtu (vtu_io.cc).
///   V      #V by 3 points
///   cells  #C by nodes_per_cell point indices of the cells of type vtk_cell_type
struct VtuCells {
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> V;
  Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> cells;
};
VtuCells read_vtu_cells(const std::string& file, int vtk_cell_type, int nodes_per_cell);

}  // namespace tb::detail
