"""Files and messages that hold up (issue 19, part 4): every file gets the user's umask
permissions through one atomic write; hints name only commands, options and extras that
exist; a long eigensolve is announced before it starts.
"""

from __future__ import annotations

import argparse
import ast
import os
import re
import stat
import warnings
from pathlib import Path

import numpy as np
import pytest
from conftest import REPO, write_off

import cshape
from cshape import shapes
from cshape.batch import DescriptorTable, describe
from cshape.cli import main
from cshape.cli.registry import build_parser

PACKAGE = REPO / "cshape"


def _pyproject() -> dict:
    tomllib = pytest.importorskip("tomllib")  # Python >= 3.11
    return tomllib.loads((REPO / "pyproject.toml").read_text())


# ------------------------------------------------------------------ permissions
@pytest.mark.parametrize("mask", [0o022, 0o077, 0o027])
def test_every_file_gets_the_umask_permissions(tmp_path, mask):
    old = os.umask(mask)
    try:
        write_off(tmp_path / "in" / "ring.off", shapes.torus(12, 6))
        table = describe([tmp_path / "in" / "ring.off", ("ball", "", shapes.icosphere(1))],
                         N=8, cache_dir=tmp_path / "cache", progress=False)
        out = tmp_path / "out"
        out.mkdir()
        table.save(out / "t.npz")
        table.save(out / "t.csv")
        assert main(["lessons", str(tmp_path / "course")]) == 0
    finally:
        os.umask(old)
    files = [p for p in tmp_path.rglob("*") if p.is_file() and "in" not in p.parts]
    kinds = {p.suffix for p in files}
    assert {".npz", ".csv", ".json", ".key", ".ipynb", ".py", ".md"} <= kinds, kinds
    wrong = {str(p.relative_to(tmp_path)): oct(stat.S_IMODE(p.stat().st_mode))
             for p in files if stat.S_IMODE(p.stat().st_mode) != 0o666 & ~mask}
    assert not wrong
    folders = [p for p in (tmp_path / "course").rglob("*") if p.is_dir()] + [tmp_path / "course"]
    assert all(stat.S_IMODE(p.stat().st_mode) == 0o777 & ~mask for p in folders)


#: Writers that bypass cshape._files.atomic_write on purpose: (module, call).
_ALLOWED_WRITERS = {
    ("_files.py", "mkstemp"),  # the helper itself
    ("readers.py", "open"),  # a .gz mesh decompressed into a private temporary folder
    ("assignments.py", "mkdtemp"),  # chmod'ed to the umask before it is renamed into place
    ("download.py", "mkdtemp"),  # an archive unpacked there; its members are moved out
    ("widgets.py", "savefig"),  # into an in-memory buffer
    ("store.py", "open"),  # an empty lock file beside a cache file while it is built
}


def _writer_calls(path: Path):
    """(call name, line) of every call in ``path`` that writes a file."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for node in ast.walk(tree):
        if not isinstance(node, ast.Call):
            continue
        f = node.func
        name = f.attr if isinstance(f, ast.Attribute) else getattr(f, "id", "")
        first = node.args[0] if node.args else None
        to_object = isinstance(first, ast.Name) and first.id in ("f", "fh", "buf")
        if name in ("write_text", "write_bytes", "mkstemp", "mkdtemp", "NamedTemporaryFile",
                    "copy2", "to_csv", "write_html", "write_image"):
            yield name, node.lineno
        elif name in ("savez", "savez_compressed", "save", "savefig") and not to_object \
                and (name != "save" or isinstance(f, ast.Attribute)
                     and getattr(f.value, "id", "") == "np"):
            yield name, node.lineno
        elif name == "open" and any(
                isinstance(a, ast.Constant) and isinstance(a.value, str)
                and set(a.value) & set("wax") for a in node.args[1:2]):
            yield name, node.lineno
        elif name == "write" and isinstance(f, ast.Attribute) \
                and getattr(f.value, "id", "") == "nbformat" and len(node.args) > 1 \
                and not (isinstance(node.args[1], ast.Name) and node.args[1].id == "f"):
            yield name, node.lineno
        elif name == "copytree" and not any(k.arg == "copy_function" for k in node.keywords):
            yield name, node.lineno


def test_files_are_written_through_the_one_atomic_write():
    found = {(p.name, name, line) for p in PACKAGE.rglob("*.py")
             for name, line in _writer_calls(p)}
    stray = sorted(x for x in found if x[:2] not in _ALLOWED_WRITERS)
    assert not stray, f"write these through cshape._files.atomic_write: {stray}"


# ------------------------------------------------------------------ hints
def _subparsers(parser: argparse.ArgumentParser) -> dict:
    acts = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    return dict(acts[0].choices) if acts else {}


def _messages():
    """(file, line, text) of every string constant of the package (f-string parts too)."""
    for p in PACKAGE.rglob("*.py"):
        for node in ast.walk(ast.parse(p.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Constant) and isinstance(node.value, str):
                yield p.name, node.lineno, node.value


def test_backticked_commands_and_their_options_exist():
    commands = _subparsers(build_parser())
    checked = 0
    for fname, line, text in _messages():
        for cmd in re.findall(r"`(?:python -m )?cshape ([^`]+)`", text):
            words = cmd.split()
            if words[0].startswith("<") or words[0] == "--help":
                continue  # 'cshape <command>: error: ...' describes the format
            where = f"{fname}:{line}: `cshape {cmd}`"
            assert words[0] in commands, f"{where}: no command {words[0]!r}"
            parser = commands[words[0]]
            nested = _subparsers(parser)
            if nested and len(words) > 1 and not words[1].startswith(("{", "-")):
                assert words[1] in nested, f"{where}: no command {words[0]} {words[1]!r}"
                parser = nested[words[1]]
            for opt in (w.split("=")[0] for w in words[1:]):
                if re.fullmatch(r"-{1,2}[A-Za-z][\w-]*", opt):
                    assert opt in parser._option_string_actions, f"{where}: no option {opt}"
            checked += 1
    assert checked > 20


#: Words that follow "cshape " in messages without being a command.
_PROSE = {"descriptor", "reads", "needs", "cannot"}


def test_messages_name_only_commands_that_exist():
    """Error and warning messages: every 'cshape WORD' is a command ('cshape subdivision'
    was not)."""
    commands = set(_subparsers(build_parser()))
    bad = []
    for p in PACKAGE.rglob("*.py"):
        for node in ast.walk(ast.parse(p.read_text(encoding="utf-8"))):
            parts = []
            if isinstance(node, ast.Raise) and node.exc is not None:
                parts = [node.exc]
            elif isinstance(node, ast.Call) and getattr(
                    node.func, "attr", getattr(node.func, "id", "")) in (
                    "warn", "print", "CommandError"):
                parts = node.args
            for part in parts:
                for c in ast.walk(part):
                    if isinstance(c, ast.Constant) and isinstance(c.value, str):
                        for w in re.findall(r"(?<![\w.\-/\[])cshape ([a-z][a-z_\-]*)",
                                            c.value):
                            if w not in commands and w not in _PROSE:
                                bad.append((p.name, c.lineno, w))
    assert not bad, bad


def test_extras_named_in_hints_exist():
    extras = set(_pyproject()["project"]["optional-dependencies"])
    named = {(f, line, x) for f, line, text in _messages()
             for x in re.findall(r"cshape\[([a-z,]+)\]", text)}
    assert named
    for f, line, x in named:
        assert set(x.split(",")) <= extras, f"{f}:{line}: no extra {x!r}"


def test_lessons_names_the_extra_when_nbgrader_is_missing(tmp_path, capsys, monkeypatch):
    import cshape.cli.course as course

    real = course._installed
    monkeypatch.setattr(course, "_installed", lambda m: m != "nbgrader" and real(m))
    assert main(["lessons", str(tmp_path / "c")]) == 0
    out = capsys.readouterr().out
    assert 'nbgrader, which is not installed: pip install "cshape[course]"' in out
    monkeypatch.setattr(course, "_installed", lambda m: False)
    assert main(["lessons", str(tmp_path / "d")]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1
    assert 'pip install "cshape[notebooks]"' in err and not (tmp_path / "d").exists()


def test_license_file_and_pyproject():
    text = (REPO / "LICENSE").read_text()
    assert text.startswith("BSD 3-Clause License") and "2026, cshape developers" in text
    project = _pyproject()["project"]
    assert project["license"] == "BSD-3-Clause" and project["license-files"] == ["LICENSE"]


# ------------------------------------------------------------------ long runs
def test_estimate_of_the_eigensolve_time():
    est = cshape.spectrum.estimate_seconds
    # the run: N = 2000 on 11.5K vertices took 396 s
    assert 200 < est(11520, 2000) < 800
    assert est(11520, 100) < 5  # the default N: seconds
    assert est(11520, 400) == pytest.approx(16 * est(11520, 100), rel=0.2)  # ~ N^2
    assert est(2562, 900) == pytest.approx(1e-9 * 2562**3, rel=0.01)  # dense: ~ n^3
    from cshape.spectrum import long_solve_message

    msg = long_solve_message(11520, 2000)
    assert msg.startswith("N=2000 eigenvalues of a mesh of 11520 vertices: the eigensolve "
                          "will take about 8 min") and msg.endswith("N=400 would take about 19 s")
    assert long_solve_message(11520, 100) is None


def test_shape_dna_warns_before_a_long_solve(monkeypatch):
    import cshape.spectrum as spectrum

    calls = []
    real = spectrum.solve_eigenproblem

    def solve(*a, **k):
        calls.append("solve")
        return real(*a, **k)

    monkeypatch.setattr(spectrum, "estimate_seconds", lambda n, N: 3600.0 * N / 10)
    monkeypatch.setattr(spectrum, "solve_eigenproblem", solve)

    def warned(message, *a, **k):
        calls.append("warn: " + str(message))

    monkeypatch.setattr(spectrum.warnings, "warn", warned)
    spectrum.shape_dna(shapes.icosphere(1), N=10)
    assert calls[0].startswith("warn: N=10 eigenvalues of a mesh of 42 vertices: the "
                               "eigensolve will take about 60 min") and calls[1] == "solve"


def test_describe_command_announces_a_long_run_at_once(tmp_path, capsys, monkeypatch):
    import cshape.batch.run as run

    write_off(tmp_path / "m" / "ball.off", shapes.icosphere(2))
    monkeypatch.setattr(run, "estimate_seconds", lambda n, N: 600.0)
    monkeypatch.setattr(run, "long_solve_message",
                        lambda n, N: f"N={N} eigenvalues of a mesh of {n} vertices: about 10 min")
    monkeypatch.setattr(run, "_ESTIMATE_MIN_N", 5)
    order = []
    real_work = run._work
    monkeypatch.setattr(run, "_work", lambda t: (order.append(capsys.readouterr().err),
                                                 real_work(t))[1])
    assert main(["describe", str(tmp_path / "m"), "-N", "6", "--no-cache",
                 "-q"]) == 0
    assert "cshape describe: warning: long run ahead: 1 eigensolve of N=6, about 10 min" \
        in order[0]  # printed before the eigensolve started
    assert "ball (162 vertices), about 10 min" in order[0]
    assert "long run ahead" not in capsys.readouterr().err  # once, not again at the end


def test_no_estimate_for_small_n(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        t = describe([("ball", "", shapes.icosphere(1))], N=8, cache_dir=False,
                     progress=False)
    assert isinstance(t, DescriptorTable) and np.all(np.isfinite(t.lam))
