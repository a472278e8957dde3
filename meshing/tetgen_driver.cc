#include "tetgen_driver.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iomanip>
#include <sstream>

#include "atomic_file.h"
#include "flat_tet_repair.h"
#include "mesh_checks.h"
#include "mesh_error.h"
#include "mesh_io.h"

namespace tb {
namespace {

namespace fs = std::filesystem;

/// A temporary folder removed when it goes out of scope.
struct TempDir {
  fs::path path;
  TempDir() {
    std::string tmpl = (fs::temp_directory_path() / "tissuebench-tetgen-XXXXXX").string();
    if (!mkdtemp(tmpl.data())) throw std::runtime_error("cannot create a temporary folder for tetgen");
    path = tmpl;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

std::string shell_quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

void write_nodes(std::ostringstream& os, const Points& V) {
  os << std::setprecision(17) << V.rows() << " 3 0 0\n";
  for (Eigen::Index i = 0; i < V.rows(); ++i) os << i << ' ' << V(i, 0) << ' ' << V(i, 1) << ' ' << V(i, 2) << '\n';
}

/// Runs tetgen with `switches` on `input` inside `dir`; returns the mesh it wrote
/// (<stem>.1.node/.ele), read with `flat` and then passed to `finish` (a repair and
/// check, given the output's name for its errors).
TetMesh run_tetgen(const TempDir& dir, const std::string& input, const std::string& switches, double timeout_seconds,
                   const std::string& source, FlatTets flat,
                   const std::function<void(TetMesh&, const std::string&)>& finish = {}) {
  const std::string log = (dir.path / "tetgen.log").string();
  std::ostringstream cmd;
  cmd << "timeout " << static_cast<int>(timeout_seconds) << ' ' << shell_quote(tetgen_program()) << " -" << switches
      << ' ' << shell_quote(input) << " > " << shell_quote(log) << " 2>&1";
  const int status = std::system(cmd.str().c_str());
  if (status != 0) {
    std::string tail;
    try {
      tail = read_file(log);
    } catch (...) {
    }
    // The last line of TetGen's output usually says what went wrong.
    while (!tail.empty() && (tail.back() == '\n' || tail.back() == ' ')) tail.pop_back();
    const size_t nl = tail.rfind('\n');
    if (nl != std::string::npos) tail = tail.substr(nl + 1);
    if (WEXITSTATUS(status) == 124)
      throw MeshError(source,
                      "tetgen did not finish within " + std::to_string(static_cast<int>(timeout_seconds)) + " s");
    throw MeshError(source, "tetgen -" + switches + " failed (exit " + std::to_string(WEXITSTATUS(status)) +
                                "): " + (tail.empty() ? "no output" : tail));
  }
  const std::string stem = fs::path(input).replace_extension("").string();
  const std::string output = stem + ".1.ele";
  try {
    TetMesh m = read_volume(output, 1.0, flat);
    if (finish) finish(m, output);
    return m;
  } catch (const MeshError& e) {
    // Named by the input the user gave: TetGen's output is a temporary file, gone
    // by the time the message is read.
    std::string problem = e.what();
    if (problem.rfind(output + ": ", 0) == 0) problem = problem.substr(output.size() + 2);
    throw MeshError(source, "tetgen -" + switches + " gave an unusable volume: " + problem);
  }
}

}  // namespace

std::string tetgen_program() {
  if (const char* env = std::getenv("TISSUEBENCH_TETGEN"); env && *env) {
    if (!fs::exists(env)) throw std::runtime_error(std::string("TISSUEBENCH_TETGEN=") + env + ": no such program");
    return env;
  }
  if (const char* path = std::getenv("PATH")) {
    std::stringstream ss(path);
    std::string dir;
    while (std::getline(ss, dir, ':'))
      if (!dir.empty() && ::access((fs::path(dir) / "tetgen").c_str(), X_OK) == 0)
        return (fs::path(dir) / "tetgen").string();
  }
  throw std::runtime_error(
      "the tetgen program was not found (install the Debian package: apt-get install tetgen, "
      "or set TISSUEBENCH_TETGEN)");
}

TetMesh tetrahedralize_surface(const SurfaceMesh& surface, const TetgenOptions& o, const std::string& source,
                               InteriorPointMerges* repair) {
  TempDir dir;
  std::ostringstream os;
  write_nodes(os, surface.V);
  os << surface.F.rows() << " 0\n";
  for (Eigen::Index t = 0; t < surface.F.rows(); ++t)
    os << "3 " << surface.F(t, 0) << ' ' << surface.F(t, 1) << ' ' << surface.F(t, 2) << '\n';
  os << "0\n0\n";  // no holes, no regions
  const std::string input = (dir.path / "surface.smesh").string();
  write_file_atomically(input, os.str());
  std::ostringstream sw;
  sw << std::setprecision(10) << "pYzQ";
  if (o.radius_edge_ratio > 0) sw << 'q' << o.radius_edge_ratio;
  if (o.max_volume > 0) sw << 'a' << o.max_volume;
  InteriorPointMerges merges;
  TetMesh m = run_tetgen(dir, input, sw.str(), o.timeout_seconds, source, FlatTets::Keep,
                         [&](TetMesh& volume, const std::string& output) {
                           merges = merge_near_coincident_interior_points(volume, static_cast<int>(surface.V.rows()));
                           orient_and_check_tets(output, volume, FlatTets::Error);
                         });
  if (repair) *repair = merges;
  // -Y keeps the surface and tetgen numbers input points first: check it held.
  if (m.V.rows() < surface.V.rows() ||
      (m.V.topRows(surface.V.rows()) - surface.V).cwiseAbs().maxCoeff() > 1e-12 * (1 + surface.V.cwiseAbs().maxCoeff()))
    throw MeshError(source, "tetgen did not keep the surface vertices first and in order");
  return m;
}

TetMesh tetrahedralize_points(const Points& points, const std::string& source) {
  TempDir dir;
  std::ostringstream os;
  write_nodes(os, points);
  const std::string input = (dir.path / "points.node").string();
  write_file_atomically(input, os.str());
  // Coplanar points on the hull (a flat face of the surface) can give Delaunay
  // slivers of zero volume: they carry no stiffness and are removed.
  TetMesh m = run_tetgen(dir, input, "zQ", 600, source, FlatTets::Drop);
  if (m.V.rows() != points.rows()) throw MeshError(source, "tetgen changed the number of points (duplicates?)");
  return m;
}

}  // namespace tb
