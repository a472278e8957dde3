#include "cube_generator.h"

#include <map>
#include <stdexcept>
#include <string>

namespace tb {

double centred_grid_coordinate(double side, int n, int i) { return side * (static_cast<double>(i) / n - 0.5); }

SurfaceMesh make_cube_surface(const CubeSpec& s) {
  if (s.nx < 1 || s.ny < 1 || s.nz < 1) throw std::invalid_argument("cube divisions must be >= 1");
  if (!(s.side > 0) || !(s.height > 0)) throw std::invalid_argument("cube side and height must be positive");
  const int n[3] = {s.nx, s.ny, s.nz};
  std::map<std::array<int, 3>, int> index;  // lattice (i, j, k) -> vertex
  std::vector<std::array<int, 3>> lattice;
  auto vertex = [&](std::array<int, 3> ijk) {
    auto [it, inserted] = index.emplace(ijk, static_cast<int>(lattice.size()));
    if (inserted) lattice.push_back(ijk);
    return it->second;
  };
  std::vector<std::array<int, 3>> tris;
  // Each face: fixed axis a at lattice value `at`, in-plane axes (u, v) chosen so
  // that e_u x e_v points outward.
  struct Face {
    int a, at_max, u, v;
  };
  const Face faces[6] = {{2, 0, 1, 0}, {2, 1, 0, 1}, {0, 0, 2, 1}, {0, 1, 1, 2}, {1, 0, 0, 2}, {1, 1, 2, 0}};
  for (const Face& f : faces) {
    const int nu = n[f.u], nv = n[f.v];
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < nv; ++j) {
        auto at = [&](int di, int dj) {
          std::array<int, 3> ijk{};
          ijk[f.a] = f.at_max ? n[f.a] : 0;
          ijk[f.u] = i + di;
          ijk[f.v] = j + dj;
          return vertex(ijk);
        };
        const int p00 = at(0, 0), p10 = at(1, 0), p11 = at(1, 1), p01 = at(0, 1);
        // Diagonal by quadrant: mirror images of the face get mirrored diagonals.
        if ((2 * i < nu) == (2 * j < nv)) {
          tris.push_back({p00, p10, p11});
          tris.push_back({p00, p11, p01});
        } else {
          tris.push_back({p00, p10, p01});
          tris.push_back({p10, p11, p01});
        }
      }
  }
  SurfaceMesh m;
  m.V.resize(static_cast<Eigen::Index>(lattice.size()), 3);
  for (size_t v = 0; v < lattice.size(); ++v) {
    const auto& l = lattice[v];
    m.V.row(static_cast<Eigen::Index>(v)) << centred_grid_coordinate(s.side, s.nx, l[0]),
        centred_grid_coordinate(s.side, s.ny, l[1]), s.height * static_cast<double>(l[2]) / s.nz;
  }
  m.F.resize(static_cast<Eigen::Index>(tris.size()), 3);
  for (size_t t = 0; t < tris.size(); ++t) m.F.row(static_cast<Eigen::Index>(t)) << tris[t][0], tris[t][1], tris[t][2];
  return m;
}

}  // namespace tb
