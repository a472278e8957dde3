"""tissuebench from Python: the model registry, scenario and experiment files, and one
case stepped frame by frame, over the same C++ the tissuebench program runs
(docs/python.md).

    import tissuebench
    experiment = tissuebench.load("experiments/scenarios/cube-pull.json")
    run = tissuebench.Run(experiment.scenarios[0], "fem-direct")
    run.run()
    run.displacement          # #V by 3 numpy array, m
    tissuebench.read_results("runs/cube-pull").cases   # a results folder as pandas DataFrames

Importable once built, with PYTHONPATH=<build folder>/python, by /usr/bin/python3.
"""
import os as _os
import warnings as _warnings

# The OpenBLAS kernels the tissuebench program pins (experiments/blas_kernels.h,
# kPinnedBlasCore; docs/determinism.md): OpenBLAS reads OPENBLAS_CORETYPE once, when it
# is loaded, and the program re-executes itself to set it. A module cannot: it is set
# here before the C++ core (which links OpenBLAS) is loaded, on a CPU with AVX2 and FMA,
# unless the user chose already. Where numpy or scipy loaded OpenBLAS first, it is too
# late: the warning below says so.
_PINNED_BLAS_CORE = "Haswell"


def _cpu_has_avx2_and_fma():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("flags"):
                    flags = line.split(":", 1)[1].split()
                    return "avx2" in flags and "fma" in flags
    except OSError:
        pass
    return False


if "OPENBLAS_CORETYPE" not in _os.environ and _cpu_has_avx2_and_fma():
    _os.environ["OPENBLAS_CORETYPE"] = _PINNED_BLAS_CORE

from ._tissuebench import Error, Experiment, Run, Scenario, blas_core, load, models  # noqa: E402
from .results import Results, read_results  # noqa: E402  (pandas is imported by read_results only)

if _os.environ.get("OPENBLAS_CORETYPE") == _PINNED_BLAS_CORE and blas_core() != _PINNED_BLAS_CORE:
    _warnings.warn(
        f"tissuebench: OpenBLAS was loaded before tissuebench (by numpy or scipy?) with its {blas_core()} kernels, "
        f"not {_PINNED_BLAS_CORE}: FEM fields may differ from the tissuebench program's in their last bits "
        "(docs/determinism.md). Import tissuebench first, or set OPENBLAS_CORETYPE before starting Python.",
        stacklevel=2)

__all__ = ["Error", "Experiment", "Results", "Run", "Scenario", "blas_core", "load", "models", "read_results"]
