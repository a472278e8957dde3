// The mesh readers' fuzz targets alone (the libFuzzer binaries of the readers, which
// link tb_meshing without the models).
#include "fuzz_targets.h"

namespace tb::fuzz {

const std::vector<Target>& targets() {
  static const std::vector<Target> all = mesh_targets();
  return all;
}

}  // namespace tb::fuzz
