#include "mutator.h"

#include <algorithm>
#include <utility>

namespace tb::fuzz {

const std::vector<std::string>& interesting_numbers() {
  static const std::vector<std::string> numbers = {"-1",
                                                   "0",
                                                   "1",
                                                   "2",
                                                   "3",
                                                   "4",
                                                   "-0",
                                                   "1e308",
                                                   "-1e308",
                                                   "1e-320",
                                                   "nan",
                                                   "-nan",
                                                   "inf",
                                                   "-inf",
                                                   "NaN",
                                                   "2147483647",
                                                   "2147483648",
                                                   "-2147483649",
                                                   "4294967295",
                                                   "4294967296",
                                                   "65535",
                                                   "255",
                                                   "256",
                                                   "1e9",
                                                   "1000000000000",
                                                   "9223372036854775807",
                                                   "9223372036854775808",
                                                   "-9223372036854775809",
                                                   "0.5",
                                                   "1e400",
                                                   "0x10",
                                                   "1.7976931348623157e308",
                                                   "2.2250738585072014e-308"};
  return numbers;
}

uint64_t hash_name(const std::string& s) {
  uint64_t h = 1469598103934665603ull;
  for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
  return h;
}

Mutator::Mutator(uint64_t seed, std::vector<std::string> dictionary)
    : state_(seed), dictionary_(std::move(dictionary)) {}

uint64_t Mutator::next() {
  uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

size_t Mutator::below(size_t n) { return static_cast<size_t>(next() % n); }

namespace {

bool number_char(char c) { return (c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.' || c == 'e' || c == 'E'; }

/// [begin, end) of the line holding position `at`.
std::pair<size_t, size_t> line_around(const std::string& s, size_t at) {
  const size_t begin = at == 0 ? 0 : s.rfind('\n', at - 1) == std::string::npos ? 0 : s.rfind('\n', at - 1) + 1;
  const size_t nl = s.find('\n', at);
  return {begin, nl == std::string::npos ? s.size() : nl + 1};
}

}  // namespace

void Mutator::mutate_once(std::string& s, const std::vector<std::string>& corpus) {
  static const char kBytes[] = {0,   '\n', ' ', '-', '0', '1', '9', '.', 'e', '/', '"', '{',  '}',
                                '[', ']',  ',', ':', '$', '#', '<', '>', '=', 'f', 'v', '\t', '\r'};
  const size_t n = s.size();
  switch (below(12)) {
    case 0:  // flip a bit
      if (n) s[below(n)] ^= static_cast<char>(1u << below(8));
      break;
    case 1:  // set a byte, to something a parser reacts to or at random
      if (n) s[below(n)] = below(2) ? kBytes[below(sizeof kBytes)] : static_cast<char>(below(256));
      break;
    case 2: {  // insert a few bytes
      const size_t k = 1 + below(4);
      std::string ins;
      for (size_t i = 0; i < k; ++i) ins += below(2) ? kBytes[below(sizeof kBytes)] : static_cast<char>(below(256));
      s.insert(n ? below(n + 1) : 0, ins);
      break;
    }
    case 3:  // delete a range
      if (n) {
        const size_t at = below(n);
        s.erase(at, 1 + below(std::min<size_t>(n - at, 32)));
      }
      break;
    case 4:  // duplicate a chunk somewhere else
      if (n) {
        const size_t at = below(n), len = 1 + below(std::min<size_t>(n - at, 256));
        s.insert(below(n + 1), s.substr(at, len));
      }
      break;
    case 5:
    case 6: {  // replace a number by an edge value (or insert one)
      const std::string& v = interesting_numbers()[below(interesting_numbers().size())];
      if (!n) {
        s = v;
        break;
      }
      size_t at = below(n);
      size_t tries = 0;
      while (tries++ < 64 && !number_char(s[at])) at = (at + 1) % n;
      if (!number_char(s[at])) {
        s.insert(at, v);
        break;
      }
      size_t b = at, e = at;
      while (b > 0 && number_char(s[b - 1])) --b;
      while (e < n && number_char(s[e])) ++e;
      s.replace(b, e - b, v);
      break;
    }
    case 7:  // splice a chunk of another corpus file
      if (!corpus.empty()) {
        const std::string& other = corpus[below(corpus.size())];
        if (other.empty()) break;
        const size_t at = below(other.size()), len = 1 + below(std::min<size_t>(other.size() - at, 512));
        const size_t where = below(n + 1);
        if (below(2))
          s.insert(where, other.substr(at, len));
        else
          s.replace(where, std::min(n - where, len), other.substr(at, len));
      }
      break;
    case 8: {  // a line repeated, dropped, or moved
      if (!n) break;
      const auto [b, e] = line_around(s, below(n));
      const std::string line = s.substr(b, e - b);
      const size_t op = below(3);
      if (op == 0) {
        std::string copies;
        for (size_t k = 1 + below(8); k > 0; --k) copies += line;
        s.insert(b, copies);
      } else if (op == 1) {
        s.erase(b, e - b);
      } else {
        s.erase(b, e - b);
        s.insert(line_around(s, s.empty() ? 0 : below(s.size())).first, line);
      }
      break;
    }
    case 9:  // truncate
      if (n) s.resize(below(n));
      break;
    case 10:
    case 11: {  // a keyword of the format, inserted or replacing a word
      if (dictionary_.empty()) break;
      const std::string& word = dictionary_[below(dictionary_.size())];
      const size_t at = n ? below(n + 1) : 0;
      if (below(2) || at == n) {
        s.insert(at, word);
      } else {
        size_t e = at;
        while (e < n && s[e] != ' ' && s[e] != '\n' && s[e] != '"' && s[e] != ',') ++e;
        s.replace(at, e - at, word);
      }
      break;
    }
  }
}

std::string Mutator::mutate(const std::string& input, const std::vector<std::string>& corpus) {
  std::string s = input;
  // Mostly one or two mutations (inputs near the valid seeds reach deep), sometimes more.
  const size_t count = 1 + (below(4) == 0 ? below(6) : below(2));
  for (size_t k = 0; k < count; ++k) mutate_once(s, corpus);
  constexpr size_t kMaxInput = 1 << 20;  // keeps every input small and fast
  if (s.size() > kMaxInput) s.resize(kMaxInput);
  return s;
}

}  // namespace tb::fuzz
