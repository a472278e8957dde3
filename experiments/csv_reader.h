// Comma-separated tables as the benchmark's files hold them (docs/benchmark_format.md):
// a header line naming the columns, then rows of as many cells; blank lines skipped.
// Read row by row through meshing/text_parsing.h's LineCursor, so every error is one
// line "<file>: line <n>: <problem>" (MeshError), and a file larger than the bound
// its caller gives is refused before it is read.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "text_parsing.h"

namespace tb {

class CsvReader {
 public:
  /// Reads `file` whole unless it is larger than `max_bytes` (then MeshError naming the
  /// file, its size and the bound) or cannot be opened; reads its header line.
  CsvReader(const std::string& file, size_t max_bytes);
  const std::string& file() const { return cursor_.file(); }
  const std::vector<std::string>& header() const { return header_; }
  /// The index of column `name`; -1 if the header has none.
  int column(const std::string& name) const;
  /// The index of column `name`; fail() naming the header if it has none.
  int require_column(const std::string& name) const;
  /// fail() unless the header is exactly `columns`, in that order.
  void expect_header(const std::vector<std::string>& columns) const;
  /// Moves to the next row; false at the end. A row of another cell count than the
  /// header's is an error.
  bool next();
  const std::string& cell(int column) const { return cells_.at(static_cast<size_t>(column)); }
  /// The cell as a finite number / an integer; else fail() naming the column.
  double number(int column) const;
  long integer(int column) const;
  int line() const { return cursor_.line_number(); }
  /// Throws MeshError "<file>: line <n>: <problem>" (the header's line before next()).
  [[noreturn]] void fail(const std::string& problem) const { cursor_.fail(problem); }

 private:
  detail::LineCursor cursor_;
  std::vector<std::string> header_;
  std::vector<std::string> cells_;
};

/// Throws MeshError naming `file` if it is not a regular file, or is larger than
/// `max_bytes` (its size and the bound in the message); the check before a read.
void check_file_size(const std::string& file, size_t max_bytes);

}  // namespace tb
