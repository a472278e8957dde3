#!/usr/bin/env python3
"""Writes the fuzz targets' seed corpus (tests/fuzz/corpus/<target>/) and the scenario
target's companion files (tests/fuzz/corpus/scenario_aux/): small valid files of every
format, made here from a unit tetrahedron and a unit cube split into five tets. None
comes from a third party. The committed corpus is this script's output:

    /usr/bin/python3 tests/fuzz/make_seeds.py
"""
import json
import os
import shutil
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
CORPUS = os.path.join(HERE, "corpus")

TET_V = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
TET_F = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]  # outward
CUBE_V = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
CUBE_QUADS = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
CUBE_F = [t for q in CUBE_QUADS for t in ((q[0], q[1], q[2]), (q[0], q[2], q[3]))]
CUBE_TETS = [(0, 1, 3, 4), (1, 2, 3, 6), (1, 4, 5, 6), (3, 4, 6, 7), (1, 3, 4, 6)]


def write(target, name, content):
    folder = os.path.join(CORPUS, target)
    os.makedirs(folder, exist_ok=True)
    mode = "wb" if isinstance(content, bytes) else "w"
    with open(os.path.join(folder, name), mode) as f:
        f.write(content)


def obj(V, F, extras=False):
    out = "# made by tests/fuzz/make_seeds.py\n" if extras else ""
    out += "".join(f"v {x} {y} {z}\n" for x, y, z in V)
    if extras:
        out += "vt 0 0\nvn 0 0 1\ng body\nusemtl skin\ns off\n"
        out += "".join("f " + " ".join(f"{i + 1}/1/1" for i in f) + "\n" for f in F[:1])
        out += "".join("f " + " ".join(str(i - len(V)) for i in f) + "\n" for f in F[1:])  # negative indices
    else:
        out += "".join("f " + " ".join(str(i + 1) for i in f) + "\n" for f in F)
    return out


def off(V, F, one_line=False):
    head = f"OFF {len(V)} {len(F)} 0\n" if one_line else f"OFF\n# comment\n{len(V)} {len(F)} 0\n"
    return head + "".join(f"{x} {y} {z}\n" for x, y, z in V) + "".join(
        f"{len(f)} " + " ".join(map(str, f)) + "\n" for f in F)


def stl_ascii(V, F):
    out = "solid seed\n"
    for f in F:
        out += " facet normal 0 0 0\n  outer loop\n"
        out += "".join(f"   vertex {V[i][0]} {V[i][1]} {V[i][2]}\n" for i in f)
        out += "  endloop\n endfacet\n"
    return out + "endsolid seed\n"


def stl_binary(V, F, header=b"binary seed"):
    out = header.ljust(80, b" ") + struct.pack("<I", len(F))
    for f in F:
        out += struct.pack("<3f", 0, 0, 0)
        for i in f:
            out += struct.pack("<3f", *V[i])
        out += b"\0\0"
    return out


def ply_ascii(V, F, extra=False):
    head = "ply\nformat ascii 1.0\ncomment seed\n"
    head += f"element vertex {len(V)}\nproperty float x\nproperty float y\nproperty float z\n"
    if extra:
        head += "property uchar red\n"
    head += f"element face {len(F)}\nproperty list uchar int vertex_indices\n"
    if extra:
        head += "element edge 1\nproperty int vertex1\nproperty int vertex2\n"
    head += "end_header\n"
    body = "".join(f"{x} {y} {z}" + (" 255" if extra else "") + "\n" for x, y, z in V)
    body += "".join(f"{len(f)} " + " ".join(map(str, f)) + "\n" for f in F)
    if extra:
        body += "0 1\n"
    return head + body


def ply_binary(V, F, big=False, double=False):
    order = ">" if big else "<"
    kind = "double" if double else "float"
    fmt = "d" if double else "f"
    head = f"ply\nformat binary_{'big' if big else 'little'}_endian 1.0\n"
    head += f"element vertex {len(V)}\nproperty {kind} x\nproperty {kind} y\nproperty {kind} z\n"
    head += f"element face {len(F)}\nproperty list {'uint8 uint32' if big else 'uchar int'} vertex_indices\nend_header\n"
    body = b"".join(struct.pack(order + "3" + fmt, *v) for v in V)
    body += b"".join(struct.pack(order + "B", len(f)) + struct.pack(order + f"{len(f)}" + ("I" if big else "i"), *f)
                     for f in F)
    return head.encode() + body


def vtu(V, cells, field=False):
    """As meshing/vtu_io.cc writes it; cells: (vtk type, node list)."""
    out = '<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">\n'
    out += f'<UnstructuredGrid>\n<Piece NumberOfPoints="{len(V)}" NumberOfCells="{len(cells)}">\n<PointData>\n'
    if field:
        out += '<DataArray type="Float64" Name="displacement" NumberOfComponents="1" format="ascii">\n'
        out += "".join("0.5\n" for _ in V) + "</DataArray>\n"
    out += '</PointData>\n<Points>\n<DataArray type="Float64" Name="Points" NumberOfComponents="3" format="ascii">\n'
    out += "".join(f"{x} {y} {z}\n" for x, y, z in V) + "</DataArray>\n</Points>\n<Cells>\n"
    out += '<DataArray type="Int32" Name="connectivity" format="ascii">\n'
    out += "".join(" ".join(map(str, c)) + "\n" for _, c in cells) + "</DataArray>\n"
    out += '<DataArray type="Int32" Name="offsets" format="ascii">\n'
    offset = 0
    for _, c in cells:
        offset += len(c)
        out += f"{offset}\n"
    out += '</DataArray>\n<DataArray type="UInt8" Name="types" format="ascii">\n'
    out += "".join(f"{t}\n" for t, _ in cells) + "</DataArray>\n</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n"
    return out


def gmsh2(V, T, offset_ids=0):
    out = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 1 \"tissue\"\n$EndPhysicalNames\n"
    out += f"$Nodes\n{len(V)}\n" + "".join(f"{i + 1 + offset_ids} {x} {y} {z}\n" for i, (x, y, z) in enumerate(V))
    out += "$EndNodes\n"
    elements = [(15, [1], [0])] + [(2, [1, 1], list(f)) for f in CUBE_F[:2]] + [(4, [1, 1], list(t)) for t in T]
    out += f"$Elements\n{len(elements)}\n"
    for k, (kind, tags, nodes) in enumerate(elements):
        out += f"{k + 1} {kind} {len(tags)} " + " ".join(map(str, tags)) + " " + " ".join(
            str(n + 1 + offset_ids) for n in nodes) + "\n"
    return out + "$EndElements\n"


def gmsh1(V, T):
    out = f"$NOD\n{len(V)}\n" + "".join(f"{i + 1} {x} {y} {z}\n" for i, (x, y, z) in enumerate(V)) + "$ENDNOD\n"
    out += f"$ELM\n{len(T) + 1}\n1 2 1 1 3 1 2 3\n"
    out += "".join(f"{k + 2} 4 1 1 4 " + " ".join(str(n + 1) for n in t) + "\n" for k, t in enumerate(T))
    return out + "$ENDELM\n"


def gmsh41(V, T, tag=lambda i: i + 1):
    """Gmsh 4.1 ASCII: $Entities, the nodes in blocks (a point, a parametric surface
    block with u v, an empty curve block, the volume), a point, a triangle and the tets."""
    tags = [tag(i) for i in range(len(V))]
    out = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 1 \"tissue\"\n$EndPhysicalNames\n"
    out += "$Entities\n1 1 1 1\n1 0 0 0 0\n1 0 0 0 1 0 0 0 2 1 -1\n1 0 0 0 1 1 0 0 1 1\n1 0 0 0 1 1 1 1 1 1 1\n"
    out += "$EndEntities\n"
    blocks = [(0, 0, range(0, 1)), (2, 1, range(1, 3)), (1, 0, range(3, 3)), (3, 0, range(3, len(V)))]
    out += f"$Nodes\n{len(blocks)} {len(V)} {min(tags)} {max(tags)}\n"
    for dim, parametric, nodes in blocks:
        out += f"{dim} 1 {parametric} {len(nodes)}\n" + "".join(f"{tags[i]}\n" for i in nodes)
        out += "".join(f"{V[i][0]} {V[i][1]} {V[i][2]}" + (" 0.5 0.5" if parametric else "") + "\n" for i in nodes)
    out += f"$EndNodes\n$Elements\n3 {len(T) + 2} 1 {len(T) + 2}\n0 1 15 1\n1 {tags[0]}\n"
    out += "2 1 2 1\n2 " + " ".join(str(tags[n]) for n in CUBE_F[0]) + "\n"
    out += f"3 1 4 {len(T)}\n" + "".join(f"{k + 3} " + " ".join(str(tags[n]) for n in t) + "\n"
                                           for k, t in enumerate(T))
    return out + "$EndElements\n"


def tetgen(V, T, first=1):
    node = f"# nodes\n{len(V)} 3 1 1\n" + "".join(
        f"{i + first} {x} {y} {z} 0.5 1\n" for i, (x, y, z) in enumerate(V))
    ele = f"{len(T)} 4 1\n" + "".join(f"{k + first} " + " ".join(str(n + first) for n in t) + " 1\n"
                                     for k, t in enumerate(T))
    return node + "\n#--ele--\n" + ele


def faces(F, first=1):
    return f"{len(F)} 1\n" + "".join(f"{k + first} " + " ".join(str(i + first) for i in f) + " -1\n"
                                    for k, f in enumerate(F))


SMALL_CUBE = {
    "name": "small",
    "description": "a cube coarse enough to mesh in a second",
    "mesh": {"type": "cube", "nx": 3, "ny": 3, "nz": 3, "fine_tetgen": {"max_volume": 2e-6},
             "coarse_selection": {"target_nodes": 20}},
    "material": {"youngs_modulus": 3000, "poisson_ratio": 0.45, "density": 1000},
    "support": {"min": [-1, -1, -1e-9], "max": [1, 1, 1e-9]},
    "load": {"point": [0, 0, 0.1], "force": [0, 0, 0.1], "ramp_frames": 5},
    "frames": {"max": 300, "static": 5, "steady_tolerance": 1e-4, "divergence_factor": 10},
    "observe": {"vertices": "top", "top_tolerance": 1e-9},
    "output": {"series_every": 0},
    "models": [{"name": "fem-direct", "model": "fem"}, {"model": "pbd", "parameters": {"iterations": 5}},
               {"model": "hybrid"}, {"model": "condensed", "parameters": {"precompute": "on_demand"}},
               {"model": "embedded"}]}


def main():
    if os.path.isdir(CORPUS):
        shutil.rmtree(CORPUS)
    write("obj", "tet.obj", obj(TET_V, TET_F, extras=True))
    write("obj", "cube_quads.obj", obj(CUBE_V, CUBE_QUADS))
    write("obj", "cube.obj", obj(CUBE_V, CUBE_F))
    write("off", "tet.off", off(TET_V, TET_F))
    write("off", "cube_quads.off", off(CUBE_V, CUBE_QUADS, one_line=True))
    write("stl_ascii", "tet.stl", stl_ascii(TET_V, TET_F))
    write("stl_ascii", "cube.stl", stl_ascii(CUBE_V, CUBE_F))
    write("stl_binary", "tet.stl", stl_binary(TET_V, TET_F))
    write("stl_binary", "cube_solid_header.stl", stl_binary(CUBE_V, CUBE_F, header=b"solid but binary"))
    write("ply_ascii", "tet.ply", ply_ascii(TET_V, TET_F))
    write("ply_ascii", "cube_quads_extra.ply", ply_ascii(CUBE_V, CUBE_QUADS, extra=True))
    write("ply_binary", "tet_le.ply", ply_binary(TET_V, TET_F))
    write("ply_binary", "cube_be_double.ply", ply_binary(CUBE_V, CUBE_QUADS, big=True, double=True))
    write("vtu_surface", "tet.vtu", vtu(TET_V, [(5, f) for f in TET_F], field=True))
    write("vtu_surface", "cube_mixed.vtu", vtu(CUBE_V, [(1, [0])] + [(5, f) for f in CUBE_F] + [(9, CUBE_QUADS[0])]))
    write("vtu_volume", "cube.vtu", vtu(CUBE_V, [(10, t) for t in CUBE_TETS], field=True))
    write("vtu_volume", "cube_mixed.vtu", vtu(CUBE_V, [(5, f) for f in CUBE_F[:2]] + [(10, t) for t in CUBE_TETS]))
    write("gmsh", "cube_v2.msh", gmsh2(CUBE_V, CUBE_TETS))
    write("gmsh", "cube_v2_ids.msh", gmsh2(CUBE_V, CUBE_TETS, offset_ids=100))
    write("gmsh", "cube_v1.msh", gmsh1(CUBE_V, CUBE_TETS))
    write("gmsh", "cube_v41.msh", gmsh41(CUBE_V, CUBE_TETS))
    write("gmsh", "cube_v41_sparse_tags.msh", gmsh41(CUBE_V, CUBE_TETS, tag=lambda i: (5 * i) % 8 * 7 + 3))
    write("tetgen", "cube_1based", tetgen(CUBE_V, CUBE_TETS, first=1))
    write("tetgen", "cube_0based", tetgen(CUBE_V, CUBE_TETS, first=0))
    write("tetgen_face", "tet.face", faces(TET_F))
    write("tetgen_face", "cube.face", faces(CUBE_F))

    # The scenario target: its companions, then its seeds.
    aux = "scenario_aux"
    write(aux, "base.json", json.dumps(SMALL_CUBE, indent=2) + "\n")
    write(aux, "scenario.json", json.dumps({
        "extends": "base.json", "name": "companion",
        "loads": [{"type": "gravity", "g": [0, 0, -9.81], "ramp_frames": 3}],
        "probes": {"file": "probes.csv"}}, indent=2) + "\n")
    write(aux, "probes.csv", "x,y,z\n0,0,0.05\n0.01,0.01,0.05\n")
    write(aux, "surface.obj", obj(TET_V, TET_F))
    os.makedirs(os.path.join(CORPUS, aux, "data", "meshes"), exist_ok=True)
    write(os.path.join(aux, "data", "meshes"), "surface.obj", obj(CUBE_V, CUBE_F))
    write(os.path.join(aux, "data", "meshes"), "coarse.msh", gmsh2(CUBE_V, CUBE_TETS))

    s = "scenario"
    write(s, "cube.json", json.dumps(SMALL_CUBE, indent=1))
    write(s, "extends.json", json.dumps({
        "extends": "base.json", "name": "pushed", "reference": "fem-direct",
        "load": {"force": [0, 0, -0.1], "disc_radius": 0.01}, "frames": {"steady_tolerance": None}}))
    write(s, "loads_tools_probes.json", json.dumps({
        "extends": "base.json", "name": "tools",
        "loads": [{"type": "point_force", "point": [0, 0, 0.1], "path": [[0, 0, 0, 0], [10, 0, 0, 0.1]]},
                  {"type": "surface_traction", "point": [0, 0, 0.1], "radius": 0.01, "force": [0, 0, 0.1],
                   "ramp_frames": 4},
                  {"type": "gravity", "g": [0, 0, -9.81]}],
        "tools": [{"type": "grasp", "point": [0.05, 0, 0.1], "radius": 0.01, "displacement": [0, 0, 0.01],
                   "ramp_frames": 3},
                  {"type": "plate", "box": {"min": [-1, -1, 0.099], "max": [1, 1, 0.11]}, "mode": "sliding",
                   "normal": "z", "path": [[0, 0, 0, 0], [5, 0, 0, -0.001], [9, 0, 0, -0.002]]}],
        "probes": {"points": [[0, 0, 0.05], [0.01, 0.01, 0.02]]}}))
    write(s, "files.json", json.dumps({
        "name": "files", "mesh": {"type": "files", "surface": "data:meshes/surface.obj",
                                  "coarse": "data:meshes/coarse.msh", "unit_scale": 0.1,
                                  "repair_self_intersections": True, "control_points": "all_surface_vertices",
                                  "build_fine_volume": False, "refine_levels": 1,
                                  "coarse_selection": {"include_points": [[0, 0, 0.1]], "seed": 3}},
        "support": {"lowest_fraction": 0.1}, "load": {"at": "nearest_surface_vertex", "point": [0, 0, 1],
                                                       "force": [0, 0, 1]},
        "probes": {"file": "probes.csv"},
        "models": [{"model": "embedded", "parameters": {"coarse_solver": "iterative"}}]}))
    write(s, "shape.json", json.dumps({
        "name": "torus", "mesh": {"type": "shape", "shape": "torus", "resolution": 8,
                                  "fine_tetgen": {"radius_edge_ratio": 2, "max_volume": 0}},
        "support": {"lowest_fraction": 0.2}, "load": {"at": "highest_surface_vertex", "force": [0, 0, 0.1]},
        "observe": {"vertices": "all"}, "output": {"series_every": 10}, "frames": {"max": 50},
        "models": [{"model": "pbd", "parameters": {"precision": "single", "threads": 2}}]}))
    write(s, "experiment.json", json.dumps({
        "name": "exp", "description": "two scenarios", "reference": "fem-direct",
        "models": [{"name": "fem-direct", "model": "fem"}],
        "scenarios": [{"file": "scenario.json", "role": "pull",
                       "models_add": [{"name": "fem-iterative", "model": "fem",
                                       "parameters": {"solver": "iterative"}}]}]}))
    write(s, "experiment_own_models.json", json.dumps({
        "name": "exp2", "scenarios": ["base.json", {"file": "scenario.json", "role": "second"}]}))
    write(s, "sweep_one_at_a_time.json", json.dumps({
        "name": "sweep", "reference": "fem-direct", "scenarios": ["base.json"],
        "sweep": {"mode": "one_at_a_time", "cases": ["fem-direct", "pbd"],
                  "factors": [{"key": "models.*.parameters.iterations", "values": [5, 10, 20]},
                              {"key": "mesh.nx", "label": "nx", "values": [3, 4]},
                              {"key": "models.fem-direct.parameters.solver", "values": ["direct", "iterative"]}]}}))
    write(s, "sweep_grid.json", json.dumps({
        "name": "grid", "reference": "fem-direct", "scenarios": [{"file": "base.json", "role": "cube"}],
        "sweep": [{"mode": "grid",
                   "factors": [{"key": "load.force", "values": [[0, 0, 0.1], [0, 0, -0.1]],
                                "value_names": ["pull", "push"]},
                               {"key": "material.poisson_ratio", "values": [0.3, 0.45]}]},
                  {"factors": [{"key": "mesh.fine_tetgen.max_volume", "values": [1e-6], "role": "reference"}]}]}))

    # The probe-point CSV of scenario.json (the probes_csv target).
    write("probes_csv", "points.csv", "x,y,z\n0,0,0.05\n0.01,0.01,0.05\n")
    write("probes_csv", "blank_lines_crlf.csv", "x,y,z\r\n\r\n 0.02 , 0.0 , 0.03\r\n\t\n-0.01,0,0.04\r\n")
    # A Truth Cube bead table in the layout of experiments/truth_cube.h (the truth_cube_csv
    # target): 7 header lines, the 6th naming the strains, then 8 corner beads made here.
    header = ("Bead table written by tests/fuzz/make_seeds.py,,,,,,,,,,,,,,\n" + ",,,,,,,,,,,,,,\n" * 4 +
              "bead nominal location,,,no strain,,,5% strain,,,12.5% strain,,,18.25% strain,,\n"
              "i,j,k,x0,y0,z0,x1,y1,z1,x2,y2,z2,x3,y3,z3\n")
    rows = ""
    for i in (1, 7):
        for j in (1, 7):
            for k in (1, 7):
                x, y, z = 10.0 * (i - 4), 10.0 * (j - 4), 10.0 * (k - 4)
                rows += f"{i},{j},{k}," + ",".join(f"{x},{y},{z + 0.5 * s * (k - 7)}" for s in range(4)) + "\n"
    write("truth_cube_csv", "corners.csv", header + rows)
    two = header.replace(",,,18.25% strain,,", "").replace(",x3,y3,z3", "")
    write("truth_cube_csv", "two_strains.csv", two + "1,1,1,-30,-30,10,-30,-30,10.5,-30,-30,11\r\n")
    # A benchmark submission (the submission target): submission.json, then each CSV after
    # its separator line, for the fixed package of tests/submission_fixture.h (whose valid
    # submission this is: three surface points and a probe, frames 1 and 2, one tool).
    submission = json.dumps({
        "format": "tissuebench-submission/1", "scenario": "tiny", "role": "tiny_role", "method": "seed",
        "resolution": {"description": "the observation points", "surface_vertices": 3, "tets": 0},
        "units": {"length": "m", "force": "N", "time": "ms", "memory": "MiB"},
        "timing": {"frame_median_ms": 10, "frame_p95_ms": 12, "setup_s": 1.5}, "peak_memory_mib": 64,
        "threads": 1, "machine": {"cpu": "seed", "cores": 2},
        "calibration": {"figure_ms": 200, "command": "tissuebench calibrate"},
        "provenance": "tests/fuzz/make_seeds.py"}, indent=1)
    rows = {f: [f"{f},{p},{0.001 * f},{0.0005 * f},{-0.001 * f}" for p in ("s0", "s1", "s2", "p0")] for f in (1, 2)}
    displacements = "frame,id,ux,uy,uz\n" + "".join(r + "\n" for f in (1, 2) for r in rows[f])
    forces = "frame,tool,fx,fy,fz\n1,grasp,0,0,0.5\n2,grasp,0,0,1\n"
    sep = "\n#--"
    write("submission", "valid.txt", submission + sep + "displacements.csv\n" + displacements + sep + "forces.csv\n" + forces)
    shuffled = "frame,id,ux,uy,uz\r\n" + "".join(r + "\r\n" for f in (1, 2) for r in reversed(rows[f]))
    write("submission", "rows_reversed_crlf.txt",
          submission + sep + "displacements.csv\n" + shuffled + sep + "forces.csv\n" + forces)
    write("submission", "last_frame_only.txt", submission + sep + "displacements.csv\n" + "frame,id,ux,uy,uz\n" +
          "".join(r + "\n" for r in rows[2]) + sep + "forces.csv\n" + "frame,tool,fx,fy,fz\n2,grasp,0,0,1\n")
    regressions()


def regressions():
    """Inputs that broke a reader once, each now refused with one line naming the file
    (tests/meshing/malformed_inputs_test.cc and tests/experiments/malformed_scenarios_test.cc
    test the same inputs): seeds, so every fuzz run replays them first."""
    tet = "".join(f"{x} {y} {z}\n" for x, y, z in TET_V)
    write("off", "regression_huge_count.off", "OFF\n99999999999 1 0\n0 0 0\n")
    write("off", "regression_face_count.off", "OFF\n4 1 0\n" + tet + "9 0 1 2\n")
    write("gmsh", "regression_huge_count.msh", "$NOD\n9223372036854775807\n1 0 0 0\n$ENDNOD\n")
    write("gmsh", "regression_negative_tags.msh",
          "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n"
          "$Elements\n1\n1 4 -5 1 2 3 4\n$EndElements\n")
    write("tetgen_face", "regression_huge_count.face", "4000000000 0\n1 1 2 3\n")
    write("tetgen_face", "regression_below_first.face", "1 0\n1 0 1 2\n")
    write("ply_ascii", "regression_huge_count.ply",
          "ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\nend_header\n0\n")
    write("ply_ascii", "regression_count_not_a_number.ply", "ply\nformat ascii 1.0\nelement vertex x\nend_header\n")
    write("ply_ascii", "regression_control_bytes.ply", "ply\nformat asc\x01ii\x7f 1.0\nend_header\n")
    header = (b"ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\nelement face 1\n")
    write("ply_binary", "regression_long_list.ply", header + b"property list uint int vertex_indices\nend_header\n"
          + struct.pack("<I", 3000000000) + bytes(12))
    write("ply_binary", "regression_nan_entry.ply", header + b"property list uchar float vertex_indices\nend_header\n"
          + bytes([3]) + struct.pack("<3f", 0, float("nan"), 2))
    write("obj", "regression_nul_in_number.obj", b"v 0 0 1\0x\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    write("scenario", "regression_deep_nesting.json", '{"name": ' + "[" * 100000 + "]" * 100000 + "}")
    write("scenario", "regression_number_beyond_double.json", '{"name": "x", "frames": {"max": 1e400}}')
    write("scenario", "regression_entry_not_a_file.json", '{"name": "e", "scenarios": ["."]}')
    write("scenario", "regression_sweep_too_large.json", json.dumps({
        "name": "e", "scenarios": ["base.json"],
        "sweep": {"mode": "grid", "factors": [{"key": k, "values": list(range(1, 31))}
                                              for k in ("mesh.nx", "mesh.ny", "mesh.nz")]}}))
    write("probes_csv", "regression_trailing_field.csv", "x,y,z\n0,0,0.05,7\n")
    # Found by the truth_cube_csv target (input 1108 of seed 1): a carriage return inside
    # the strain label line, quoted into the message, which then took two lines.
    with open(os.path.join(CORPUS, "truth_cube_csv", "corners.csv")) as f:
        lines = f.read().split("\n")
    lines[5] = lines[5].replace("5% strain", "5% st\rrain")
    write("truth_cube_csv", "regression_carriage_return.csv", "\n".join(lines))


if __name__ == "__main__":
    main()
