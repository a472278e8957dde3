#include "build_info.h"

#include <malloc.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cstdlib>
#include <ctime>
#include <fstream>
#include <limits>
#include <string>
#include <thread>

#include "blas_kernels.h"
#include "compile_flags.h"
#include "git_commit.h"  // written at every build (cmake/git_commit.cmake)

namespace tb {

nlohmann::json build_and_machine_info() {
  nlohmann::json j;
  j["git_commit"] = TB_GIT_COMMIT;
  j["build_type"] = TB_BUILD_TYPE;
  j["compiler"] = std::string("g++ ") + __VERSION__;
  // What each library was really compiled with (checked against compile_commands.json
  // by tests/build/test_compile_flags.py).
  j["compiler_flags"] = {{"tb_meshing", TB_FLAGS_MESHING},
                         {"tb_models", TB_FLAGS_MODELS},
                         {"tb_models PBD kernel sources", TB_FLAGS_PBD_KERNELS},
                         {"tb_fem_assembly (deal.II)", TB_FLAGS_DEAL_II_UNITS},
                         {"tb_experiments", TB_FLAGS_EXPERIMENTS}};
  std::ifstream cpu("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpu, line))
    if (line.rfind("model name", 0) == 0) {
      j["cpu_model"] = line.substr(line.find(':') + 2);
      break;
    }
  // The CPU's family and model (two VMs of the same kind report the same model
  // name on different CPUs) and the BLAS kernels chosen for it (blas_kernels.h).
  cpu.clear();
  cpu.seekg(0);
  for (const char* key : {"cpu family", "model"})
    while (std::getline(cpu, line))
      if (line.rfind(key, 0) == 0 && line.find(':') != std::string::npos &&
          line.substr(0, line.find(':')).find_last_not_of(" \t") + 1 == std::string(key).size()) {
        j[std::string(key) == "model" ? "cpu_model_number" : "cpu_family"] = std::stoi(line.substr(line.find(':') + 2));
        break;
      }
  j["blas_core"] = blas_core_name();
  j["blas_core_pinned"] = std::getenv("OPENBLAS_CORETYPE") ? std::getenv("OPENBLAS_CORETYPE") : "";
  j["hardware_threads"] = std::thread::hardware_concurrency();
  // tissuebench's main pins OpenBLAS and OpenMP to one thread; a Newton reference's
  // newton_blas_threads (its report's blas_threads) may take more during its solve.
  j["blas_threads"] = 1;
  j["peak_memory_mib"] = process_peak_memory_mib();  // since the process started or the case's reset
  char host[256] = {};
  gethostname(host, sizeof host - 1);
  j["hostname"] = host;
  const std::time_t now = std::time(nullptr);
  char date[32];
  std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  j["date_utc"] = date;
  return j;
}

bool reset_peak_memory() {
  // Memory an earlier case freed through malloc may still be resident: glibc keeps
  // freed heap chunks (after a large block is freed its mmap threshold grows to that
  // size, up to 32 MiB, so a model's many vectors come from the heap), and the new
  // peak would start from it. Give it back first (mallopt(3), malloc_trim(3)).
  malloc_trim(0);
  std::ofstream clear("/proc/self/clear_refs");
  clear << "5";
  clear.close();
  return static_cast<bool>(clear);
}

double load_average_1min() {
  double load[1];
  return getloadavg(load, 1) == 1 ? load[0] : std::numeric_limits<double>::quiet_NaN();
}

double peak_memory_since_reset_mib() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;  // "VmHWM:  316092 kB"
  return std::numeric_limits<double>::quiet_NaN();
}

double process_peak_memory_mib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

}  // namespace tb
