// A small seeded mutator (docs/robustness.md): the same seed gives the same inputs
// on every machine, so a finding in CI is reproduced by its target, seed and index.
// Byte-level mutations (bit flips, byte insertions and deletions, chunk duplication,
// splices from other corpus files) and text-aware ones (numbers replaced by edge
// values such as -1, 0, 1e308, nan, 2147483648; lines duplicated, dropped or
// swapped; the format's keywords inserted).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace tb::fuzz {

class Mutator {
 public:
  /// `dictionary`: the format's keywords (section names, JSON keys), spliced in.
  Mutator(uint64_t seed, std::vector<std::string> dictionary);
  /// One to six stacked mutations of `input`; `corpus` supplies splices.
  std::string mutate(const std::string& input, const std::vector<std::string>& corpus);
  /// A number in [0, n) (n > 0).
  size_t below(size_t n);

 private:
  uint64_t next();  // splitmix64
  void mutate_once(std::string& s, const std::vector<std::string>& corpus);
  uint64_t state_;
  std::vector<std::string> dictionary_;
};

/// The edge-value numbers spliced into text.
const std::vector<std::string>& interesting_numbers();

/// A 64-bit FNV-1a hash (to derive per-target seeds from names).
uint64_t hash_name(const std::string& s);

}  // namespace tb::fuzz
