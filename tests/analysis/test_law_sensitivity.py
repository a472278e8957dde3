"""analysis/law_sensitivity.py on a small results tree (test_leaderboard.py's cases):
the difference between each pair of laws on the surface, the probes, the tool force
and the Truth Cube's beads, beside the ranked models' spread; the ranking under each
law's answer (the pairs in another order, the budget both fit, the leaderboard cells
another law gives to another model); the law references never ranked by the leaderboard; law cases run
alone scored beside the others (--with); a law reference whose answer inverts a tet
left out and named; a law reference whose report names no law, or a case without its
surface, is a one-line error."""
import csv
import json
import os
import sys
import tempfile
import unittest

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "analysis"))
sys.path.insert(0, HERE)
import law_sensitivity  # noqa: E402
import leaderboard  # noqa: E402
from test_leaderboard import U_REF, edit_json, write_case  # noqa: E402

NEWTON = {"solve": "newton"}
LINEAR = {"solve": "direct"}
# case: (model, its scale of the reference's answer, its fine solve, median ms).
# The law references are fast here, so a ranking that took them would rank them first.
LAWS = {"reference": ("fem", 1.0, dict(NEWTON, material_law="neo_hookean"), 300.0),
        "reference-isochoric": ("fem", 1.05, dict(NEWTON, material_law="neo_hookean_isochoric"), 0.05),
        "reference-stable": ("fem", 0.97, dict(NEWTON, material_law="stable_neo_hookean"), 0.05)}
MODELS = {"fem-linear": ("fem", 0.8, LINEAR, 2.0),
          "vbd": ("vbd", 0.99, dict(material_law="neo_hookean", solve="vertex block descent"), 60.0),
          "pbd": ("pbd", 0.3, None, 0.3),
          "mymodel": ("my_model", 1.02, None, 0.5)}
# Two beads (the table's frame is the model's here), measured 1 mm lower at 5 %.
BEADS_REST = np.array([[0.0, 0.0, 10.0], [0.0, 0.0, 20.0]])
BEADS_U = np.array([[0.0, 0.0, -1.0], [0.0, 0.0, -1.0]])
FRAME = {"origin_mm": [0, 0, 0], "centre_m": [0, 0, 0], "axes": [1, 1, 1]}


def patch_run(folder, report, truth_cube):
    path = os.path.join(folder, "run.json")
    with open(path) as f:
        run = json.load(f)
    run["model_report"] = {"fine_solve": report} if report else {}
    if truth_cube:
        run["scenario_resolved"]["probes"] = {"truth_cube": {"compare_at_strain": 0.05, "frame": FRAME}}
    with open(path, "w") as f:
        json.dump(run, f)


def write_scenario(exp, scenario, cases, probes=None, force=None, truth_cube=False):
    for name, (model, scale, report, median) in cases.items():
        write_case(exp, scenario, name, model, scale * U_REF, median,
                   probes=None if probes is None else scale * np.array(probes),
                   tool_force=None if force is None else scale * np.array(force))
        if truth_cube:  # the runner's bead probes: "probe,ux,uy,uz" in m, a row per bead of the table
            with open(os.path.join(exp, scenario, name, "probes.csv"), "w") as f:
                f.write("probe,ux,uy,uz\n")
                for i, u in enumerate(scale * BEADS_U / 1000):
                    f.write(f"{i},{u[0]},{u[1]},{u[2]}\n")
        patch_run(os.path.join(exp, scenario, name), report, truth_cube)
    return list(cases)


def write_index(exp, scenarios, law_references=("reference-isochoric", "reference-stable")):
    with open(os.path.join(exp, "experiment.json"), "w") as f:
        json.dump({"name": "suite", "reference": "reference", "law_references": list(law_references),
                   "scenarios": [{"name": s, "role": role, "cases": cases} for s, role, cases in scenarios]}, f)


def write_suite(tmp, laws=True):
    """A disc pull, a grasp with a probe and a force, a palpation (linear reference,
    no law references) and a Truth Cube; laws=False leaves the law references out."""
    exp = os.path.join(tmp, "suite")
    law_cases = LAWS if laws else {"reference": LAWS["reference"]}
    write_index(exp, [
        ("pull", "cube_pull_disc", write_scenario(exp, "pull", {**MODELS, **law_cases})),
        ("grasp", "torus_grasp", write_scenario(exp, "grasp", {**MODELS, **law_cases}, probes=[[0, 0, 0.002]],
                                                force=[0, 0, -2.0])),
        ("palp", "cube_palpation", write_scenario(exp, "palp", {"reference": ("fem", 1.0, LINEAR, 100.0),
                                                                "fem-linear": ("fem", 1.0, LINEAR, 100.0),
                                                                "pbd": MODELS["pbd"]})),
        ("tc", "truth_cube_5", write_scenario(exp, "tc", {**law_cases, "fem-linear": MODELS["fem-linear"],
                                                          "vbd": MODELS["vbd"]}, truth_cube=True))])
    return exp


def write_bead_table(tmp):
    """The Truth Cube table of the two beads (analysis/truth_cube.py's reader), in DATA/data/truthcube/."""
    folder = os.path.join(tmp, "data", "data", "truthcube")
    os.makedirs(folder)
    measured = BEADS_REST + BEADS_U
    with open(os.path.join(folder, "uniaxial_positions.csv"), "w") as f:
        f.write("Truth Cube\n\n\n\n\nbead nominal location,,,no strain,,,5% strain,,\ni,j,k,x0,y0,z0,x1,y1,z1\n")
        for k, (p, q) in enumerate(zip(BEADS_REST, measured)):
            f.write(f"4,4,{k + 1}," + ",".join(f"{x:.2f}" for x in (*p, *q)) + "\n")
    return os.path.join(tmp, "data")


class LawSensitivity(unittest.TestCase):
    def test_each_pair_of_laws_beside_the_models_spread(self):
        with tempfile.TemporaryDirectory() as tmp:
            out = law_sensitivity.make(write_suite(tmp), tmp, write_bead_table(tmp))
            pull = out["cube_pull_disc"]
            self.assertEqual(pull["laws"], {"neo_hookean": "reference", "neo_hookean_isochoric": "reference-isochoric",
                                            "stable_neo_hookean": "reference-stable", "linear": "fem-linear"})
            field = pull["values"]["surface field"]
            for pair, expected in (("coupled vs isochoric", 0.05), ("coupled vs stable", 0.03),
                                   ("isochoric vs stable", 0.08), ("coupled vs linear", 0.2),
                                   ("isochoric vs linear", 0.25), ("stable vs linear", 0.17)):
                self.assertAlmostEqual(field[pair], expected, msg=pair)
            # Ranked: fem-linear 0.2, vbd 0.01, pbd 0.7, mymodel 0.02 (the law references are not models);
            # below the law gap (isochoric vs stable, 0.08): vbd and mymodel.
            self.assertAlmostEqual(field["models min"], 0.01)
            self.assertAlmostEqual(field["models median"], 0.11)
            self.assertAlmostEqual(field["models max"], 0.7)
            self.assertEqual((field["models n"], field["models below the law gap"]), (4, 2))
            self.assertEqual(field["models below"], ["vbd", "mymodel"])
            self.assertNotIn("probes", pull["values"])  # no probes, no tool on the disc pull
            grasp = out["torus_grasp"]["values"]
            self.assertAlmostEqual(grasp["probes"]["coupled vs stable"], 0.03)
            self.assertAlmostEqual(grasp["probes"]["models min"], 0.01)  # pbd has probes here: 0.7
            self.assertAlmostEqual(grasp["tool force"]["isochoric vs linear"], 0.25)
            self.assertEqual(grasp["tool force"]["models n"], 4)
            palpation = out["cube_palpation"]
            self.assertEqual(palpation["laws"], {"linear": "reference"})  # its reference is the linear law
            self.assertTrue(np.isnan(palpation["values"]["surface field"]["models below the law gap"]))
            beads = out["truth_cube_5"]["beads"]  # 1 mm measured: each law off by |1 - its scale| mm
            for law, expected in (("coupled", 0.0), ("isochoric", 0.05), ("stable", 0.03), ("linear", 0.2)):
                self.assertAlmostEqual(beads[law], expected, places=9, msg=law)
            self.assertAlmostEqual(beads["models min"], 0.01, places=9)  # vbd
            with open(os.path.join(tmp, "tables", "law_sensitivity.md")) as f:
                md = f.read()
            self.assertIn("| cube_pull_disc | coupled | surface field | \\|\\|u_ref\\|\\| = 5 mm | 0.05 | 0.03 | "
                          "0.08 | 0.2 | 0.25 | 0.17 | 0.01 | 0.11 | 0.7 | 2 of 4 |", md)
            self.assertIn("| cube_palpation | linear | surface field |", md)
            self.assertIn("its law references are not run", md)
            self.assertIn("| truth_cube_5 | 0 | 0.05 | 0.03 | 0.2 | 0.01 | 0.105 | 0.2 |", md)
            self.assertIn("from 0.08 (cube_pull_disc) to 0.08 (cube_pull_disc) of ||u_ref||", md)
            self.assertIn("Ranked models below the gap (surface field): cube_pull_disc (vbd, mymodel);", md)
            # With the isochoric answer (1.05) as the reference, mymodel (1.02) is nearer than vbd (0.99);
            # vbd (60 ms) fits no budget, so no leaderboard cell changes.
            self.assertIn("| cube_pull_disc | isochoric | 1 of 6 | same | same | same |", md)
            self.assertIn("| cube_pull_disc | isochoric | over 16 ms | vbd, mymodel | 0.01, 0.02 | 0.06, 0.03 |", md)
            self.assertIn("| cube_pull_disc | stable | 0 of 6 | same | same | same |", md)
            self.assertIn("| truth_cube_5 | isochoric | 0 of 1 | n/a (the beads rank) |", md)
            self.assertIn("change order in cube_pull_disc (1 pair under isochoric);", md)
            self.assertIn("0 of the 12 leaderboard cells ranked by the surface field", md)
            with open(os.path.join(tmp, "tables", "law_sensitivity.csv")) as f:
                rows = list(csv.reader(f))
            force = {r[2]: r[3] for r in rows if r[:2] == ["torus_grasp", "tool force"]}
            self.assertAlmostEqual(float(force["coupled vs isochoric"]), 0.05)
            self.assertEqual(force["models n"], "4")

    def test_a_leaderboard_cell_another_law_gives_to_another_model(self):
        with tempfile.TemporaryDirectory() as tmp:
            exp = write_suite(tmp)
            # vbd (0.01) now takes the 16 ms cell under the coupled law
            edit_json(os.path.join(exp, "pull", "vbd", "timings.json"),
                      lambda timings: timings["step"].update(median_ms=10.0))
            out = law_sensitivity.make(exp, tmp, write_bead_table(tmp))
            changes = law_sensitivity.cell_changes(out["cube_pull_disc"])
            self.assertEqual([(law, budget, ref[0], other[0]) for law, _, budget, ref, other in changes],
                             [("isochoric", 16.0, "vbd", "mymodel")])
            with open(os.path.join(tmp, "tables", "law_sensitivity.md")) as f:
                md = f.read()
            self.assertIn("| cube_pull_disc | isochoric | 1 of 6 | same | same | mymodel 0.03 (coupled: vbd 0.01) |",
                          md)
            self.assertIn("| cube_pull_disc | isochoric | 16 ms | vbd, mymodel | 0.01, 0.02 | 0.06, 0.03 |", md)
            self.assertIn("1 of the 12 leaderboard cells ranked by the surface field (a scenario, a budget, a law) go "
                          "to another model (1 within 16 ms: the next-to-last table).", md)

    def test_equal_errors_are_a_tie_not_a_swap(self):
        errors = {"fem-linear": 0.1, "condensed": 0.1 + 1e-12, "vbd": 0.2}
        other = {"fem-linear": 0.1 + 1e-12, "condensed": 0.1, "vbd": 0.05}
        self.assertEqual(law_sensitivity.swapped(errors, other),
                         ([("fem-linear", "vbd"), ("condensed", "vbd")], 3))

    def test_the_leaderboard_ranks_no_law_reference(self):
        with tempfile.TemporaryDirectory() as tmp:
            scores = leaderboard.make(write_suite(tmp), tmp, write_bead_table(tmp), figures=False)
            by_case = {s["case"]: s for s in scores["cube_pull_disc"]}
            self.assertTrue(by_case["reference-isochoric"]["is_reference"])  # scored, listed in suite_scores
            self.assertAlmostEqual(by_case["reference-stable"]["rel_l2"], 0.03)
            with open(os.path.join(tmp, "tables", "leaderboard.csv")) as f:
                board = {r[0]: r for r in csv.reader(f)}
            # At 0.05 ms the law references would take the 0.1 ms budget; nothing else fits it.
            self.assertEqual(board["cube_pull_disc"][2:5], ["none fits", "mymodel 0.02", "mymodel 0.02"])

    def test_law_cases_run_alone_are_scored_beside_the_others(self):
        with tempfile.TemporaryDirectory() as tmp:
            committed = write_suite(os.path.join(tmp, "committed"), laws=False)
            alone = os.path.join(tmp, "alone", "suite")
            write_index(alone, [("pull", "cube_pull_disc", write_scenario(alone, "pull", LAWS))])
            path = os.path.join(alone, "pull", "reference-isochoric", "run.json")
            with open(path) as f:
                run = json.load(f)
            run["build"] = dict(run["build"], git_commit="def", hardware_threads=2)  # built later than the others
            with open(path, "w") as f:
                json.dump(run, f)
            with open(os.path.join(os.path.dirname(path), "timings.json"), "w") as f:  # and run beside other work
                json.dump({"load_average_1min": {"at_setup": 3.5}}, f)
            out = law_sensitivity.make(committed, tmp, write_bead_table(tmp), with_results=alone)
            with open(os.path.join(tmp, "tables", "law_sensitivity.md")) as f:
                text = f.read()
            self.assertIn("commit def; threads as each case's parameters say (reference-isochoric).", text)
            self.assertEqual(text.count("On a busy machine"), 1, "the busy cases are named once, not per commit")
            self.assertIn("cube_pull_disc/reference-isochoric (load 3.5).", text)
            field = out["cube_pull_disc"]["values"]["surface field"]
            self.assertAlmostEqual(field["isochoric vs linear"], 0.25)  # the committed fem-linear
            self.assertEqual(field["models n"], 4)
            self.assertNotIn("coupled vs isochoric", out["torus_grasp"]["values"]["surface field"])
            with self.assertRaises(law_sensitivity.ResultsError):  # nothing to add
                law_sensitivity.make(committed, tmp, None, with_results=committed)

    def test_a_law_reference_whose_answer_inverts_a_tet_is_left_out_and_named(self):
        with tempfile.TemporaryDirectory() as tmp:
            exp = write_suite(tmp)
            patch_run(os.path.join(exp, "pull", "reference-stable"),
                      dict(LAWS["reference-stable"][2], smallest_det_f_last_solve=-0.47), False)
            patch_run(os.path.join(exp, "grasp", "reference-stable"),
                      dict(LAWS["reference-stable"][2], smallest_det_f_last_solve=0.2), False)
            out = law_sensitivity.make(exp, tmp, write_bead_table(tmp))
            pull = out["cube_pull_disc"]
            self.assertNotIn("stable_neo_hookean", pull["laws"])
            self.assertEqual(pull["inverted"], {"stable_neo_hookean": ("reference-stable", -0.47)})
            field = pull["values"]["surface field"]
            self.assertNotIn("coupled vs stable", field)
            # The gap is now coupled vs isochoric's 0.05: vbd (0.01) and mymodel (0.02) below it.
            self.assertEqual(field["models below"], ["vbd", "mymodel"])
            self.assertNotIn("stable", pull["rankings"])
            # An uninverted answer (det F 0.2) stays.
            self.assertIn("coupled vs stable", out["torus_grasp"]["values"]["surface field"])
            with open(os.path.join(tmp, "tables", "law_sensitivity.md")) as f:
                md = f.read()
            self.assertIn("Left out, their answer inverting tets (the law is defined past det F = 0, a tissue is "
                          "not): stable on cube_pull_disc (reference-stable: smallest det F -0.47).", md)
            with open(os.path.join(tmp, "tables", "law_sensitivity.csv")) as f:
                rows = list(csv.reader(f))
            self.assertIn(["cube_pull_disc", "left out: inverts a tet", "stable (reference-stable)", "-0.47",
                           "smallest det F"], rows)

    def test_bad_results_are_one_line_errors(self):
        with tempfile.TemporaryDirectory() as tmp:
            exp = write_suite(tmp)
            patch_run(os.path.join(exp, "pull", "reference-stable"), None, False)
            data = write_bead_table(tmp)
            with self.assertRaisesRegex(law_sensitivity.ResultsError, r"reference-stable/run\.json: .*no material law"):
                law_sensitivity.make(exp, tmp, data)
            patch_run(os.path.join(exp, "pull", "reference-stable"), LAWS["reference-stable"][2], False)
            os.remove(os.path.join(exp, "pull", "vbd", "top_surface.csv"))
            with self.assertRaisesRegex(law_sensitivity.ResultsError, r"pull/vbd: unreadable results"):
                law_sensitivity.make(exp, tmp, data)


if __name__ == "__main__":
    unittest.main()
