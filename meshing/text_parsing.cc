#include "text_parsing.h"

#include <cerrno>
#include <cstdlib>

namespace tb::detail {

std::vector<std::string> split_whitespace(const std::string& line) {
  std::vector<std::string> out;
  std::istringstream ss(line);
  std::string tok;
  while (ss >> tok) out.push_back(tok);
  return out;
}

LineCursor::LineCursor(std::string file, const std::string& text, char comment)
    : file_(std::move(file)), in_(text), comment_(comment) {}

bool LineCursor::at_end() {
  if (has_peeked_) return false;
  std::string line;
  while (std::getline(in_, line)) {
    ++line_no_;
    auto toks = split_whitespace(line);
    if (toks.empty()) continue;
    if (comment_ && toks[0][0] == comment_) continue;
    peeked_ = std::move(toks);
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

double to_double(const LineCursor& c, const std::string& token) {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(token.c_str(), &end);
  if (end == token.c_str() || *end != '\0' || errno == ERANGE) c.fail("expected a number, found '" + token + "'");
  if (!std::isfinite(v)) c.fail("coordinate is NaN or Inf ('" + token + "')");
  return v;
}

long to_long(const LineCursor& c, const std::string& token) {
  errno = 0;
  char* end = nullptr;
  const long v = std::strtol(token.c_str(), &end, 10);
  if (end == token.c_str() || *end != '\0' || errno == ERANGE) c.fail("expected an integer, found '" + token + "'");
  return v;
}

}  // namespace tb::detail
