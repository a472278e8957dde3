#include "material_laws.h"

#include <stdexcept>

#include "arap_volume.h"
#include "linear_elastic.h"
#include "neo_hookean.h"
#include "neo_hookean_isochoric.h"
#include "stable_neo_hookean.h"
#include "xpbd_neo_hookean.h"

namespace tb {
namespace {

template <class Law>
double energy_of(const Eigen::Matrix3d& F, const LameParameters& lame) {
  return Law(lame).energy(F);
}

template <class Law>
Eigen::Matrix3d first_piola_of(const Eigen::Matrix3d& F, const LameParameters& lame) {
  return Law(lame).first_piola(F);
}

template <class Law>
Matrix9d tangent_of(const Eigen::Matrix3d& F, const LameParameters& lame) {
  return Law(lame).tangent(F);
}

template <class Law>
MaterialLawInfo entry(const char* name, const char* description, bool defined_when_inverted) {
  return {name, description, &energy_of<Law>, &first_piola_of<Law>, &tangent_of<Law>, defined_when_inverted};
}

}  // namespace

const std::vector<MaterialLawInfo>& material_laws() {
  static const std::vector<MaterialLawInfo> laws = {
      entry<LinearElastic>("linear",
                           "small-strain linear isotropic elasticity as a function of F: eps = sym(F - I), "
                           "W = mu eps:eps + lambda/2 tr(eps)^2, the law of the serial stiffness B^T D B; "
                           "not frame-indifferent (a rigid rotation stores energy)",
                           true),
      entry<NeoHookean>("neo_hookean",
                        "compressible neo-Hookean (Bonet and Wood 2008, eq. 6.28): "
                        "W = mu/2 (I1 - 3) - mu ln J + lambda/2 (ln J)^2 with the Lame parameters of (E, nu), "
                        "the distributed reference's law; undefined for J <= 0",
                        false),
      entry<NeoHookeanIsochoric>("neo_hookean_isochoric",
                                 "neo-Hookean with the isochoric/volumetric split (Flory 1961; the Abaqus form): "
                                 "W = C10 (J^(-2/3) I1 - 3) + (J - 1)^2 / D1, C10 = mu/2, D1 = 2/K; "
                                 "undefined for J <= 0",
                                 false),
      entry<StableNeoHookean>("stable_neo_hookean",
                              "stable neo-Hookean (Smith, de Goes and Kim 2018): "
                              "W = mu'/2 (I1 - 3) + lambda'/2 (J - alpha)^2 - mu'/2 ln(I1 + 1), "
                              "mu' = 4 mu/3, lambda' = lambda + 5 mu/6, alpha = 1 + mu'/lambda' - mu'/(4 lambda'); "
                              "rest-stable, finite for J <= 0",
                              true),
      entry<XpbdNeoHookean>("xpbd_neo_hookean",
                            "the neo-Hookean energy of volumetric XPBD (Macklin and Mueller 2021): "
                            "W = mu'/2 (I1 - 3) + lambda'/2 (J - alpha)^2, mu' = mu, lambda' = lambda + mu, "
                            "alpha = 1 + mu'/lambda'; rest-stable, finite for J <= 0",
                            true),
      entry<ArapVolume>("arap_volume",
                        "as-rigid-as-possible with a volume term, the solid of Projective Dynamics (Bouaziz et al. "
                        "2014): W = mu |F - R|^2 + 3 lambda/2 |F - Pi|^2, R the nearest rotation, Pi the nearest "
                        "matrix of unit determinant; finite for J <= 0",
                        true),
  };
  return laws;
}

const MaterialLawInfo& find_material_law(const std::string& name) {
  std::string known;
  for (const MaterialLawInfo& law : material_laws()) {
    if (law.name == name) return law;
    known += (known.empty() ? "" : ", ") + law.name;
  }
  throw std::invalid_argument("unknown material law \"" + name + "\"; known: " + known);
}

}  // namespace tb
