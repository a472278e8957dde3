#include "csv_reader.h"

#include <filesystem>

#include "atomic_file.h"
#include "mesh_error.h"

namespace tb {
namespace {

/// The cells of the cursor's next line: its tokens (split on blanks) joined by one
/// space, then split on commas, so "0, s1, 1e-3" and "0,s1,1e-3" read alike and a
/// blank inside a cell ("1 2") stays in it, to be refused as a number.
std::vector<std::string> next_cells(detail::LineCursor& cursor, const std::string& what) {
  std::string line;
  for (const std::string& token : cursor.next(what)) line += (line.empty() ? "" : " ") + token;
  return detail::split_commas(line);
}

std::string joined(const std::vector<std::string>& cells) {
  std::string out;
  for (const std::string& c : cells) out += (out.empty() ? "" : ",") + c;
  return out;
}

}  // namespace

void check_file_size(const std::string& file, size_t max_bytes) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) throw MeshError(file, "missing (or not a regular file)");
  const auto size = std::filesystem::file_size(file, ec);
  if (ec) throw MeshError(file, "cannot read its size");
  if (size > max_bytes)
    throw MeshError(file, std::to_string(size) + " bytes, more than the " + std::to_string(max_bytes) +
                              " this file can need; not read");
}

CsvReader::CsvReader(const std::string& file, size_t max_bytes)
    : cursor_(file, (check_file_size(file, max_bytes), read_file(file)), 0) {
  header_ = next_cells(cursor_, "the header line");
}

int CsvReader::column(const std::string& name) const {
  for (size_t k = 0; k < header_.size(); ++k)
    if (header_[k] == name) return static_cast<int>(k);
  return -1;
}

int CsvReader::require_column(const std::string& name) const {
  const int k = column(name);
  if (k < 0) fail("the header has no column '" + name + "' (found '" + detail::shown(joined(header_)) + "')");
  return k;
}

void CsvReader::expect_header(const std::vector<std::string>& columns) const {
  if (header_ != columns)
    fail("expected the header '" + joined(columns) + "', found '" + detail::shown(joined(header_)) + "'");
}

bool CsvReader::next() {
  if (cursor_.at_end()) return false;
  cells_ = next_cells(cursor_, "a row");
  if (cells_.size() != header_.size())
    fail(std::to_string(cells_.size()) + " cells, the header has " + std::to_string(header_.size()) + " (" +
         detail::shown(joined(header_)) + ")");
  return true;
}

double CsvReader::number(int column) const {
  return detail::to_double(cursor_, cell(column), header_.at(static_cast<size_t>(column)));
}

long CsvReader::integer(int column) const {
  return detail::to_long(cursor_, cell(column), header_.at(static_cast<size_t>(column)));
}

}  // namespace tb
