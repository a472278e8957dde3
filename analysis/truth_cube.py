"""The Truth Cube: every case's bead positions against the CT-measured ones.

Usage: /usr/bin/python3 analysis/truth_cube.py RESULTS/truth_cube OUT [--data-dir DIR]

RESULTS/truth_cube is the runner's output of experiments/truth_cube.json. The bead
table (Kerdok et al., Medical Image Analysis 7(3):283-291, 2003) is third-party data,
read from the data directory (--data-dir, else $TISSUEBENCH_DATA, else ../shared
beside the repository; README "Data"), never copied into the results. Each case's
run.json names the table and the rigid frame the runner moved it into
(experiments/truth_cube.h); probes.csv holds the case's displacement at each bead's
rest position, by row of the table.

Writes OUT/tables/truth_cube.{md,csv} and OUT/figures/truth_cube_beads.png,
OUT/figures/truth_cube_slice.png. docs/truth_cube.md says what they show.
"""
import argparse
import os
import sys

import numpy as np

import results_index
from results_index import ResultsError
from table_io import fmt, machine_note, write_table

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
STRAIN_TAGS = {0.05: "5", 0.125: "12_5", 0.1825: "18_25"}
MODES = ("bonded", "sliding")
HEADER_LINES = 7


def data_dir(flag):
    if flag:
        return flag
    if os.environ.get("TISSUEBENCH_DATA"):
        return os.environ["TISSUEBENCH_DATA"]
    return os.path.normpath(os.path.join(REPO, "..", "shared"))


def read_table(path):
    """(grid #beads x 3 ints, positions #beads x strains x 3 mm, strains) in the table's frame."""
    if not os.path.isfile(path):
        raise ResultsError(f"{path}: the Truth Cube table is not there (README 'Data' says where to obtain it)")
    with open(path) as f:
        lines = f.read().splitlines()
    labels = lines[5].split(",")
    strains = [0.0] + [float(c.split("%")[0]) / 100 for c in labels if "% strain" in c]
    rows = np.array([[float(v) for v in line.split(",")[: 3 + 3 * len(strains)]]
                     for line in lines[HEADER_LINES:] if line.strip(" ,")])
    return rows[:, :3].astype(int), rows[:, 3:].reshape(len(rows), len(strains), 3), strains


def to_model_mm(positions_mm, frame):
    """The runner's rigid motion (truth_cube.h), in mm."""
    origin = np.array(frame["origin_mm"])
    return np.array(frame["centre_m"]) * 1000 + np.array(frame["axes"]) * (positions_mm - origin)


def measurement_resolution(positions):
    """What the table can resolve, from the table alone.

    The coordinates are given to 0.01 mm, and one axis is quantised on a coarser grid
    (the CT slice spacing): per axis, the largest step (with its best offset) on which
    more than half of the values lie. The displacement field is smooth at the beads'
    1 cm spacing: a polynomial of degree 5 in the rest position (56 terms, per component
    and strain) fitted to the 343 beads leaves a residual (scaled for the fitted
    parameters) that bounds the noise of a measured displacement from above, per axis
    and in all. A model exact to the physics would still score about this RMS error:
    the floor of the table."""
    flat = positions.reshape(-1, 3)

    def share_on_grid(v, step):  # the largest share of values on one offset of this grid (to 0.01 mm)
        return max(np.mean(np.abs(((v - o) / step - np.round((v - o) / step)) * step) <= 0.0051)
                   for o in np.arange(0, step, 0.005))

    steps = []
    for axis in range(3):
        v = flat[:, axis]
        step_found = 0.01
        for step in (1.0, 0.5, 0.25, 0.2, 0.125, 0.1):
            # A multiple of the true grid also holds many values (half of them for twice
            # the step): a grid counts only if it holds nearly as many as its half does.
            share = share_on_grid(v, step)
            if share > 0.5 and share >= 0.9 * share_on_grid(v, step / 2):
                step_found = step
                break
        steps.append(step_found)
    rest = positions[:, 0, :]
    x = (rest - rest.mean(axis=0)) / 30.0
    degree = 5
    powers = [(a, b, c) for a in range(degree + 1) for b in range(degree + 1) for c in range(degree + 1)
              if a + b + c <= degree]
    basis = np.stack([x[:, 0] ** a * x[:, 1] ** b * x[:, 2] ** c for a, b, c in powers], axis=1)
    residuals = []
    for s in range(1, positions.shape[1]):
        u = positions[:, s, :] - rest
        coef, *_ = np.linalg.lstsq(basis, u, rcond=None)
        # unbiased for the fit's 56 parameters per component: the residual's variance
        # is (n - p) / n of the noise's when the field itself is fitted exactly
        r = (u - basis @ coef) * np.sqrt(len(u) / (len(u) - basis.shape[1]))
        residuals.append((float(np.sqrt(np.mean(np.sum(r ** 2, axis=1)))), np.sqrt(np.mean(r ** 2, axis=0))))
    quantisation = float(np.sqrt(np.sum(np.square(steps) / 12.0)))
    return steps, quantisation, residuals


def case_beads(case, table_positions, strains):
    """rest, measured, predicted positions (mm, model frame) of one case, or None if it has no probes."""
    run = case["run"]
    source = run["scenario_resolved"]["probes"]["truth_cube"]
    path = os.path.join(case["folder"], "probes.csv")
    if not os.path.isfile(path):
        return None
    strain = source["compare_at_strain"]
    column = min(range(len(strains)), key=lambda i: abs(strains[i] - strain))
    rest = to_model_mm(table_positions[:, 0, :], source["frame"])
    measured = to_model_mm(table_positions[:, column, :], source["frame"])
    u = np.loadtxt(path, delimiter=",", skiprows=1)
    if u.shape[0] != rest.shape[0]:
        raise ResultsError(f"{path}: {u.shape[0]} beads, the table has {rest.shape[0]}")
    return rest, measured, rest + u[:, 1:4] * 1000


def without_layer_shear(rest, positions, grid):
    """positions with each bead layer's (k) mean horizontal displacement taken out."""
    out = positions.copy()
    for k in np.unique(grid[:, 2]):
        layer = grid[:, 2] == k
        out[layer, :2] -= (positions[layer, :2] - rest[layer, :2]).mean(axis=0)
    return out


def layer_shear_rms(rest, measured, grid):
    """RMS over the beads of their layer's mean horizontal displacement (mm)."""
    return float(np.sqrt(np.mean(np.sum((measured - without_layer_shear(rest, measured, grid)) ** 2, axis=1))))


def errors(rest, measured, predicted, grid):
    e = np.linalg.norm(predicted - measured, axis=1)
    d = np.linalg.norm(measured - rest, axis=1)
    centre = grid[:, 1] == 4  # the slice through the cube's centre normal to y
    unsheared = np.linalg.norm(without_layer_shear(rest, predicted, grid) - without_layer_shear(rest, measured, grid),
                               axis=1)
    return {"rms": float(np.sqrt(np.mean(e ** 2))), "max": float(e.max()),
            "unsheared_rms": float(np.sqrt(np.mean(unsheared ** 2))),
            "centre_rms": float(np.sqrt(np.mean(e[centre] ** 2))),
            "relative": float(np.sqrt(np.mean(e ** 2) / np.mean(d ** 2))),
            "measured_rms": float(np.sqrt(np.mean(d ** 2)))}


def implied_top_displacement(rest, measured, grid):
    """The top face's displacement the beads imply: the two layers nearest the plate
    (k = 6, 7) extrapolated linearly in height to the top (z = 80 mm), mm."""
    z = {k: rest[grid[:, 2] == k, 2].mean() for k in (6, 7)}
    w = {k: (measured - rest)[grid[:, 2] == k, 2].mean() for k in (6, 7)}
    return w[7] + (w[7] - w[6]) * (80.0 - z[7]) / (z[7] - z[6])


def support_force_n(folder):
    """|force| on the support at the last frame (N), from the case's reactions.csv."""
    path = os.path.join(folder, "reactions.csv")
    if not os.path.isfile(path):
        raise ResultsError(f"{path}: missing (the runner writes it for every model that measures reactions)")
    with open(path) as f:
        rows = [line.rstrip("\n").split(",") for line in f][1:]
    final = max(int(x[0]) for x in rows)
    last = [r for r in rows if r[1] == "support" and int(r[0]) == final]
    if not last:
        raise ResultsError(f"{path}: no support row")
    return float(np.linalg.norm([float(v) for v in last[0][3:6]]))


def reference_levels(e, positions, strains, grid, scored):
    """The reference's own discretisation error at 18.25 % bonded: how far each case's
    beads move between the coarse level (role truth_cube_18_25_bonded_coarse, 8
    divisions a side) and the table's level (16), as a paragraph ("" without it)."""
    role = "truth_cube_18_25_bonded_coarse"
    names = e.roles.get(role, [])
    if len(names) != 1 or names[0] not in e.scenarios:
        return ""
    parts = []
    for name, case in e.by_role(role).items():
        if case["run"]["model"] not in ("fem", "fem_distributed"):
            continue  # a coarse-mesh model's coarse mesh is chosen anew, not refined
        fine = scored.get((0.1825, "bonded", name))
        coarse = case_beads(case, positions, strains)
        if fine is None or coarse is None:
            continue
        change = np.linalg.norm(fine[1][2] - coarse[2], axis=1)
        forces = [support_force_n(c["folder"]) for c in (case, e.by_role("truth_cube_18_25_bonded")[name])]
        parts.append(f"{name} {np.sqrt(np.mean(change ** 2)):.2f} mm (its score {fine[0]['rms']:.2f} mm, "
                     f"{errors(coarse[0], coarse[1], coarse[2], grid)['rms']:.2f} on the coarse mesh; the plate's "
                     f"force {forces[0]:.1f} N coarse, {forces[1]:.1f} N on this table's mesh)")
    if not parts:
        return ""
    return f"""
The reference's own error (18.25 %, bonded): between the coarse mesh (8 divisions a side,
tets at most 8 times larger) and this table's (16), the beads move by (RMS) {"; ".join(parts)}.
If a case's error falls at least linearly with the mesh size, its error on this table's
mesh is at most its change between the levels (Richardson: change / (2^p - 1), p >= 1);
P2's asymptotic order (p = 3 for displacements) would make it a seventh of it.
"""


def make(results, out, data_flag):
    e = results_index.Experiment(results)
    table_path = os.path.join(data_dir(data_flag), "data", "truthcube", "uniaxial_positions.csv")
    grid, positions, strains = read_table(table_path)
    steps, quantisation, residuals = measurement_resolution(positions)

    rows, scored = [], {}
    frame = None
    for mode in MODES:
        for strain, tag in STRAIN_TAGS.items():
            role = f"truth_cube_{tag}_{mode}"
            cases = e.by_role(role)
            scenario = e.scenario_name(role)
            for name in e.listed_cases.get(scenario, []):
                if name not in cases:
                    why = e.failure(scenario, name) or "not run"
                    rows.append([f"{strain * 100:g}", mode, name] + ["n/a"] * 6 + [f"no results: {why}"])
            for name, case in cases.items():
                beads = case_beads(case, positions, strains)
                timing = case["timings"]["step"]
                if beads is None:
                    why = case["run"].get("observables", {}).get("probes", "no probes.csv")
                    rows.append([f"{strain * 100:g}", mode, name, "n/a", "n/a", "n/a", "n/a", "n/a",
                                 fmt(timing["median_ms"], 2), f"no interior: {why}"])
                    continue
                rest, measured, predicted = beads
                frame = frame or case["run"]["scenario_resolved"]["probes"]["truth_cube"]["frame"]
                m = errors(rest, measured, predicted, grid)
                scored[(strain, mode, name)] = (m, beads)
                rows.append([f"{strain * 100:g}", mode, name, fmt(m["rms"], 2), fmt(m["max"], 2),
                             fmt(m["centre_rms"], 2), fmt(m["unsheared_rms"], 2), fmt(m["relative"], 3),
                             fmt(timing["median_ms"], 2), ""])
    if not scored:
        raise ResultsError(f"{results}: no case wrote probes.csv")

    level_text = reference_levels(e, positions, strains, grid, scored)
    rest_all = to_model_mm(positions[:, 0, :], frame)
    implied = []
    for s in range(1, len(strains)):
        meas = to_model_mm(positions[:, s, :], frame)
        implied.append((strains[s], implied_top_displacement(rest_all, meas, grid)))
    implied_text = "; ".join(f"{st * 100:g} %: {-w:.1f} mm (nominal {st * 80:.1f} mm)" for st, w in implied)
    shear_text = ", ".join(f"{layer_shear_rms(rest_all, to_model_mm(positions[:, s, :], frame), grid):.2f}"
                           for s in range(1, len(strains)))
    notes = f"""
RMS and max of |predicted - measured| bead position (mm) over the 343 beads; centre: the
49 beads of the slice through the centre (j = 4); unsheared: the RMS once each bead
layer's mean horizontal displacement is taken out of the measured and the predicted
positions alike (the beads show a shear no vertical plate produces: the layers' mean
horizontal displacement is {shear_text} mm RMS at 5, 12.5, 18.25 %, growing with height);
relative: RMS error over the RMS measured bead displacement; frame: median time of a
frame (ms; taken while other jobs shared the 2 cores: compare within a row's strain
only). The plate moves by the nominal strain times 80 mm; the material is OpenSurgSim's
(E = 15.3 kPa, nu = 0.499), not fitted. The hybrid's interior is its coarse FEM's, as
embedded's: their bead errors are the same.

The measurement's resolution, from the table alone: positions given to 0.01 mm, on
grids of {", ".join(f"{s:g}" for s in steps)} mm along the table's x, y, z (a quantisation of
{quantisation:.2f} mm RMS); a smooth field (degree-5 polynomial) fitted to the measured
displacements leaves {", ".join(f"{r[0]:.2f}" for r in residuals)} mm RMS at 5, 12.5, 18.25 %
(per axis at 18.25 %: {", ".join(f"{v:.2f}" for v in residuals[-1][1])} mm), an upper bound on
the noise of a measured displacement and the floor a model exact to the physics would
still score. The top displacement
the beads imply (the two layers nearest the plate extrapolated to the top face):
{implied_text}.
{level_text}
{machine_note(e.scenarios[next(iter(e.scenarios))])}
"""
    write_table(os.path.join(out, "tables"), "truth_cube",
                ["strain (%)", "plate", "case", "RMS (mm)", "max (mm)", "centre RMS (mm)", "unsheared RMS (mm)",
                 "relative", "frame (ms)", "note"], rows, notes)
    figures(scored, grid, os.path.join(out, "figures"))
    print(f"truth_cube: {len(rows)} rows -> {out}/tables/truth_cube.md")


def figures(scored, grid, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    os.makedirs(out, exist_ok=True)
    names = sorted({k[2] for k in scored}, key=lambda n: list(dict.fromkeys(k[2] for k in scored)).index(n))
    fig, axes = plt.subplots(len(MODES), len(STRAIN_TAGS), figsize=(12, 7.5), squeeze=False)
    for r, mode in enumerate(MODES):
        for c, strain in enumerate(STRAIN_TAGS):
            ax = axes[r][c]
            for name in names:
                if (strain, mode, name) not in scored:
                    continue
                _, (rest, measured, predicted) = scored[(strain, mode, name)]
                ax.plot(measured[:, 2] - rest[:, 2], predicted[:, 2] - rest[:, 2], ".", ms=3, label=name)
            lim = ax.get_xlim()
            ax.plot(lim, lim, "k-", lw=0.8)
            ax.set_title(f"{strain * 100:g} %, plate {mode}", fontsize=9)
            ax.set_xlabel("measured u_z (mm)", fontsize=8)
            ax.set_ylabel("predicted u_z (mm)", fontsize=8)
    axes[0][0].legend(fontsize=7)
    fig.suptitle("Truth Cube: vertical bead displacement, predicted against measured (every bead)")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "truth_cube_beads.png"), dpi=110)
    plt.close(fig)

    strain, mode = 0.1825, "bonded"
    shown = [n for n in names if (strain, mode, n) in scored][:3]
    fig, axes = plt.subplots(1, len(shown) + 1, figsize=(4 * (len(shown) + 1), 4.2), squeeze=False)
    centre = grid[:, 1] == 4
    _, (rest, measured, _) = scored[(strain, mode, shown[0])]
    panels = [("measured", measured)] + [(n, scored[(strain, mode, n)][1][2]) for n in shown]
    for ax, (title, pos) in zip(axes[0], panels):
        d = pos - rest
        ax.quiver(rest[centre, 0], rest[centre, 2], d[centre, 0], d[centre, 2], angles="xy", scale_units="xy",
                  scale=1, width=0.004)
        ax.plot([-40, 40, 40, -40, -40], [0, 0, 80, 80, 0], "k-", lw=0.6)
        ax.set_aspect("equal")
        ax.set_xlim(-45, 45)
        ax.set_ylim(-5, 85)
        ax.set_title(title, fontsize=9)
        ax.set_xlabel("x (mm)", fontsize=8)
    axes[0][0].set_ylabel("z (mm)", fontsize=8)
    fig.suptitle("Truth Cube, 18.25 %, plate bonded: bead displacements in the centre slice (to scale)")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "truth_cube_slice.png"), dpi=110)
    plt.close(fig)


def run_command(make_tables, name, doc):
    """The command line of a script over the Truth Cube's results: RESULTS OUT [--data-dir DIR],
    then make_tables(results, out, data_dir) (a ResultsError is one line)."""
    p = argparse.ArgumentParser(description=doc.splitlines()[0])
    p.add_argument("results")
    p.add_argument("out")
    p.add_argument("--data-dir", default="")
    a = p.parse_args()
    results_index.main(lambda: make_tables(a.results, a.out, a.data_dir), name)


def main():
    run_command(make, "truth_cube", __doc__)


if __name__ == "__main__":
    main()
