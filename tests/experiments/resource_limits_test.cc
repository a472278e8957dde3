// Resource limits stated before a run starts (experiments/resource_limits.h): the
// mesh-size estimate against a committed run, and a scenario too large for the
// limit stopped before anything is built or written, by the runner and the CLI;
// and a case's own peak memory, measured after a reset (build_info.h).
#include "resource_limits.h"

#include <gtest/gtest.h>

#include <sys/mman.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "build_info.h"
#include "scenario_fixture.h"

namespace tb {
namespace {
namespace fs = std::filesystem;

constexpr double kGiB = 1ull << 30;

TEST(ResourceLimits, TheCubeEstimateIsNearTheCommittedRunsMesh) {
  const Experiment e = load_experiment(std::string(TB_SOURCE_DIR) + "/experiments/scenarios/cube-pull.json");
  const MeshSizeEstimate size = estimate_mesh_size(e.scenarios.at(0).mesh);
  std::ifstream in(std::string(TB_SOURCE_DIR) + "/results/paper/cube-pull/fem-direct/run.json");
  const nlohmann::json mesh = nlohmann::json::parse(in).at("mesh");
  EXPECT_EQ(size.surface_vertices, mesh.at("surface_vertices").get<double>());  // exact before meshing
  const double tets = mesh.at("fine_tets").get<double>(), nodes = mesh.at("fine_nodes").get<double>();
  EXPECT_GE(size.fine_tets, tets);  // an estimate above the mesh, within 1.5x
  EXPECT_LE(size.fine_tets, 1.5 * tets);
  EXPECT_GE(size.fine_nodes, nodes);
  EXPECT_LE(size.fine_nodes, 2 * nodes);
  // Every case of the paper's cube fits in 1 GiB.
  EXPECT_NO_THROW(check_memory(e, "", "", kGiB, "--max-memory"));
}

TEST(PeakMemory, ARunsPeakIsMeasuredFromTheLastResetOnly) {
  ASSERT_TRUE(reset_peak_memory()) << "/proc/self/clear_refs refused";
  const double before = peak_memory_since_reset_mib();
  {
    // 256 MiB mapped, every page touched, then unmapped (not malloc: it may keep freed memory).
    const size_t bytes = 256u << 20;
    void* map = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    ASSERT_NE(map, MAP_FAILED);
    char* block = static_cast<char*>(map);
    for (size_t i = 0; i < bytes; i += 4096) block[i] = 1;
    EXPECT_GT(peak_memory_since_reset_mib(), before + 250) << "the touched block is not in the peak";
    munmap(map, bytes);
  }
  // Returned to the kernel: the peak stays until a reset ...
  EXPECT_GT(peak_memory_since_reset_mib(), before + 250);
  ASSERT_TRUE(reset_peak_memory());
  // ... which starts it again from what is resident now.
  EXPECT_LT(peak_memory_since_reset_mib(), before + 50);
  EXPECT_LT(process_peak_memory_mib(), before + 50) << "getrusage's ru_maxrss is the same high-water mark";
}

double resident_mib() {  // VmRSS, this process's resident memory now
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  return -1;
}

// A case that freed many heap blocks (as a model's vectors are) leaves them resident
// in glibc's heap; the next case's peak must not start from them. Seen before the
// trim: every suite case run after condensed at 10 000 surface vertices in the same
// process reported condensed's 8.4 GiB as its own peak.
TEST(PeakMemory, WhatAnEarlierCaseFreedThroughMallocIsNotInTheNextPeak) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "the sanitizer's allocator is not glibc's";
#endif
  ASSERT_TRUE(reset_peak_memory());
  const double before = resident_mib();
  // A large block freed raises glibc's mmap threshold: the 1 MiB blocks below come
  // from the heap; a small block allocated after them keeps the freed ones off the
  // heap's top, so free() does not trim them.
  std::free(std::malloc(16u << 20));
  std::vector<char*> blocks;
  for (int i = 0; i < 256; ++i) {
    blocks.push_back(static_cast<char*>(std::malloc(1u << 20)));
    for (size_t k = 0; k < (1u << 20); k += 4096) blocks.back()[k] = 1;
  }
  char* pin = static_cast<char*>(std::malloc(64));
  pin[0] = 1;
  for (char* b : blocks) std::free(b);
  ASSERT_GT(resident_mib(), before + 200) << "glibc returned the freed blocks itself: this test shows nothing";
  ASSERT_TRUE(reset_peak_memory());
  EXPECT_LT(resident_mib(), before + 50);
  EXPECT_LT(peak_memory_since_reset_mib(), before + 50);
  std::free(pin);
}

TEST(ResourceLimits, CondensedResponsesGrowAsTheSquareOfTheSurface) {
  MeshSizeEstimate size;
  size.surface_vertices = 10000;
  size.fine_tets = 70000;
  size.fine_nodes = 17500;
  ModelRun run;
  run.model = "condensed";
  run.parameters.set_choice("precompute", "surface_vertices");
  std::string what;
  const double small = estimate_case_bytes(run, size, what);
  size.surface_vertices *= 2;
  const double large = estimate_case_bytes(run, size, what);
  EXPECT_NEAR(large - small, 72 * (4 - 1) * 1e8, 0.5 * 72 * 1e8);  // the responses, with the surface's share
  EXPECT_EQ(what, "the precomputed responses, 72 n^2 bytes for n surface vertices");
}

class ResourceLimitsRun : public Scenarios {
 protected:
  /// The small cube refined six times (4^6 x its surface): far beyond 1 GiB.
  std::string too_large() {
    nlohmann::json j = small_cube();
    j["mesh"]["refine_levels"] = 6;
    return write("large.json", j);
  }
};

TEST_F(ResourceLimitsRun, TheRunnerStopsBeforeBuildingOrWriting) {
  RunOptions o;
  o.out_dir = (dir / "out").string();
  o.progress = false;
  o.max_memory_bytes = kGiB;
  try {
    run_experiment(load_experiment(too_large()), o);
    FAIL() << "ran";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("large.json: scenario 'small', case 'fem-direct': needs about "), std::string::npos) << m;
    EXPECT_NE(m.find("more than the 1 GiB of --max-memory; change mesh.refine_levels"), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
  EXPECT_FALSE(fs::exists(o.out_dir));
}

TEST_F(ResourceLimitsRun, TheCliSaysSoInOneLine) {
  const std::string out = (dir / "out").string();
  FILE* p = popen(
      (std::string(TB_CLI) + " run " + too_large() + " --max-memory 1 --quiet --out " + out + " 2>&1").c_str(), "r");
  ASSERT_TRUE(p);
  std::string output;
  char buffer[4096];
  while (size_t n = fread(buffer, 1, sizeof buffer, p)) output.append(buffer, n);
  EXPECT_EQ(WEXITSTATUS(pclose(p)), 1);
  EXPECT_EQ(output.rfind("tissuebench: ", 0), 0u) << output;
  EXPECT_NE(output.find("needs about"), std::string::npos) << output;
  EXPECT_EQ(output.find('\n'), output.size() - 1) << output;  // one line
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace tb
