#include "constraint_kinds.h"

#include <set>
#include <stdexcept>
#include <string>

namespace tb::pbd {

// Each kind is defined in its own file, numerics/pbd/<name>_kind.cc.
const ConstraintKind& stretch_kind();
const ConstraintKind& bending_kind();

const KindTable& surface_constraint_kinds() {
  static const KindTable kinds = [] {
    KindTable table = {
        &stretch_kind(),  // eqs. (14)-(18)
        &bending_kind(),  // eqs. (19)-(26)
    };
    check_kinds(table);
    return table;
  }();
  return kinds;
}

void check_kinds(const KindTable& kinds) {
  std::set<std::string> names;
  for (const ConstraintKind* k : kinds) {
    const std::string name = k->name;
    const bool well_named = !name.empty() && name.find_first_not_of("abcdefghijklmnopqrstuvwxyz_") == std::string::npos;
    if (!well_named) throw std::invalid_argument("PBD constraint kind '" + name + "': a name of [a-z_] expected");
    if (!names.insert(name).second) throw std::invalid_argument("PBD constraint kind '" + name + "' is listed twice");
    if (k->arity < 1 || k->rest_values < 0)
      throw std::invalid_argument("PBD constraint kind '" + name + "': at least one vertex per constraint expected");
  }
}

ConstraintSet build_constraints(const SurfaceMesh& surface, const KindTable& kinds) {
  check_kinds(kinds);
  ConstraintSet c;
  for (const ConstraintKind* kind : kinds) {
    c.kinds.emplace_back(*kind);
    kind->build(surface, c.kinds.back());
  }
  return c;
}

KindConstraints::KindConstraints(const ConstraintKind& k, Eigen::Index count)
    : kind(&k), vertices(Eigen::MatrixXi::Zero(count, k.arity)), rest(Eigen::MatrixXd::Zero(count, k.rest_values)) {}

void KindConstraints::resize(Eigen::Index count) {
  vertices.resize(count, kind->arity);
  rest.resize(count, kind->rest_values);
}

const KindConstraints& ConstraintSet::of(const std::string& name) const {
  for (const KindConstraints& k : kinds)
    if (name == k.kind->name) return k;
  throw std::invalid_argument("PBD constraints: no kind '" + name + "'");
}

KindConstraints& ConstraintSet::of(const std::string& name) {
  return const_cast<KindConstraints&>(static_cast<const ConstraintSet&>(*this).of(name));
}

}  // namespace tb::pbd
