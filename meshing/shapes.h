// Closed test surfaces generated in code: a sphere, an ellipsoid, a
// torus, a bar with a through hole, an L-block and a dumbbell, about the paper
// cube's size (0.1 m) and resting on z = 0, at any resolution. Each is built from
// structured quad patches (a cube sphere, a periodic grid, an extruded 2D grid,
// a surface of revolution with disk caps) welded along shared edges.
#pragma once

#include <string>
#include <vector>

#include "mesh_types.h"

namespace tb {

/// The shapes make_shape_surface builds, in a fixed order:
/// sphere, ellipsoid, torus, bar_with_hole, l_block, dumbbell.
const std::vector<std::string>& shape_names();

/// One line per shape: what it is and its dimensions, for help texts and README.
std::string shape_description(const std::string& name);

/// Lowest and highest accepted ShapeSpec::resolution.
constexpr int kMinShapeResolution = 4;
constexpr int kMaxShapeResolution = 200;

struct ShapeSpec {
  std::string name = "sphere";
  /// Edge segments per 0.1 m: the target edge length is h = 0.1 m / resolution
  /// (the paper's cube surface has 10). Every patch gets round(length / h)
  /// segments (at least one), so vertex counts grow as resolution^2.
  int resolution = 15;
};

/// A closed, 2-manifold, outward-oriented triangle surface of the named shape, in
/// metres, with min z = 0 and the x and y extents centred on 0. Deterministic.
/// Throws std::invalid_argument for an unknown name or a resolution outside
/// [kMinShapeResolution, kMaxShapeResolution].
///   returns V  #V by 3, F  #F by 3 (counter-clockwise seen from outside)
SurfaceMesh make_shape_surface(const ShapeSpec& spec);

/// Volume of the exact (smooth) solid the named shape approximates, m^3.
double shape_exact_volume(const std::string& name);

}  // namespace tb
