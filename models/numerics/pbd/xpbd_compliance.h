// XPBD's compliances (Macklin, Mueller, Chentanez 2016: alpha = 1 / k per
// constraint, energy U = C^2 / (2 alpha)) derived from a linear elastic material
// for the fine surface read as a thin shell of thickness h (Young's modulus E,
// Poisson's ratio nu). Stateless; the solver computes them once at setup.
//
// Stretch, one constraint per edge e (C = |p1 - p2| - L_e, metres):
//   k_e = E h A_e / L_e^2   (N/m),
// A_e the summed area of the (one or two) triangles sharing e, L_e its rest
// length. The form is Van Gelder's (1998, "Approximate simulation of elastic
// membranes by triangulated spring meshes", J. Graphics Tools 3(2): stiffness as
// triangle area over edge length squared); the constant is the one with which a
// uniform equilateral mesh has the membrane's in-plane Young's modulus E h exactly
// (a triangular spring lattice of spring constant k has 2D modulus 2 k / sqrt(3)
// and Poisson's ratio 1/3, Seung and Nelson 1988; with two triangles of area
// sqrt(3) L^2 / 4 per edge, k_e = sqrt(3) E h / 2). A spring mesh cannot represent
// another Poisson's ratio: nu enters the bending only.
//
// Bending, one constraint per interior edge (hinge; C = theta - theta0, radians):
//   k_e = 3 D L_e^2 / A_e   (N m),   D = E h^3 / (12 (1 - nu^2)),
// D the plate's flexural rigidity, 3 L_e^2 / A_e the hinge factor of Discrete
// Shells (Grinspun, Hirani, Desbrun, Schroeder 2003: |e| / h_e with h_e a sixth of
// the sum of the two triangles' heights) and of Wardetzky et al. 2007, "Discrete
// quadratic curvature energies": sum_e (k_e / 2) (theta - theta0)^2 is then the
// discrete (D / 2) int (2H)^2 dA (exact for a sphere tiled by equilateral
// triangles). The Kirchhoff plate energy's Gaussian-curvature term
// -D (1 - nu) int K dA is a constant on a closed surface (Gauss-Bonnet), so nothing
// else of the plate energy is dropped there; on anisotropic bending (a cylinder)
// the hinge energy depends on the mesh (1.5 times the continuum on equilateral
// triangles), a known limit of hinge bending.
//
// XPBD uses alpha~ = alpha / dt^2 (Macklin et al. eq. 4) per time step.
#pragma once

#include <Eigen/Core>

#include "constraint_kind.h"
#include "mesh_types.h"

namespace tb::pbd {

/// The thickness of a shell holding the body's volume: enclosed volume / surface
/// area (m); 1/6 of the side for a cube (16.7 mm on the paper's 0.1 m cube).
double volume_preserving_thickness(const SurfaceMesh& surface);

/// Stretch compliances alpha_e = L_e^2 / (E h A_e) (m/N), one per stretch
/// constraint (rows of `stretch`: edge ends, rest length), at the rest shape
/// `surface` (the one the constraints were built from).
/// Throws std::invalid_argument for E <= 0, h <= 0, or an edge with zero rest length
/// or zero area.
///   returns #S compliances
Eigen::VectorXd stretch_compliances(const SurfaceMesh& surface, const KindConstraints& stretch, double youngs_modulus,
                                    double thickness);

/// Bending compliances alpha_e = A_e / (3 D L_e^2) (1/(N m)), one per bending
/// constraint (rows of `bending`: p1, p2 the hinge, p3, p4 the wings),
/// D = E h^3 / (12 (1 - nu^2)). Throws std::invalid_argument for E <= 0,
/// h <= 0, nu outside (-1, 0.5], or a degenerate hinge.
///   returns #B compliances
Eigen::VectorXd bending_compliances(const SurfaceMesh& surface, const KindConstraints& bending, double youngs_modulus,
                                    double poisson_ratio, double thickness);

}  // namespace tb::pbd
