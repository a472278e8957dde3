// Vertices split into spatial domains for the PBD sweep on several threads
// (issue 16). A constraint whose vertices all lie in one domain is independent
// of every constraint of another domain, so each thread can sweep whole domains
// with no barrier between colours; only the constraints that cross domains (the
// interface, a few per cent) are swept colour by colour with barriers
// (constraint_batches.h).
#pragma once

#include <vector>

#include "mesh_types.h"

namespace tb::pbd {

/// Recursive coordinate bisection: the vertices split at the median of the
/// bounding box's longest axis (ties broken by index), recursively, into
/// `domains` parts whose sizes differ by at most one. Deterministic.
///   positions  #V by 3
///   returns    #V domain indices in [0, domains); all 0 when domains is 1
std::vector<int> bisect_into_domains(const Points& positions, int domains);

}  // namespace tb::pbd
