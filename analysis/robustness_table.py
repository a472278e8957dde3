"""results/tables/robustness.md from the reports of scripts/fuzz_libfuzzer.

Per reader: the inputs the deterministic mutator ran (tb_fuzz, CI's seed and count)
and the inputs libFuzzer ran, the crashes, hangs and contract findings of each, the
distinct error messages (numbers and quoted text taken out: message_kind in
tests/fuzz/fuzz_targets.cc) and the slowest input. Then the machine and the commands.

  robustness_table.py WORK OUT.md --mutator-runs N --libfuzzer-seconds S --targets "obj off ..."

WORK is build-fuzz/fuzz: reports/mutator_<t>.json (tb_fuzz --report),
reports/libfuzzer_<t>.json (TB_LIBFUZZER_REPORT, tests/fuzz/libfuzzer_main.cc),
libfuzzer/<t>/log.txt and libfuzzer/<t>/artifacts/ (libFuzzer's own output).
"""
import argparse
import datetime
import json
import os
import platform
import re
import subprocess

# The reader each target runs (docs/robustness.md, "What is fuzzed").
READERS = {
    "obj": "Wavefront OBJ",
    "off": "OFF",
    "stl_ascii": "STL, ASCII",
    "stl_binary": "STL, binary",
    "ply_ascii": "PLY, ASCII",
    "ply_binary": "PLY, binary (both byte orders)",
    "vtu_surface": "VTU triangle surface",
    "gmsh": "Gmsh .msh v1 and v2",
    "tetgen": "TetGen .node + .ele",
    "tetgen_face": "TetGen .face",
    "vtu_volume": "VTU tet volume",
    "scenario": "scenario and experiment JSON",
    "probes_csv": "probe-point CSV",
    "truth_cube_csv": "Truth Cube bead table",
    "submission": "benchmark submission",
}


def load(path):
    if not os.path.isfile(path):
        return None
    with open(path) as f:
        return json.load(f)


def libfuzzer_log(path):
    """(executed units, peak RSS MB, the first error line) from libFuzzer's output."""
    units, rss, error = None, None, None
    if os.path.isfile(path):
        with open(path, errors="replace") as f:
            for line in f:
                m = re.match(r"stat::number_of_executed_units:\s*(\d+)", line)
                if m:
                    units = int(m.group(1))
                m = re.match(r"stat::peak_rss_mb:\s*(\d+)", line)
                if m:
                    rss = int(m.group(1))
                if error is None and ("==ERROR" in line or "FINDING" in line or "runtime error" in line):
                    error = line.strip()
    return units, rss, error


def artifacts(folder):
    """libFuzzer's artifacts by kind: crash, leak, oom, timeout, slow-unit."""
    kinds = {}
    if os.path.isdir(folder):
        for name in os.listdir(folder):
            kind = name.split("-")[0] if not name.startswith("slow-unit") else "slow-unit"
            kinds[kind] = kinds.get(kind, 0) + 1
    return kinds


def command_output(cmd):
    try:
        return subprocess.run(cmd, capture_output=True, text=True, check=False).stdout.strip()
    except OSError:
        return ""


def machine():
    cpu = ""
    if os.path.isfile("/proc/cpuinfo"):
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    clang = command_output(["clang++", "--version"]).splitlines()
    load = os.getloadavg()
    return {"cpu": cpu, "threads": os.cpu_count(), "system": f"{platform.system()} {platform.release()}",
            "clang": clang[0] if clang else "", "load": f"{load[0]:.1f}, {load[1]:.1f}, {load[2]:.1f}",
            "commit": command_output(["git", "rev-parse", "--short=12", "HEAD"]),
            "dirty": bool(command_output(["git", "status", "--porcelain", "--untracked-files=no"])),
            "date": datetime.date.today().isoformat()}


def recorded_machine(work):
    """machine(), with the commit, dirtiness and load that scripts/fuzz_libfuzzer
    recorded when the fuzzing ended (reports/machine.json), when it did."""
    m = machine()
    m.update(load(os.path.join(work, "reports", "machine.json")) or {})
    return m


def row(target, work):
    mut = (load(os.path.join(work, "reports", f"mutator_{target}.json")) or {}).get(target)
    lib = load(os.path.join(work, "reports", f"libfuzzer_{target}.json"))
    units, rss, error = libfuzzer_log(os.path.join(work, "libfuzzer", target, "log.txt"))
    art = artifacts(os.path.join(work, "libfuzzer", target, "artifacts"))
    r = {"target": target, "reader": READERS.get(target, target)}
    r["mutator_inputs"] = mut["inputs"] if mut else None
    r["mutator_findings"] = mut["findings"] if mut else None
    r["mutator_messages"] = mut["distinct_messages"] if mut else None
    r["mutator_slowest_ms"] = mut["slowest_ms"] if mut else None
    # The binary's own count (inputs that returned) and libFuzzer's (executed units).
    r["libfuzzer_inputs"] = units if units is not None else (lib["inputs"] if lib else None)
    r["libfuzzer_messages"] = lib["distinct_messages"] if lib else None
    r["libfuzzer_slowest_ms"] = lib["slowest_ms"] if lib else None
    r["libfuzzer_peak_rss_mb"] = rss
    r["crashes"] = art.get("crash", 0) + art.get("leak", 0) + art.get("oom", 0) + art.get("deadly", 0)
    r["hangs"] = art.get("timeout", 0)
    r["slow_units"] = art.get("slow-unit", 0)
    r["libfuzzer_error"] = error
    kinds = set((mut or {}).get("messages", {})) | set((lib or {}).get("messages", {}))
    r["messages_union"] = len(kinds)
    # The same, each message cut at its first quote: a quoted input holding a quote
    # itself, or bytes above 0x7f the readers print as they are, makes one kind
    # many in the count above (libFuzzer's inputs often do).
    r["messages_before_quote"] = len({k.split("'")[0] for k in kinds})
    return r


def cell(v, fmt="{}"):
    return "(no report)" if v is None else fmt.format(v)


def make(work, out, targets, mutator_runs, seconds):
    rows = [row(t, work) for t in targets]
    m = recorded_machine(work)
    lines = [
        "# Robustness of the readers: fuzzing counts",
        "",
        "Written by `analysis/robustness_table.py` from the reports of `bash scripts/fuzz_libfuzzer`"
        " (docs/robustness.md says what each target runs and what counts as a finding).",
        "",
        f"- deterministic mutator (`tb_fuzz`, as CI's sanitized step): the committed seeds, then {mutator_runs} "
        "mutations of seed 1 per target, each input under a 10 s limit;",
        f"- libFuzzer (`fuzz_<target>`): {seconds} s per target from the committed seeds with the target's "
        "dictionary, `-timeout=10 -rss_limit_mb=4096 -malloc_limit_mb=4096 -report_slow_units=1 -seed=1`;",
        "- both built by clang with `-fsanitize=address,undefined` (libFuzzer's binaries with `-fsanitize=fuzzer`) "
        "at -O1 with assertions; a sanitizer report is a crash.",
        "",
        "A crash counts crash, leak and out-of-memory artifacts; a hang an input beyond 10 s. Distinct error "
        "messages count one-line rejections with numbers and quoted text taken out; \"both\" is the union of the "
        "two drivers' kinds. libFuzzer's kinds are inflated: its inputs put quotes and bytes above 0x7f inside "
        "the text a message quotes, which the count cannot tell from the message, so the next column counts the "
        "kinds cut at their first quote (a lower bound). The slowest input is timed around the target alone, instrumented (ASan, UBSan, "
        "coverage), on the shared machine below: a bound, not the readers' speed.",
        "",
        "| target | reader | mutator inputs | libFuzzer inputs | crashes | hangs | contract findings | "
        "distinct error messages (mutator / libFuzzer / both) | both, cut at the first quote | "
        "slowest input, ms (mutator / libFuzzer) | inputs > 1 s |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        findings = r["mutator_findings"]
        lines.append(
            f"| {r['target']} | {r['reader']} | {cell(r['mutator_inputs'])} | {cell(r['libfuzzer_inputs'])} | "
            f"{r['crashes']} | {r['hangs']} | {cell(findings)} | {cell(r['mutator_messages'])} / "
            f"{cell(r['libfuzzer_messages'])} / {r['messages_union']} | {r['messages_before_quote']} | "
            f"{cell(r['mutator_slowest_ms'], '{:.1f}')} / "
            f"{cell(r['libfuzzer_slowest_ms'], '{:.1f}')} | {r['slow_units']} |")
    total_mut = sum(r["mutator_inputs"] or 0 for r in rows)
    total_lib = sum(r["libfuzzer_inputs"] or 0 for r in rows)
    lines += [
        "",
        f"Total: {total_mut} mutator inputs, {total_lib} libFuzzer inputs, "
        f"{sum(r['crashes'] for r in rows)} crashes, {sum(r['hangs'] for r in rows)} hangs.",
    ]
    errors = [r for r in rows if r["libfuzzer_error"]]
    if errors:
        lines += ["", "libFuzzer's first error line, per target that reported one:", ""]
        lines += [f"- {r['target']}: `{r['libfuzzer_error']}`" for r in errors]
    lines += [
        "",
        "## Machine and commands",
        "",
        f"- {m['cpu']}, {m['threads']} hardware threads, {m['system']}; {m['clang']}",
        f"- commit {m['commit']}{' (with uncommitted changes)' if m['dirty'] else ''}, {m['date']}; "
        f"load average at the end {m['load']} (a shared machine)",
        f"- `FUZZ_SECONDS={seconds} TB_FUZZ_RUNS={mutator_runs} bash scripts/fuzz_libfuzzer`, which runs per target "
        f"`build-fuzz/tests/fuzz/tb_fuzz --corpus tests/fuzz/corpus --target T --runs {mutator_runs}` and "
        f"`build-fuzz/tests/fuzz/fuzz_T -dict=T.dict -max_total_time={seconds} -timeout=10 -rss_limit_mb=4096 "
        "-malloc_limit_mb=4096 -report_slow_units=1 -print_final_stats=1 -seed=1 NEW_CORPUS tests/fuzz/corpus/T`",
        "",
    ]
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    with open(out, "w") as f:
        f.write("\n".join(lines))
    return rows


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("work")
    p.add_argument("out")
    p.add_argument("--mutator-runs", type=int, required=True)
    p.add_argument("--libfuzzer-seconds", type=int, required=True)
    p.add_argument("--targets", default=" ".join(READERS))
    a = p.parse_args()
    make(a.work, a.out, a.targets.split(), a.mutator_runs, a.libfuzzer_seconds)


if __name__ == "__main__":
    main()
