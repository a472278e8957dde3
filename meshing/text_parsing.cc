#include "text_parsing.h"

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <iomanip>

namespace tb {

std::string one_line(const std::string& text, size_t max_chars) {
  static const char* const kHex = "0123456789abcdef";
  std::string out;
  out.reserve(std::min(text.size(), max_chars) + 16);
  size_t i = 0;
  for (; i < text.size() && out.size() < max_chars; ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c == '\n')
      out += "\\n";
    else if (c == '\r')
      out += "\\r";
    else if (c == '\t')
      out += ' ';
    else if (c < 0x20 || c == 0x7f)
      out += std::string("\\x") + kHex[c >> 4] + kHex[c & 15];
    else
      out += static_cast<char>(c);
  }
  if (i < text.size()) out += " ... (" + std::to_string(text.size() - i) + " more characters)";
  return out;
}

}  // namespace tb

namespace tb::detail {

std::string shown(const std::string& token, size_t max_chars) {
  if (token.size() <= max_chars) return token;
  return token.substr(0, max_chars) + "...";
}

std::vector<std::string> split_whitespace(const std::string& line) {
  std::vector<std::string> out;
  std::istringstream ss(line);
  std::string tok;
  while (ss >> tok) out.push_back(tok);
  return out;
}

std::vector<std::string> split_commas(const std::string& line) {
  std::vector<std::string> cells;
  for (size_t start = 0;;) {
    const size_t comma = line.find(',', start);
    const std::string cell = line.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    const size_t first = cell.find_first_not_of(" \t\r");
    cells.push_back(first == std::string::npos ? "" : cell.substr(first, cell.find_last_not_of(" \t\r") - first + 1));
    if (comma == std::string::npos) return cells;
    start = comma + 1;
  }
}

LineCursor::LineCursor(std::string file, const std::string& text, char comment)
    : file_(std::move(file)), in_(text), size_(text.size()), comment_(comment) {}

size_t LineCursor::bytes_left() {
  const auto at = in_.tellg();
  return (at < 0 ? 0 : size_ - static_cast<size_t>(at)) + (has_peeked_ ? peeked_bytes_ : 0);
}

long LineCursor::count(const std::string& token, const std::string& what, size_t bytes_per_item,
                       size_t min_bytes_in_file) {
  const long n = to_long(*this, token);
  if (n < 0) fail("negative " + what + " count " + token);
  // Each item takes at least min_bytes_in_file of what is left of the file (a
  // number and a line end): a larger count is a damaged header, refused before
  // anything is allocated for it.
  const size_t room = bytes_left() / std::max<size_t>(min_bytes_in_file, 1);
  if (static_cast<unsigned long>(n) > room)
    fail("truncated file: the header says " + token + " " + what +
         ", more than the rest of the file can hold (at most " + std::to_string(room) + ")");
  check_allocation(file_, static_cast<size_t>(n), bytes_per_item, what);
  return n;
}

bool LineCursor::at_end() {
  if (has_peeked_) return false;
  std::string line;
  while (std::getline(in_, line)) {
    ++line_no_;
    auto toks = split_whitespace(line);
    if (toks.empty()) continue;
    if (comment_ && toks[0][0] == comment_) continue;
    peeked_ = std::move(toks);
    peeked_bytes_ = line.size() + 1;
    has_peeked_ = true;
    return false;
  }
  return true;
}

std::vector<std::string> LineCursor::next(const std::string& what) {
  if (at_end()) throw MeshError(file_, "truncated file (expected " + what + ")");
  has_peeked_ = false;
  return std::move(peeked_);
}

void LineCursor::fail(const std::string& problem) const {
  throw MeshError(file_, "line " + std::to_string(line_no_) + ": " + problem);
}

void check_allocation(const std::string& file, size_t count, size_t bytes_per_item, const std::string& what) {
  if (bytes_per_item == 0 || count <= kMaxReaderBytes / bytes_per_item) return;
  std::ostringstream need;
  need << std::setprecision(3) << static_cast<double>(count) * static_cast<double>(bytes_per_item) / (1ull << 30);
  throw MeshError(file, std::to_string(count) + " " + what + " would need " + need.str() +
                            " GiB, more than the readers' limit of " + std::to_string(kMaxReaderBytes >> 30) +
                            " GiB (kMaxReaderBytes, meshing/text_parsing.h)");
}

double to_double(const LineCursor& c, const std::string& token, const std::string& what) {
  const std::string lead = what.empty() ? "" : what + ": ";
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(token.c_str(), &end);
  // end must be the token's end: a NUL byte inside a token is not its end.
  if (end != token.c_str() + token.size() || token.empty() || errno == ERANGE)
    c.fail(lead + "expected a number, found '" + shown(token) + "'");
  if (!std::isfinite(v)) c.fail((what.empty() ? "coordinate" : what) + " is NaN or Inf ('" + shown(token) + "')");
  return v;
}

long to_long(const LineCursor& c, const std::string& token, const std::string& what) {
  errno = 0;
  char* end = nullptr;
  const long v = std::strtol(token.c_str(), &end, 10);
  if (end != token.c_str() + token.size() || token.empty() || errno == ERANGE)
    c.fail((what.empty() ? "" : what + ": ") + "expected an integer, found '" + shown(token) + "'");
  return v;
}

}  // namespace tb::detail
