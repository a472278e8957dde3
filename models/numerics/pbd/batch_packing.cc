#include "batch_packing.h"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <stdexcept>

namespace tb::pbd {
namespace {

using VertexRows = Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// The constraints (rows of `vertices`) that can move something: one of their
/// vertices has inverse mass > 0.
std::vector<int> movable(const VertexRows& vertices, const Eigen::VectorXd& w) {
  std::vector<int> kept;
  for (Eigen::Index i = 0; i < vertices.rows(); ++i) {
    bool moves = false;
    for (Eigen::Index j = 0; j < vertices.cols(); ++j) {
      if (vertices(i, j) < 0 || vertices(i, j) >= w.size())
        throw std::invalid_argument("PBD constraints: vertex index out of range of the inverse masses");
      moves = moves || w(vertices(i, j)) > 0;
    }
    if (moves) kept.push_back(static_cast<int>(i));
  }
  return kept;
}

/// The colour of overflowing constraints, whose members may share vertices.
constexpr int kOverflowColour = 64;

/// `kept` reordered by a greedy graph colouring (no two constraints of one colour
/// share a vertex), keeping the original order within a colour, so that runs of
/// consecutive constraints are independent and fill batches. `colour_of_ordered`
/// gets the colour of each entry of the result (ascending).
std::vector<int> colour_order(const VertexRows& vertices, const std::vector<int>& kept, size_t vertex_count,
                              std::vector<int>& colour_of_ordered) {
  const Eigen::Index N = vertices.cols();
  std::vector<uint64_t> used(vertex_count, 0);  // colours already taken at each vertex
  std::vector<int> colour(kept.size());
  for (size_t i = 0; i < kept.size(); ++i) {
    uint64_t taken = 0;
    for (Eigen::Index j = 0; j < N; ++j) taken |= used[static_cast<size_t>(vertices(kept[i], j))];
    // The lowest free colour; a vertex with 64 colours around it (valence > 64 for
    // stretch) sends the rest to colour 64, whose constraints may share vertices:
    // the packing below then splits them into smaller batches.
    const int c = ~taken ? __builtin_ctzll(~taken) : kOverflowColour;
    colour[i] = c;
    if (c < kOverflowColour)
      for (Eigen::Index j = 0; j < N; ++j) used[static_cast<size_t>(vertices(kept[i], j))] |= uint64_t{1} << c;
  }
  std::vector<size_t> by_colour(kept.size());
  std::iota(by_colour.begin(), by_colour.end(), size_t{0});
  std::stable_sort(by_colour.begin(), by_colour.end(), [&](size_t a, size_t b) { return colour[a] < colour[b]; });
  std::vector<int> order;
  order.reserve(kept.size());
  colour_of_ordered.clear();
  for (size_t i : by_colour) {
    order.push_back(kept[i]);
    colour_of_ordered.push_back(colour[i]);
  }
  return order;
}

/// Colour ids of group g are g * kColoursPerGroup + (its colour), so that no two
/// groups share a colour and pack() closes a batch and a colour at a group's end.
constexpr int kColoursPerGroup = kOverflowColour + 1;

/// `kept` ordered group by group (domain 0, 1, ..., then the interface: the
/// constraints whose vertices lie in several domains), each group coloured by
/// colour_order. With no `vertex_domain`, one group: colour_order itself.
std::vector<int> grouped_colour_order(const VertexRows& vertices, const std::vector<int>& kept, size_t vertex_count,
                                      const std::vector<int>& vertex_domain, int domains,
                                      std::vector<int>& colour_of_ordered) {
  if (vertex_domain.empty()) return colour_order(vertices, kept, vertex_count, colour_of_ordered);
  std::vector<std::vector<int>> groups(static_cast<size_t>(domains) + 1);
  for (int i : kept) {
    const int d = vertex_domain[static_cast<size_t>(vertices(i, 0))];
    bool inside = true;
    for (Eigen::Index j = 1; j < vertices.cols(); ++j)
      inside = inside && vertex_domain[static_cast<size_t>(vertices(i, j))] == d;
    groups[inside ? static_cast<size_t>(d) : groups.size() - 1].push_back(i);
  }
  std::vector<int> order, colours;
  colour_of_ordered.clear();
  for (size_t g = 0; g < groups.size(); ++g) {
    const std::vector<int> part = colour_order(vertices, groups[g], vertex_count, colours);
    order.insert(order.end(), part.begin(), part.end());
    for (int c : colours) colour_of_ordered.push_back(static_cast<int>(g) * kColoursPerGroup + c);
  }
  return order;
}

/// Consecutive constraints of `order` packed into batches of `width` lanes; a
/// batch closes when it is full, when the next constraint shares a vertex with it
/// or is of another colour. Padding lanes repeat lane 0's first vertex in every
/// slot with inverse mass 0: degenerate, so their corrections are zero.
///   groups  domains + 1 (the colour ids' groups: grouped_colour_order)
BatchLayout pack(const VertexRows& vertices, const std::vector<int>& order, const std::vector<int>& colour,
                 size_t vertex_count, int width, int groups) {
  const size_t N = static_cast<size_t>(vertices.cols());
  std::vector<size_t> last_batch(vertex_count, SIZE_MAX);  // the last batch using each vertex
  std::vector<int> group_of_colour;
  BatchLayout b;
  const size_t W = static_cast<size_t>(width);
  for (size_t k = 0; k < order.size(); ++k) {
    const int i = order[k];
    const bool new_colour = k == 0 || colour[k] != colour[k - 1];
    bool fits = !new_colour && b.count.back() < width;
    for (size_t j = 0; j < N && fits; ++j)
      fits = last_batch[static_cast<size_t>(vertices(i, static_cast<Eigen::Index>(j)))] != b.count.size() - 1;
    if (new_colour) {
      b.colours.begin.push_back(b.count.size());
      group_of_colour.push_back(colour[k] / kColoursPerGroup);
    }
    if (!fits) {
      b.count.push_back(0);
      b.q.resize(b.q.size() + N * W, -1);
    }
    const size_t batch = b.count.size() - 1;
    const size_t l = static_cast<size_t>(b.count.back()++);
    for (size_t j = 0; j < N; ++j) {
      const int v = vertices(i, static_cast<Eigen::Index>(j));
      b.q[(batch * N + j) * W + l] = v;
      last_batch[static_cast<size_t>(v)] = batch;
    }
  }
  b.colours.begin.push_back(b.count.size());
  for (int g = 0; g <= groups; ++g)
    b.group_begin.push_back(static_cast<size_t>(std::lower_bound(group_of_colour.begin(), group_of_colour.end(), g) -
                                                group_of_colour.begin()));
  // Only the last (interface) group is split between threads colour by colour.
  b.colours.last_shares_vertices =
      !colour.empty() && colour.back() == (groups - 1) * kColoursPerGroup + kOverflowColour;
  for (size_t batch = 0; batch < b.count.size(); ++batch)
    for (size_t l = static_cast<size_t>(b.count[batch]); l < W; ++l)
      for (size_t j = 0; j < N; ++j) b.q[(batch * N + j) * W + l] = b.q[batch * N * W];
  return b;
}

/// The batches' inverse masses, as the kind's kernel takes them (slot_weights),
/// and rest values in precision S.
template <class S>
BatchNumbers<S> numbers(const KindConstraints& c, const BatchLayout& b, const std::vector<int>& order,
                        const Eigen::VectorXd& w, int width) {
  const size_t W = static_cast<size_t>(width), N = static_cast<size_t>(c.kind->arity),
               R = static_cast<size_t>(c.kind->rest_values);
  void (*const slot_weights)(S*) = c.kind->kernels<S>().slot_weights;
  BatchNumbers<S> n;
  n.w.assign(b.batch_count() * N * W, S(0));
  n.rest.assign(b.batch_count() * R * W, S(0));
  std::vector<S> slot_w(N);
  size_t next = 0;  // position in `order` of the batch's lane 0
  for (size_t batch = 0; batch < b.batch_count(); ++batch) {
    for (size_t l = 0; l < static_cast<size_t>(b.count[batch]); ++l) {
      for (size_t j = 0; j < N; ++j) slot_w[j] = static_cast<S>(w(b.q[(batch * N + j) * W + l]));
      slot_weights(slot_w.data());
      for (size_t j = 0; j < N; ++j) n.w[(batch * N + j) * W + l] = slot_w[j];
      for (size_t r = 0; r < R; ++r)
        n.rest[(batch * R + r) * W + l] = static_cast<S>(c.rest(order[next + l], static_cast<Eigen::Index>(r)));
    }
    next += static_cast<size_t>(b.count[batch]);
  }
  return n;
}

}  // namespace

KindBatches pack_kind(const KindConstraints& c, const Eigen::VectorXd& w, int width, Precision precision,
                      const std::vector<int>& vertex_domain, int domains) {
  const size_t vertex_count = static_cast<size_t>(w.size());
  KindBatches k{c.kind, {}, {}, {}, {}, c.size()};
  std::vector<int> colour;
  k.order = grouped_colour_order(c.vertices, movable(c.vertices, w), vertex_count, vertex_domain, domains, colour);
  k.layout = pack(c.vertices, k.order, colour, vertex_count, width, domains + 1);
  if (precision == Precision::Double)
    k.double_numbers = numbers<double>(c, k.layout, k.order, w, width);
  else
    k.single_numbers = numbers<float>(c, k.layout, k.order, w, width);
  return k;
}

}  // namespace tb::pbd
