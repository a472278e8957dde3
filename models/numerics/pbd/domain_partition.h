// Vertices split into spatial domains for the PBD sweep on several threads
// (docs/scaling.md). A constraint whose vertices all lie in one domain is independent
// of every constraint of another domain, so each thread can sweep whole domains
// with no barrier between colours; only the constraints that cross domains (the
// interface, a few per cent) are swept colour by colour with barriers
// (constraint_batches.h).
#pragma once

#include <vector>

#include "mesh_types.h"

namespace tb::pbd {

/// Recursive coordinate bisection: the vertices split at the weighted median of
/// the longest axis of the bounding box of the vertices with work (ties broken by
/// index), recursively, into `domains` parts whose work differs by at most one
/// vertex's. Work balances the threads: a fixed vertex moves nothing (the
/// constraints among fixed vertices are dropped), so the solver gives it none; by
/// vertex count alone a plane along the support put 40 % of the constraints on one
/// side of the 40 346-vertex cube. Deterministic.
///   positions  #V by 3
///   work       #V non-negative weights, or empty: 1 each (sizes differ by at most one)
///   returns    #V domain indices in [0, domains); all 0 when domains is 1
std::vector<int> bisect_into_domains(const Points& positions, int domains, const std::vector<double>& work = {});

}  // namespace tb::pbd
