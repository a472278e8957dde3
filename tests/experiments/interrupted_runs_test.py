"""Interrupted runs leave every result folder complete or absent (docs/robustness.md,
"Interrupted runs").

Each command below writes several result folders. It is started, interrupted by
SIGINT, SIGTERM or SIGKILL once its first case folder exists (polled, so the signal
lands mid-run whatever the machine's load), and then:

- every folder it was writing is complete (every file a finished run writes, each
  whole: JSON that parses, VTU that ends, CSVs of the finished run's length) or
  absent; staging folders (<name>.tmp<pid>, <name>.old<pid>) are allowed, and are
  not taken for results (analysis/results_index.py);
- the same command rerun finishes, removes what the interrupted run left, and
  results_index lists exactly the experiment's cases.

The commands: a sweep (`tissuebench run` on an experiment of several points, one
process), `mpirun -n 2 tissuebench run` on the distributed FEM (the signal goes to
mpirun, as a terminal's Ctrl-C or a batch system's kill would), and `tissuebench
mesh`. Before each rerun, staging folders of a process that no longer exists, run.json
and all, are planted beside the results: the rerun must remove them.

Usage: interrupted_runs_test.py MPIEXEC TISSUEBENCH SOURCE_DIR
(TB_INTERRUPTED_ONLY=REGEX: only the checks whose label matches, e.g. "mpirun.*SIGKILL")
"""
import json
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET

MPIEXEC, CLI, SRC = sys.argv[1:4]
sys.path.insert(0, os.path.join(SRC, "analysis"))
import results_index  # noqa: E402

STAGING = re.compile(r"\.(tmp|old)\d+$")
SIGNALS = [("SIGINT", signal.SIGINT), ("SIGTERM", signal.SIGTERM), ("SIGKILL", signal.SIGKILL)]
FAILURES = []


def fail(message):
    print("FAIL: " + message, flush=True)
    FAILURES.append(message)


CUBE = {"type": "cube", "nx": 4, "ny": 4, "nz": 4, "fine_tetgen": {"max_volume": 2e-6},
        "coarse_selection": {"target_nodes": 30}}


def sweep_experiment(folder):
    """Four points x two PBD cases, each a fixed 25 000 frames (about 0.5 s on a 2-vCPU
    machine: 2500 frames were 0.05 s, so that under load a poll late by 0.4 s saw every
    case written before the signal)."""
    scenario = {
        "name": "long",
        "mesh": CUBE,
        "support": {"min": [-1, -1, -1e-9], "max": [1, 1, 1e-9]},
        "load": {"point": [0, 0, 0.1], "force": [0, 0, 0.1], "ramp_frames": 5},
        "frames": {"max": 25000, "steady_tolerance": 0},
        "output": {"series_every": 5000},
        "models": [{"name": "pbd-a", "model": "pbd"}, {"name": "pbd-b", "model": "pbd"}],
    }
    experiment = {"name": "interrupted-sweep", "scenarios": [{"file": "long.json"}],
                  "sweep": {"factors": [{"key": "models.*.parameters.iterations", "label": "it",
                                         "values": [4, 5, 6, 7]}]}}
    write_json(os.path.join(folder, "long.json"), scenario)
    path = os.path.join(folder, "sweep.json")
    write_json(path, experiment)
    return path


def distributed_experiment(folder):
    """The distributed FEM, P1 and P2, on a cube at three loads: six case folders."""
    scenario = {
        "name": "dist",
        "mesh": {"type": "cube", "nx": 6, "ny": 6, "nz": 6, "fine_tetgen": {"max_volume": 5e-07},
                 "coarse_selection": {"target_nodes": 40}},
        "support": {"min": [-1, -1, -1e-09], "max": [1, 1, 1e-09]},
        "load": {"point": [0, 0, 0.1], "force": [0, 0, 0.2], "disc_radius": 0.02},
        "frames": {"max": 20, "static": 4},
        "models": [{"name": "fem-p1", "model": "fem_distributed", "parameters": {"cg_tolerance": 1e-12}},
                   {"name": "fem-p2", "model": "fem_distributed", "parameters": {"degree": 2,
                                                                                "cg_tolerance": 1e-12}}],
    }
    # Eight loads (sixteen case folders): the ranks of a signalled mpirun take a
    # moment to end, in which three loads' cases could all be written.
    forces = [[0, 0, 0.05 * (k + 1)] for k in range(8)]
    experiment = {"name": "interrupted-mpi", "scenarios": [{"file": "dist.json"}],
                  "sweep": {"factors": [{"key": "load.force", "label": "f", "values": forces,
                                         "value_names": [chr(ord("a") + k) for k in range(8)]}]}}
    write_json(os.path.join(folder, "dist.json"), scenario)
    path = os.path.join(folder, "mpi.json")
    write_json(path, experiment)
    return path


def study_experiment(folder):
    """A small reference-convergence study (scripts/reference_convergence's input):
    two point-pull scenarios x two distributed-FEM cases."""
    paths = []
    for level, nx in ((0, 4), (1, 5)):
        scenario = {
            "name": f"study-{level}",
            "mesh": {"type": "cube", "nx": nx, "ny": nx, "nz": nx, "fine_tetgen": {"max_volume": 1e-06},
                     "coarse_selection": {"target_nodes": 30}},
            "support": {"min": [-1, -1, -1e-09], "max": [1, 1, 1e-09]},
            "load": {"point": [0, 0, 0.1], "force": [0, 0, 1.0]},
            "frames": {"max": 20, "static": 4},
            "models": [{"name": "fem-p1", "model": "fem_distributed", "parameters": {"cg_tolerance": 1e-10}},
                       {"name": "fem-p2", "model": "fem_distributed",
                        "parameters": {"degree": 2, "cg_tolerance": 1e-10}}],
        }
        write_json(os.path.join(folder, f"study-{level}.json"), scenario)
        paths.append(f"study-{level}.json")
    path = os.path.join(folder, "study.json")
    write_json(path, {"name": "interrupted-study", "scenarios": paths})
    return path


def write_json(path, j):
    with open(path, "w") as f:
        json.dump(j, f, indent=1)


def dead_pid():
    """The pid of a process that has exited (a killed run's, for planted leftovers)."""
    p = subprocess.Popen(["true"])
    p.wait()
    return p.pid


def case_folders(exp_dir):
    """{scenario/case: path} of the folders holding run.json, staging folders left out."""
    out = {}
    if not os.path.isdir(exp_dir):
        return out
    for scenario in sorted(os.listdir(exp_dir)):
        sdir = os.path.join(exp_dir, scenario)
        if not os.path.isdir(sdir):
            continue
        for case in sorted(os.listdir(sdir)):
            if case != "mesh" and not STAGING.search(case) and os.path.isfile(os.path.join(sdir, case, "run.json")):
                out[f"{scenario}/{case}"] = os.path.join(sdir, case)
    return out


def file_summary(path):
    """What a whole file looks like: JSON parses, XML parses, CSV line count."""
    with open(path, "rb") as f:
        data = f.read()
    if path.endswith(".json"):
        json.loads(data)
        return "json"
    if path.endswith(".vtu") or path.endswith(".pvd"):
        ET.fromstring(data)
        return f"xml, {len(data)} bytes" if path.endswith(".vtu") and "series" not in path else "xml"
    if path.endswith(".csv"):
        lines = data.count(b"\n")
        return f"csv {lines} lines" if data.endswith(b"\n") else "csv without its last newline"
    if path.endswith(".obj"):
        return f"obj {data.count(b'v ')} vertex lines"
    return f"{len(data) > 0}"


def folder_summary(folder):
    """{relative file: summary} of a folder, or the error a file gave."""
    out = {}
    for root, _, files in os.walk(folder):
        for name in files:
            path = os.path.join(root, name)
            rel = os.path.relpath(path, folder)
            try:
                out[rel] = file_summary(path)
            except Exception as e:  # noqa: BLE001 (any parse error is what is reported)
                out[rel] = f"broken ({type(e).__name__})"
    return out


def snapshot(exp_dir):
    """Every folder the run writes (case folders, the scenario's mesh folder, any
    folder without run.json that is not a staging folder) with its files."""
    folders = {}
    if not os.path.isdir(exp_dir):
        return folders
    for scenario in sorted(os.listdir(exp_dir)):
        sdir = os.path.join(exp_dir, scenario)
        if not os.path.isdir(sdir):
            continue
        for entry in sorted(os.listdir(sdir)):
            path = os.path.join(sdir, entry)
            if os.path.isdir(path) and not STAGING.search(entry):
                folders[f"{scenario}/{entry}"] = folder_summary(path)
    return folders


def wait_for(predicate, timeout, what):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if predicate():
            return True
        time.sleep(0.05)
    fail(f"timed out after {timeout} s waiting for {what}")
    return False


def descendants(pid):
    """The pids of pid's children, grandchildren ... (from /proc). OpenMPI starts each
    rank in a process group of its own: a group signal would miss them."""
    parent = {}
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/stat") as f:
                    stat = f.read()
                parent[int(entry)] = int(stat.rsplit(")", 1)[1].split()[1])
            except (OSError, IndexError, ValueError):
                pass
    out, frontier = [], [pid]
    while frontier:
        p = frontier.pop()
        children = [c for c, pp in parent.items() if pp == p]
        out += children
        frontier += children
    return out


def alive(pid):
    """pid runs (a zombie does not: it has ended, its parent has not reaped it)."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def wait_for_processes(pids, timeout):
    """Waits until none of pids runs; kills what is left after timeout and returns it."""
    end = time.monotonic() + timeout
    while time.monotonic() < end and any(alive(p) for p in pids):
        time.sleep(0.05)
    left = [p for p in pids if alive(p)]
    for p in left:
        try:
            os.kill(p, signal.SIGKILL)
        except ProcessLookupError:
            pass
    return left


def run_to_completion(cmd, log, timeout=600, env=None):
    with open(log, "w") as err:
        r = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=err, timeout=timeout, start_new_session=True,
                           env=env)
    if r.returncode != 0:
        with open(log) as f:
            fail(f"{' '.join(cmd)}: exit status {r.returncode}: {f.read()[-2000:]}")
    return r.returncode == 0


def check_complete(label, interrupted, finished):
    """Every folder of the interrupted run is absent or the finished run's, file by file."""
    for name, files in interrupted.items():
        if name not in finished:
            fail(f"{label}: {name} is neither a case nor the mesh folder of the finished run")
            continue
        if files != finished[name]:
            missing = sorted(set(finished[name]) - set(files))
            differ = sorted(f for f in files if files[f] != finished[name].get(f))
            fail(f"{label}: {name} left incomplete: missing {missing}, differing {differ} "
                 f"({ {f: files[f] for f in differ} })")


def plant_leftovers(exp_dir):
    """Staging folders of a process that no longer exists, beside a case folder and
    the mesh folder, as a kill between the last write and the rename leaves them."""
    pid = dead_pid()
    planted = []
    for name in sorted(case_folders(exp_dir))[:1]:
        scenario, case = name.split("/")
        for tag in (".tmp", ".old"):
            d = os.path.join(exp_dir, scenario, f"{case}{tag}{pid}")
            os.makedirs(d, exist_ok=True)
            write_json(os.path.join(d, "run.json"), {"case": case})
            planted.append(d)
        d = os.path.join(exp_dir, scenario, f"mesh.tmp{pid}")
        os.makedirs(d, exist_ok=True)
        write_json(os.path.join(d, "summary.json"), {})
        planted.append(d)
    return planted


def selected(label):
    """TB_INTERRUPTED_ONLY=REGEX runs only the matching checks (e.g. "mpirun.*SIGKILL")."""
    return re.search(os.environ.get("TB_INTERRUPTED_ONLY", ""), label) is not None


def interrupt_and_rerun(label, cmd, out, exp_name, expected_cases, sig, extra_delay, env=None, group=False,
                        exp_dir=None):
    """Starts cmd, signals it once a case folder exists (+ extra_delay), checks, reruns.
    group: the signal goes to cmd's process group, as a terminal's Ctrl-C does."""
    if not selected(label):
        return
    exp_dir = exp_dir or os.path.join(out, exp_name)
    os.makedirs(out, exist_ok=True)
    log = os.path.join(out, re.sub(r"\W+", "-", label) + ".log")
    with open(log, "w") as err:
        p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=err, start_new_session=True, env=env)
    started = time.monotonic()
    ok = wait_for(lambda: case_folders(exp_dir) or p.poll() is not None, 300, f"{label}: a first case folder")
    if p.poll() is not None:
        fail(f"{label}: the run ended (status {p.returncode}) before it could be interrupted")
        return
    if not ok:
        os.killpg(p.pid, signal.SIGKILL)
        p.wait()
        return
    time.sleep(extra_delay)
    written_before = len(case_folders(exp_dir))
    children = descendants(p.pid)
    if group:
        os.killpg(p.pid, sig)
    else:
        p.send_signal(sig)
    try:
        p.wait(timeout=120)
    except subprocess.TimeoutExpired:
        fail(f"{label}: still running 120 s after the signal")
        os.killpg(p.pid, signal.SIGKILL)
        p.wait()
    # Under mpirun the ranks are mpirun's children: they must end too, not go on
    # writing (or wait in MPI_Finalize) once mpirun is gone. (A study script's
    # mpirun, its shell killed, finishes its one case: bounded too.)
    left = wait_for_processes(children, 60)
    if left:
        fail(f"{label}: {len(left)} process(es) of the run still running 60 s after the signal")
    state = snapshot(exp_dir)
    cases = case_folders(exp_dir)
    print(f"{label}: signalled after {time.monotonic() - started:.1f} s with {written_before} case folder(s); "
          f"after exit {len(cases)} of {len(expected_cases)}; exit status {p.returncode}", flush=True)
    if len(cases) >= len(expected_cases):
        fail(f"{label}: every case was written: the signal did not land mid-run")
    planted = plant_leftovers(exp_dir)
    if not run_to_completion(cmd, log + ".rerun", env=env):
        return
    finished = snapshot(exp_dir)
    check_complete(label, state, finished)
    if sorted(case_folders(exp_dir)) != sorted(expected_cases):
        fail(f"{label}: after the rerun the cases are {sorted(case_folders(exp_dir))}")
    listed = results_index.Experiment(exp_dir).scenarios
    found = sorted(f"{s}/{c}" for s in listed for c in listed[s])
    if found != sorted(expected_cases):
        fail(f"{label}: results_index lists {found}")
    for root, dirs, _ in os.walk(exp_dir):
        for d in dirs:
            if STAGING.search(d):
                fail(f"{label}: left after the rerun: {os.path.join(root, d)}"
                     + (" (planted)" if os.path.join(root, d) in planted else ""))


def mesh_command(label, out, sig, delay):
    """`tissuebench mesh --out DIR` over a previous, coarser mesh folder, signalled
    twice: after delay s (while it meshes), and once it writes (its staging folder
    DIR.tmp<pid> exists, or a file of DIR is newer than the start). DIR must be the
    previous folder or the new one, whole, never a mix; a rerun writes the new one and
    removes a dead process's staging folder."""
    if not selected(label):
        return
    label_file = re.sub(r"\W+", "-", label)
    target = os.path.join(out, f"{label_file}-mesh")
    reference = os.path.join(out, f"{label_file}-reference")
    cmd = [CLI, "mesh", "--cube", "--refine-levels", "1", "--out", target]
    if not (run_to_completion(cmd[:-1] + [reference], os.path.join(out, f"{label_file}-reference.log"))
            and run_to_completion([CLI, "mesh", "--cube", "--out", target], os.path.join(out, f"{label_file}-first.log"))):
        return
    new, old = folder_summary(reference), folder_summary(target)
    if new == old:
        fail(f"{label}: the two meshes are alike: a mix of them could not be seen")
    parent = os.path.dirname(target)
    staging = re.compile(re.escape(os.path.basename(target)) + r"\.tmp\d+$")

    def writing(since):
        if any(staging.match(n) for n in os.listdir(parent)):
            return True
        return any(os.stat(os.path.join(target, n)).st_mtime_ns > since for n in os.listdir(target))

    for when in (f"{delay:.2f} s in", "once it writes"):
        since = time.time_ns()
        with open(os.devnull, "w") as null:
            p = subprocess.Popen(cmd, stdout=null, stderr=null, start_new_session=True)
        if when == "once it writes":
            wait_for(lambda: p.poll() is not None or writing(since), 300, f"{label}: the mesh command's writes")
        else:
            time.sleep(delay)
        p.send_signal(sig)
        p.wait(timeout=120)
        print(f"{label}, signalled {when}: exit status {p.returncode}", flush=True)
        after = folder_summary(target) if os.path.isdir(target) else None
        if after not in (old, new):
            fail(f"{label}, signalled {when}: the mesh folder is neither the previous one nor the new one: {after}")
        if after == new:  # the next interruption again over the previous mesh
            run_to_completion([CLI, "mesh", "--cube", "--out", target], os.path.join(out, f"{label_file}-first.log"))
    pid = dead_pid()
    os.makedirs(f"{target}.tmp{pid}")
    if run_to_completion(cmd, os.path.join(out, f"{label_file}-rerun.log")):
        if folder_summary(target) != new:
            fail(f"{label}: the rerun's mesh folder differs: {folder_summary(target)}")
        left = [n for n in os.listdir(parent) if staging.match(n)]
        if left:
            fail(f"{label}: left after the rerun: {left}")


def main():
    start = time.monotonic()
    with tempfile.TemporaryDirectory(prefix="tb-interrupted-") as tmp:
        sweep = sweep_experiment(tmp)
        dist = distributed_experiment(tmp)
        # The cases each experiment expands to, from the index the runner writes.
        index_cmd = [CLI, "run", sweep, "--out", os.path.join(tmp, "index"), "--index-only", "--quiet"]
        subprocess.run(index_cmd, check=True, stderr=subprocess.DEVNULL, stdout=subprocess.DEVNULL)
        with open(os.path.join(tmp, "index", "interrupted-sweep", "experiment.json")) as f:
            sweep_cases = [f"{s['name']}/{c}" for s in json.load(f)["scenarios"] for c in s["cases"]]
        index_cmd = [CLI, "run", dist, "--out", os.path.join(tmp, "index"), "--index-only", "--quiet"]
        subprocess.run(index_cmd, check=True, stderr=subprocess.DEVNULL, stdout=subprocess.DEVNULL)
        with open(os.path.join(tmp, "index", "interrupted-mpi", "experiment.json")) as f:
            dist_cases = [f"{s['name']}/{c}" for s in json.load(f)["scenarios"] for c in s["cases"]]
        study = study_experiment(tmp)
        study_cases = [f"study-{level}/fem-p{d}" for level in (0, 1) for d in (1, 2)]
        for k, (name, sig) in enumerate(SIGNALS):
            delay = [0.0, 0.15, 0.4][k]  # a few moments into the next case
            out = os.path.join(tmp, f"sweep-{name}")
            interrupt_and_rerun(f"sweep {name}", [CLI, "run", sweep, "--out", out, "--quiet", "--no-mesh-cache"],
                                out, "interrupted-sweep", sweep_cases, sig, delay)
            out = os.path.join(tmp, f"mpi-{name}")
            interrupt_and_rerun(f"mpirun -n 2 {name}",
                                [MPIEXEC, "-n", "2", CLI, "run", dist, "--out", out, "--quiet", "--no-mesh-cache"],
                                out, "interrupted-mpi", dist_cases, sig, delay)
            mesh_command(f"mesh {name}", tmp, sig, 0.3 + delay)
            # The reference-convergence script: one mpirun per case, a case skipped
            # when its folder is there. Ctrl-C reaches the whole process group; a
            # kill, the shell alone (its mpirun then finishes the case it runs).
            out = os.path.join(tmp, f"study-{name}")
            env = dict(os.environ, TISSUEBENCH=CLI, EXPERIMENT=study, OUT=out, NO_ANALYSIS="1", RANKS="2",
                       TISSUEBENCH_MESH_CACHE=os.path.join(tmp, f"study-cache-{name}"))
            interrupt_and_rerun(f"reference_convergence {name}",
                                ["bash", os.path.join(SRC, "scripts", "reference_convergence")], out,
                                "interrupted-study", study_cases, sig, delay, env=env, group=sig == signal.SIGINT,
                                exp_dir=os.path.join(out, "np2", "interrupted-study"))
    print(f"interrupted_runs: {len(FAILURES)} failure(s), {time.monotonic() - start:.0f} s")
    return 1 if FAILURES else 0


if __name__ == "__main__":
    sys.exit(main())
