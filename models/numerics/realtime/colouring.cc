#include "colouring.h"

#include <algorithm>

namespace tb {
namespace {

/// The smallest colour not marked in `used` (entries equal to `stamp`).
int first_free(const std::vector<int>& used, int stamp) {
  int c = 0;
  while (c < static_cast<int>(used.size()) && used[static_cast<size_t>(c)] == stamp) ++c;
  return c;
}

void add_to(Colouring& classes, int colour, int item) {
  if (colour >= static_cast<int>(classes.size())) classes.resize(static_cast<size_t>(colour) + 1);
  classes[static_cast<size_t>(colour)].push_back(item);
}

}  // namespace

VertexTets vertex_tets(const Tetrahedra& T, int vertex_count) {
  VertexTets r;
  r.offset.assign(static_cast<size_t>(vertex_count) + 1, 0);
  for (Eigen::Index t = 0; t < T.rows(); ++t)
    for (int a = 0; a < 4; ++a) ++r.offset[static_cast<size_t>(T(t, a)) + 1];
  for (size_t v = 0; v < static_cast<size_t>(vertex_count); ++v) r.offset[v + 1] += r.offset[v];
  r.around.resize(static_cast<size_t>(r.offset.back()));
  std::vector<int> fill(r.offset.begin(), r.offset.end() - 1);
  for (Eigen::Index t = 0; t < T.rows(); ++t)
    for (int a = 0; a < 4; ++a)
      r.around[static_cast<size_t>(fill[static_cast<size_t>(T(t, a))]++)] = {static_cast<int>(t), a};
  return r;
}

Colouring colour_vertices(const Tetrahedra& T, int vertex_count, const std::vector<int>& active) {
  const VertexTets around = vertex_tets(T, vertex_count);
  std::vector<int> sorted = active;
  std::sort(sorted.begin(), sorted.end());
  std::vector<int> colour(static_cast<size_t>(vertex_count), -1), used;
  Colouring classes;
  int stamp = 0;
  for (int v : sorted) {
    ++stamp;
    for (int k = around.offset[static_cast<size_t>(v)]; k < around.offset[static_cast<size_t>(v) + 1]; ++k)
      for (int a = 0; a < 4; ++a) {
        const int c = colour[static_cast<size_t>(T(around.around[static_cast<size_t>(k)].first, a))];
        if (c < 0) continue;
        if (c >= static_cast<int>(used.size())) used.resize(static_cast<size_t>(c) + 1, 0);
        used[static_cast<size_t>(c)] = stamp;
      }
    const int c = first_free(used, stamp);
    colour[static_cast<size_t>(v)] = c;
    add_to(classes, c, v);
  }
  return classes;
}

Colouring colour_tets(const Tetrahedra& T, int vertex_count, const std::vector<char>& moving) {
  // Per vertex, the colours its tets took so far (as a list: a vertex has few tets).
  std::vector<std::vector<int>> taken(static_cast<size_t>(vertex_count));
  std::vector<int> used;
  Colouring classes;
  int stamp = 0;
  for (Eigen::Index t = 0; t < T.rows(); ++t) {
    ++stamp;
    for (int a = 0; a < 4; ++a)
      for (int c : taken[static_cast<size_t>(T(t, a))]) {
        if (c >= static_cast<int>(used.size())) used.resize(static_cast<size_t>(c) + 1, 0);
        used[static_cast<size_t>(c)] = stamp;
      }
    const int c = first_free(used, stamp);
    for (int a = 0; a < 4; ++a)
      if (moving[static_cast<size_t>(T(t, a))]) taken[static_cast<size_t>(T(t, a))].push_back(c);
    add_to(classes, c, static_cast<int>(t));
  }
  return classes;
}

}  // namespace tb
