"""Finds the raw results of an experiment: results/<experiment>/<scenario>/<case>/."""
import json
import os


def load_case(folder):
    """run.json and timings.json of one case folder, with its path."""
    with open(os.path.join(folder, "run.json")) as f:
        run = json.load(f)
    with open(os.path.join(folder, "timings.json")) as f:
        timings = json.load(f)
    return {"folder": folder, "run": run, "timings": timings}


def load_experiment(root):
    """{scenario: {case: case}} for every case folder holding a run.json."""
    out = {}
    if not os.path.isdir(root):
        raise FileNotFoundError(f"{root}: no such results folder (run tissuebench first)")
    for scenario in sorted(os.listdir(root)):
        sdir = os.path.join(root, scenario)
        if not os.path.isdir(sdir):
            continue
        for case in sorted(os.listdir(sdir)):
            cdir = os.path.join(sdir, case)
            if os.path.isfile(os.path.join(cdir, "run.json")):
                out.setdefault(scenario, {})[case] = load_case(cdir)
    return out
