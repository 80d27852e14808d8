"""Helpers shared by the benchmark scripts: machine summary, load, peak memory, differences."""

from __future__ import annotations

import datetime
import importlib
import os
import platform

import numpy as np

__all__ = [
    "load_average",
    "max_relative_difference",
    "machine_summary",
    "proc_status_kib",
    "processor",
    "relative_difference",
    "reset_peak",
    "run_child",
    "write_section",
]


def load_average():
    """The 1, 5 and 15 minute load averages (NaN where unavailable)."""
    try:
        return os.getloadavg()
    except OSError:  # pragma: no cover
        return (float("nan"),) * 3


def cpu_summary():
    """The processor as Linux reports it: model, clock, L2 / L3 per core, widest vector unit.

    Ratios against LaPy moved by up to 1.7x between the virtual machines measured
    (``SCALE.md``, "Machines"): runs are comparable only on one processor.
    ``''`` where ``/proc/cpuinfo`` does not exist.
    """
    try:
        with open("/proc/cpuinfo") as fh:
            info = fh.read()
    except OSError:  # pragma: no cover - not Linux
        return ""
    fields = {}
    for line in info.splitlines():
        key, _, value = line.partition(":")
        fields.setdefault(key.strip(), value.strip())
    caches = _caches()
    flags = set(fields.get("flags", "").split())
    simd = next((f for f in ("avx512f", "avx2", "avx", "sse4_2") if f in flags), "")
    mhz = fields.get("cpu MHz", "")
    parts = [fields.get("model name", "")] + ([f"{float(mhz):.0f} MHz"] if mhz else [])
    return ", ".join(p for p in parts + caches + [simd] if p)


def _caches():
    """The sizes of the L2 and L3 caches of CPU 0, e.g. ``['L2 2048K', 'L3 491520K']``."""
    caches = []
    for index, name in (("index2", "L2"), ("index3", "L3")):
        try:
            with open(f"/sys/devices/system/cpu/cpu0/cache/{index}/size") as fh:
                caches.append(f"{name} {fh.read().strip()}")
        except OSError:
            pass
    return caches


def processor():
    """The processor named for a table: model, cores, vector units, caches and the load.

    For example ``'Intel(R) Xeon(R) Processor, 2 cores, AVX2 AVX-512 AMX, L2 2048K, L3
    491520K; load average 0.31 0.09 0.35'``.  Tables of different processors are not
    comparable (``SCALE.md``, "Machines").
    """
    fields, flags = {}, set()
    try:
        with open("/proc/cpuinfo") as fh:
            for line in fh:
                key, _, value = line.partition(":")
                fields.setdefault(key.strip(), value.strip())
        flags = set(fields.get("flags", "").split())
    except OSError:  # pragma: no cover - not Linux
        pass
    units = [name for flag, name in (("avx2", "AVX2"), ("avx512f", "AVX-512"),
                                     ("amx_tile", "AMX")) if flag in flags]
    caches = _caches()
    la = load_average()
    parts = [fields.get("model name", "?"), f"{os.cpu_count()} cores", " ".join(units)]
    return (", ".join(p for p in parts + caches if p)
            + f"; load average {la[0]:.2f} {la[1]:.2f} {la[2]:.2f}")


def machine_summary(libs=("scipy",)):
    """One line: date, machine, processor, memory, versions of numpy, ``libs`` and cshape,
    and the load."""
    import cshape

    try:
        mem = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") / 2**30
    except (ValueError, OSError):  # pragma: no cover
        mem = float("nan")
    versions = [f"numpy {np.__version__}"]
    for name in libs:
        try:
            mod = importlib.import_module(name)
            try:  # the installed distribution (cholespy's __version__ lags behind it)
                from importlib.metadata import version
                versions.append(f"{name} {version(name)}")
            except Exception:
                versions.append(f"{name} {getattr(mod, '__version__', '?')}")
        except ImportError:
            versions.append(f"{name} (not installed)")
    la = load_average()
    return (
        f"{datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC, "
        f"{platform.machine()}, {os.cpu_count()} cores ({cpu_summary() or '?'}), "
        f"{mem:.0f} GiB, "
        f"Python {platform.python_version()}, {', '.join(versions)}, "
        f"cshape {cshape.__version__}; load average {la[0]:.2f} {la[1]:.2f} {la[2]:.2f}"
    )


def proc_status_kib(field):
    """A ``/proc/self/status`` field in KiB (e.g. ``'VmHWM'``, ``'VmRSS'``); NaN elsewhere."""
    try:
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith(field + ":"):
                    return float(line.split()[1])
    except OSError:  # pragma: no cover - not Linux
        pass
    return float("nan")


def reset_peak():
    """Reset the peak resident size (``VmHWM``) of this process; False where unsupported."""
    try:
        with open("/proc/self/clear_refs", "w") as fh:
            fh.write("5")
        return True
    except OSError:  # pragma: no cover - not Linux or too old
        return False


def relative_difference(lam, ref):
    """``|lam - ref| / |ref|`` elementwise, with ``max |ref|`` as the scale of zeros."""
    lam = np.asarray(lam, dtype=float)
    ref = np.asarray(ref, dtype=float)
    big = float(np.abs(ref).max())
    scale = np.where(np.abs(ref) > 1e-9 * big, np.abs(ref), big)
    return np.abs(lam - ref) / scale


def max_relative_difference(lam, ref):
    """The largest entry of :func:`relative_difference`, a float."""
    return float(relative_difference(lam, ref).max())


def run_child(script, args, *, threads=None, timeout=None):
    """Run ``python script *args`` in a fresh process and return the JSON of its last line.

    Parameters
    ----------
    script : path of the benchmark script (it handles its own ``--child`` mode).
    args : list of str, the arguments after the script.
    threads : int, optional
        BLAS / OpenMP threads of the child (``OMP_NUM_THREADS`` and friends).
    timeout : float, optional
        Seconds before the child is killed.

    Returns
    -------
    dict
        The child's result, or ``{'error': message}`` on a time-out or a non-zero exit.
    """
    import json
    import subprocess
    import sys

    env = dict(os.environ)
    if threads:
        for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
            env[var] = str(threads)
    cmd = [sys.executable, str(script), *map(str, args)]
    try:
        out = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env,
                             check=False)
    except subprocess.TimeoutExpired:
        return {"error": f"timed out after {timeout:.0f} s"}
    if out.returncode != 0:
        tail = (out.stderr.strip().splitlines() or ["?"])[-1]
        return {"error": f"exit {out.returncode}: {tail}"}
    return json.loads(out.stdout.strip().splitlines()[-1])


def write_section(path, key, lines, title):
    """Write ``lines`` as the section ``key`` of the Markdown result file ``path``.

    A script's one result file holds one section per kind of run (for example the size sweep
    and the real meshes); a run replaces its own section and keeps the others.  A section
    runs from ``<!-- section: key -->`` to ``<!-- end of section: key -->``; a new one is
    appended, and a new file starts with ``# title``.
    """
    from pathlib import Path

    path = Path(path)
    start, end = f"<!-- section: {key} -->", f"<!-- end of section: {key} -->"
    block = "\n".join([start, *lines, end])
    text = path.read_text() if path.exists() else f"# {title}\n"
    i, j = text.find(start), text.find(end)
    if i >= 0 and j > i:
        text = text[:i] + block + text[j + len(end):]
    else:
        text = text.rstrip("\n") + "\n\n" + block + "\n"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    return path
