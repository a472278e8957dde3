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

/// The most memory a reader allocates for the items a file's header announces
/// (nodes, tetrahedra, faces, PLY elements): a count that would need more is refused
/// with an error naming the file, before anything is allocated. Counts are also
/// refused when the rest of the file cannot hold that many items (LineCursor::count).
inline constexpr size_t kMaxReaderBytes = size_t{16} << 30;

/// Throws MeshError naming `file` when `count` items of `bytes_per_item` exceed
/// kMaxReaderBytes.
void check_allocation(const std::string& file, size_t count, size_t bytes_per_item, const std::string& what);

/// `token` cut to `max_chars` (with "..."), for quoting input in a message.
std::string shown(const std::string& token, size_t max_chars = 60);

/// Splits on whitespace.
std::vector<std::string> split_whitespace(const std::string& line);

/// The cells of one comma-separated line, each without the blanks around it (spaces,
/// tabs, a carriage return); "a,,b" has an empty middle cell and a trailing comma an
/// empty last one. No quoting: the project's tables hold none.
std::vector<std::string> split_commas(const std::string& line);

/// Walks the lines of a text file, skipping blank lines and those starting with
/// `comment` (if non-zero), and throws "truncated" when asked past the end.
class LineCursor {
 public:
  LineCursor(std::string file, const std::string& text, char comment);
  /// Next non-blank, non-comment line split into tokens; throws MeshError
  /// "<file>: truncated file (expected <what>)" at end of input.
  std::vector<std::string> next(const std::string& what);
  bool at_end();
  /// A count from a header: a non-negative integer no larger than the rest of the
  /// file can hold (each item at least `min_bytes_in_file` bytes) and whose items
  /// (`bytes_per_item` each in memory) fit in kMaxReaderBytes; else fail() naming
  /// `what`.
  long count(const std::string& token, const std::string& what, size_t bytes_per_item, size_t min_bytes_in_file = 2);
  /// Bytes of the text not yet read.
  size_t bytes_left();
  int line_number() const { return line_no_; }
  const std::string& file() const { return file_; }
  [[noreturn]] void fail(const std::string& problem) const;

 private:
  std::string file_;
  std::istringstream in_;
  size_t size_;
  char comment_;
  int line_no_ = 0;
  std::vector<std::string> peeked_;
  bool has_peeked_ = false;
  size_t peeked_bytes_ = 0;
};

/// `token` as a finite number, else c.fail() quoting it; `what` (a column's name, say)
/// leads the message when given.
double to_double(const LineCursor& c, const std::string& token, const std::string& what = "");
long to_long(const LineCursor& c, const std::string& token, const std::string& what = "");

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
