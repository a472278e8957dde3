// Repair of the flat and needle tets TetGen leaves when it may not split the
// boundary (-Y).
//
// To recover a fine boundary without Steiner points on it, TetGen 1.5 sometimes
// inserts an interior point almost on a surface vertex. On the liver refined to
// 140 000 surface vertices (tetgen -pYzQq1.414): 20 points within 6e-7 m of a
// node (edges there are 3e-4 m), 38 within 1/100 of a tet's longest edge; 8 of
// their tets have zero volume, the others are needles (smallest dihedral angle
// 0.0016 degrees). Merging such points into their near-coincident neighbour
// removes them and leaves the boundary as given: there 33 were merged, 2 left where
// they were (each merge would invert or flatten a tet), no flat tet is left, the
// smallest dihedral angle is 0.024 degrees and the volume equals the surface's to
// 4e-14. On the liver refined twice (34 994 surface vertices) one flat tet was left
// that way: its near-coincident point's merge would invert a tet of two other
// interior points 2.2e-5 m apart (1/20 of that tet's longest edge, so not merged
// themselves). A second pass takes such a flat tet's other interior point (2.7e-4 to
// 4.2e-4 m from the nodes of its link) into the one that leaves the best-shaped
// tets: no flat tet left, the smallest dihedral angle 0.0076 degrees.
// The paper's cube and liver, the liver at 8 750 surface vertices and the generated
// shapes have no such point (shortest over longest edge of a tet at least 0.04).
#pragma once

#include "mesh_types.h"

namespace tb {

/// Merges interior points (index >= `fixed_nodes`) into the node they nearly
/// coincide with, one at a time in tet order: for each tet whose shortest edge has
/// an interior end and is shorter than 1/100 of its longest, that end is merged
/// into the other (the lower-numbered; both ends may be interior). The tets holding
/// both go; the merge is made only if every other tet of the moved point stays
/// positively oriented and not flat (mesh_checks.h, flat_tet_volume_bound): then
/// those tets fill what the moved point's tets filled, once, so the mesh never
/// folds and the boundary is kept. Then, for each flat tet left, one of its interior
/// points is collapsed the same way into the node of its link that leaves the
/// largest smallest volume over longest edge cubed among its tets (a collapse
/// refused as above is not a candidate). The removed nodes go and the others keep
/// their order, so nodes below `fixed_nodes` keep their indices. Flat tets left (no
/// interior point, or every collapse refused) are for orient_and_check_tets to
/// report. Counts: `merged` (first pass), `flat_tets_collapsed` (second pass, one
/// point per flat tet), `refused` (points whose first-pass merge was refused and that
/// are still there after both passes). Expects every tet positively oriented, the flat ones too (their sign
/// cannot be checked, so orient_and_check_tets with FlatTets::Keep leaves them as
/// written): TetGen writes them so (of the liver's 1 138 130 tets, none negative, its
/// 8 flat ones positive).
InteriorPointMerges merge_near_coincident_interior_points(TetMesh& mesh, int fixed_nodes);

}  // namespace tb
