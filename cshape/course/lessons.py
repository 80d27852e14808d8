"""Execute the walkthrough notebooks into an output folder: executed ``.ipynb`` + HTML.

This is the README's main job (``make demo`` runs ``python -m cshape notebooks``)::

    python -m cshape notebooks                    # all notebooks/NN_*.ipynb -> out/notebooks/
    python -m cshape notebooks --small 01 03      # small sizes (CSHAPE_SMALL=1), two notebooks
    python -m cshape notebooks --student          # the student versions, each up to its first stub

Every notebook runs top to bottom on a fresh kernel of **this** Python interpreter (the
kernel is started as ``sys.executable -m ipykernel_launcher``, whatever kernelspecs the user
has installed), with the notebook's folder as working directory.  A cell error stops that
notebook and is reported; the others still run.  ``out/notebooks/index.html`` links the
results.

The HTML pages work offline: equations are typeset by a copy of MathJax 2.7 next to them
(``mathjax/``, from the ``jupyter-server-mathjax`` package, see :func:`offline_mathjax`), and
the kernels draw plotly figures with plotly.js embedded in the page (``PLOTLY_RENDERER`` is
``plotly_mimetype+notebook``: JupyterLab's renderer for the ``.ipynb``, embedded HTML for the
page), so the 3-D viewers of :mod:`cshape.plots.viewer` turn and slide without a network or kernel.
"""

from __future__ import annotations

import html
import os
import re
import shutil
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .._checks import check_int
from .._files import atomic_write

if TYPE_CHECKING:
    from collections.abc import Callable, Iterable

__all__ = [
    "run_notebook",
    "run_notebooks",
]

#: Notebooks are named ``NN_topic.ipynb``.
PATTERN = "[0-9][0-9]_*.ipynb"


@dataclass
class RunResult:
    """Outcome of executing one notebook.

    Attributes
    ----------
    name : str
        File name of the notebook.
    ok : bool
        True when every cell ran (or, with ``stop_at_stub``, when the first error was an
        exercise stub's ``NotImplementedError``).
    seconds : float
        Wall time, kernel start included.
    error : str
        Empty when ``ok``; else the error name and message of the failing cell.
    stopped_at_stub : bool
        Execution stopped at an exercise stub.
    ipynb, html : pathlib.Path or None
        The executed notebook and its HTML rendering (None when not written).
    stderr : list of str
        ``"cell <k>: <text>"`` for every stderr output (a warning box in the lesson) of a
        cell not tagged ``expect-stderr`` (the tag marks a lesson about that warning).
    """

    name: str
    ok: bool
    seconds: float
    error: str = ""
    stopped_at_stub: bool = False
    ipynb: Path | None = None
    html: Path | None = None
    stderr: list = field(default_factory=list)


#: Cell tag of a cell whose stderr output is part of the lesson (e.g. a warning it explains).
EXPECT_STDERR = "expect-stderr"


def stderr_outputs(nb: Any) -> list[str]:
    """The stderr outputs of an executed notebook, outside cells tagged ``expect-stderr``.

    Parameters
    ----------
    nb : nbformat.NotebookNode

    Returns
    -------
    list of str
        ``"cell <k>: <first 300 characters>"``, in cell order.
    """
    found = []
    for k, cell in enumerate(nb.cells):
        if cell.cell_type != "code" or EXPECT_STDERR in cell.get("metadata", {}).get("tags", []):
            continue
        for out in cell.get("outputs", []):
            if out.get("output_type") == "stream" and out.get("name") == "stderr":
                found.append(f"cell {k}: {''.join(out.get('text', ''))[:300]}")
    return found


def default_notebook_dir() -> Path:
    """The lessons: ``notebooks/`` of a source checkout, or the package data
    ``cshape/lessons`` of an installed cshape
    (see :func:`cshape.course.assignments.lessons_dir`)."""
    from .assignments import lessons_dir

    return lessons_dir()


def find_notebooks(src: str | os.PathLike[str] | None = None,
                   names: Iterable[str] | None = None) -> list[Path]:
    """The notebooks ``NN_*.ipynb`` in ``src``, sorted; ``names`` picks some by number or name.

    Parameters
    ----------
    src : str or os.PathLike, optional
        Folder (default :func:`default_notebook_dir`).
    names : sequence of str, optional
        ``'01'``, ``'01_fem_assembly'`` or ``'01_fem_assembly.ipynb'``.

    Returns
    -------
    list of pathlib.Path
    """
    folder = Path(default_notebook_dir() if src is None else src)
    if not folder.is_dir():
        raise FileNotFoundError(
            f"notebook folder {str(folder)!r} does not exist; pass src= (or --src) pointing to "
            "the repository's notebooks/ folder"
        )
    paths = sorted(folder.glob(PATTERN))
    if names:
        chosen = []
        for n in names:
            n = str(n)
            hit = [p for p in paths if p.name == n or p.stem == n or p.name.startswith(f"{n}_")]
            if not hit:
                raise ValueError(
                    f"no notebook {n!r} in {str(folder)!r}; choose from "
                    f"{[p.name for p in paths]}"
                )
            chosen += [p for p in hit if p not in chosen]
        paths = chosen
    return paths


def kernel_manager() -> Any:
    """A Jupyter ``KernelManager`` whose kernel is ``sys.executable -m ipykernel_launcher``.

    The kernel therefore sees exactly the packages of the running interpreter (the project's
    ``.venv``), even when a user-wide ``python3`` kernelspec points elsewhere.
    """
    from jupyter_client.kernelspec import KernelSpec, KernelSpecManager
    from jupyter_client.manager import KernelManager

    class _ThisPython(KernelSpecManager):
        def get_kernel_spec(self, kernel_name: str) -> Any:
            return KernelSpec(
                # log level ERROR: no "running over TCP without encryption" line per
                # notebook (the kernel listens on loopback only); errors still show
                argv=[sys.executable, "-m", "ipykernel_launcher", "-f", "{connection_file}",
                      "--IPKernelApp.log_level=ERROR"],
                display_name="Python 3 (cshape)",
                language="python",
                metadata={"debugger": False},
            )

    return KernelManager(kernel_name="python3", kernel_spec_manager=_ThisPython())


#: Folder of the MathJax copy, next to the HTML pages.
MATHJAX_DIR = "mathjax"
#: MathJax's own configuration files in the copy (jupyter-server-mathjax ships these two) and
#: ours: the HTML-CSS output with the STIX-Web fonts, the only web fonts in the copy, and no
#: fast preview (a first, rough typesetting of every equation, redone by HTML-CSS: a page
#: full of equations is typeset once instead of twice).
_MATHJAX_CONFIG = "TeX-AMS-MML_HTMLorMML-full,Safe,local/cshape"
_MATHJAX_LOCAL = """\
MathJax.Hub.Config({
  "HTML-CSS": {availableFonts: [], preferredFont: null, webFont: "STIX-Web", imageFont: null},
  "fast-preview": {disabled: true},
  MathMenu: {showRenderer: false},
  messageStyle: "none"
});
MathJax.Ajax.loadComplete("[MathJax]/config/local/cshape.js");
"""


def offline_mathjax(out_dir: str | os.PathLike[str]) -> str | None:
    """Copy MathJax 2.7 next to exported HTML pages, so that their equations render offline.

    The files come from the ``jupyter-server-mathjax`` package (the ``notebooks`` extra);
    the copy (about 12 MB) is made once per output folder.

    Parameters
    ----------
    out_dir : str or os.PathLike
        The folder of the HTML pages; the copy goes to ``out_dir/mathjax/``.

    Returns
    -------
    str or None
        The relative URL for nbconvert's ``HTMLExporter.mathjax_url``, or None when
        ``jupyter-server-mathjax`` is not installed (the pages then load MathJax from the
        internet, as nbconvert does by default).
    """
    try:
        import jupyter_server_mathjax
    except ImportError:
        return None
    src = Path(jupyter_server_mathjax.__file__).parent / "static"
    if not (src / "MathJax.js").is_file():
        return None
    dest = Path(out_dir) / MATHJAX_DIR
    local = dest / "config" / "local" / "cshape.js"
    if not (local.is_file() and (dest / "MathJax.js").stat().st_size
            == (src / "MathJax.js").stat().st_size):
        # copies with the user's permissions (copy2 would keep the package files' modes)
        shutil.copytree(src, dest, dirs_exist_ok=True, copy_function=shutil.copyfile)
    if not (local.is_file() and local.read_text() == _MATHJAX_LOCAL):
        local.parent.mkdir(parents=True, exist_ok=True)
        atomic_write(local, lambda f: f.write(_MATHJAX_LOCAL), binary=False)
    return f"{MATHJAX_DIR}/MathJax.js?config={_MATHJAX_CONFIG}"


#: plotly's notebook renderer adds MathJax 3 from a CDN to every figure; the page has MathJax
#: already (plotly.js uses the page's), and a second MathJax would fight the first online.
_PLOTLY_CDN_MATHJAX = re.compile(
    r'<script src="https://cdnjs\.cloudflare\.com/ajax/libs/mathjax/[^"]*"></script>')


#: The lesson pages' template: nbconvert's "lab" page without require.js, which it loads from a
#: network host for widget JavaScript that a lesson page does not have (widgets show their
#: static copy, see :func:`run_notebook`); plotly figures bring their own plotly.js.
_LESSON_TEMPLATE = """\
{%- extends 'index.html.j2' -%}
{%- block html_head_js_requirejs -%}{%- endblock html_head_js_requirejs -%}
"""


def _html(nb: Any, mathjax_url: str | None = None) -> str:
    import jinja2
    from nbconvert import HTMLExporter

    exporter = HTMLExporter(
        template_name="lab", template_file="cshape_lesson.html.j2",
        extra_loaders=[jinja2.DictLoader({"cshape_lesson.html.j2": _LESSON_TEMPLATE})])
    if mathjax_url:
        exporter.mathjax_url = mathjax_url
    body, _ = exporter.from_notebook_node(nb)
    return _PLOTLY_CDN_MATHJAX.sub("", body) if mathjax_url else body


#: The text a tqdm bar shows when it is displayed (``" 40%|####      | 2/5 [...]"``).
_TQDM_TEXT = re.compile(r"\d+%\|")


def _final_progress_text(nb: Any, widget_state: dict[str, dict[str, Any]]) -> int:
    """Write each tqdm progress bar's final state into its text copy, in place.

    A notebook progress bar (``tqdm.auto`` in a kernel) is a widget: its output keeps the text
    it had when it was displayed ("0%"), and its later states live in the widget models only.
    From the models' last states (``widget_state``: model id -> state, as nbclient records
    them) the bar's text becomes what the widget showed last, e.g.
    ``"describe: 100%|##########| 54/54 [00:10<00:00, 5.2mesh/s]"`` (with full blocks).

    Returns
    -------
    int
        The number of bars rewritten.
    """
    from html import unescape

    done = 0
    for cell in nb.cells:
        for out in cell.get("outputs", []):
            data = out.get("data", {})
            view = data.get("application/vnd.jupyter.widget-view+json")
            if not view or not _TQDM_TEXT.search(str(data.get("text/plain", ""))):
                continue
            box = widget_state.get(view.get("model_id", ""), {})
            kids = [widget_state.get(str(c).removeprefix("IPY_MODEL_"), {})
                    for c in box.get("children", [])]
            if len(kids) != 3 or "max" not in kids[1]:
                continue
            left, bar, right = kids
            total = float(bar.get("max") or 0)
            frac = min(1.0, float(bar.get("value") or 0) / total) if total > 0 else 1.0
            filled = round(10 * frac)
            text = (f"{unescape(str(left.get('value', '')))}|"
                    f"{chr(0x2588) * filled}{' ' * (10 - filled)}|"
                    f"{unescape(str(right.get('value', '')))}")
            # the widget pads with figure spaces and no-break spaces; text uses plain ones
            data["text/plain"] = text.replace("\u2007", " ").replace("\xa0", " ")
            done += 1
    return done


def _kernel_env(small: bool, env: dict[str, str] | None = None) -> dict[str, str]:
    """The environment of a lesson's kernel: this process's, ``CSHAPE_SMALL=1`` only with
    ``small``, inline matplotlib and plotly's renderers (unless set), then ``env``."""
    kernel_env = dict(os.environ)
    kernel_env.pop("CSHAPE_SMALL", None)
    if small:
        kernel_env["CSHAPE_SMALL"] = "1"
    kernel_env.setdefault("MPLBACKEND", "module://matplotlib_inline.backend_inline")
    # plotly figures: the lab extension's mime type for JupyterLab, plus HTML with plotly.js
    # embedded once per notebook for the exported page (works offline, no kernel needed)
    kernel_env.setdefault("PLOTLY_RENDERER", "plotly_mimetype+notebook")
    kernel_env.update(env or {})
    return kernel_env


def run_notebook(path: str | os.PathLike[str], out_dir: str | os.PathLike[str] | None = None, *,
                 small: bool = False, timeout: float = 1200, html: bool = True,
                 stop_at_stub: bool = False, env: dict[str, str] | None = None) -> RunResult:
    """Execute one notebook top to bottom on a fresh kernel.

    Parameters
    ----------
    path : str or os.PathLike
        The ``.ipynb`` file; it is not modified.
    out_dir : str or os.PathLike, optional
        Where to write the executed notebook (same name) and, with ``html``, ``<stem>.html``.
        None writes nothing.
    small : bool, default=False
        Set ``CSHAPE_SMALL=1`` in the kernel's environment (small meshes and ``N``).
    timeout : float, default=1200
        Seconds allowed for one cell.
    html : bool, default=True
        Also write the notebook as a self-contained page, ``<out_dir>/<stem>.html`` (only
        with ``out_dir``).
    stop_at_stub : bool, default=False
        For student versions: an exercise stub raising ``NotImplementedError`` ends the run
        successfully (the cells after it are not run).
    env : dict, optional
        Extra environment variables for the kernel.

    Returns
    -------
    RunResult
        Whether every cell ran, the error of the failing cell, the time taken, the stderr
        outputs and the files written.

    Raises
    ------
    FileNotFoundError
        If there is no file at ``path``.
    """
    import nbformat
    from nbclient import NotebookClient
    from nbclient.exceptions import CellExecutionError

    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"notebook {str(path)!r} does not exist")
    nb = nbformat.read(path, as_version=4)
    kernel_env = _kernel_env(small, env)
    km = kernel_manager()
    # the widgets' states are recorded (for the progress bars' final text) but not saved: a
    # page without a kernel shows a widget's own static copy (the text/html of its display
    # data) instead of an empty box waiting for widget JavaScript from a network host
    client = NotebookClient(
        nb, km=km, timeout=int(timeout), allow_errors=False, store_widget_state=True,
        resources={"metadata": {"path": str(path.parent.resolve())}},
    )
    t0 = time.perf_counter()
    ok, err, stub = True, "", False
    try:
        client.execute(env=kernel_env, cwd=str(path.parent.resolve()))
    except CellExecutionError as exc:
        if stop_at_stub and exc.ename == "NotImplementedError":
            stub = True
        else:
            ok, err = False, f"{exc.ename}: {exc.evalue}"
    except Exception as exc:  # kernel died, timeout, ...
        ok, err = False, f"{type(exc).__name__}: {exc}"
    finally:  # we own the kernel manager: nbclient does not shut its kernel down
        if client.kc is not None:
            client.kc.stop_channels()
        if km.has_kernel:
            km.shutdown_kernel(now=True)
    seconds = time.perf_counter() - t0
    _final_progress_text(nb, client.widget_state)
    nb.metadata.pop("widgets", None)
    res = RunResult(path.name, ok, seconds, err, stub, stderr=stderr_outputs(nb))
    if out_dir is not None:
        out = Path(out_dir)
        out.mkdir(parents=True, exist_ok=True)
        res.ipynb = out / path.name
        atomic_write(res.ipynb, lambda f: nbformat.write(nb, f), binary=False)
        if html:
            res.html = out / f"{path.stem}.html"
            page = _html(nb, offline_mathjax(out))
            atomic_write(res.html, lambda f: f.write(page), binary=False)
    return res


def lesson_title(path: str | os.PathLike[str]) -> str:
    """The title of a lesson: its first Markdown heading (``# 2 · Shape-DNA ...``), else its
    file name."""
    return _lesson_head(path)[0]


def _lesson_head(path: str | os.PathLike[str]) -> tuple[str, str]:
    """``(title, sections)``: the first Markdown heading and the paper's sections that the
    ``**Paper:**`` paragraph below it names (``"Section 3.1, Section 3.2"``), or ``""``."""
    import nbformat

    nb = nbformat.read(path, as_version=4)
    for cell in nb.cells:
        if cell.cell_type != "markdown":
            continue
        heads = [ln[2:].strip() for ln in cell.source.splitlines() if ln.startswith("# ")]
        if heads:
            paper = cell.source.partition("**Paper:**")[2].partition("\n\n")[0]
            found = re.findall(r"Section \d(?:\.\d)?(?:-\d\.\d)?(?: and \d\.\d)?", paper)
            return heads[0], ", ".join(dict.fromkeys(found))
    return Path(path).stem, ""


#: The index page's look: the documentation site's (the PyData Sphinx theme's fonts,
#: colours and top bar), in one self-contained page.
_INDEX_CSS = """
:root { --fg: #222832; --muted: #48566b; --primary: #0a7d91; --line: #d1d5da;
        --bg-soft: #f3f4f5; --ok: #00854f; --bad: #c0392b; }
* { box-sizing: border-box; }
body { margin: 0; color: var(--fg); background: #fff; line-height: 1.65; font-size: 1rem;
       font-family: -apple-system, BlinkMacSystemFont, "Segoe UI", "Helvetica Neue", Arial,
       "Noto Sans", "Liberation Sans", sans-serif; }
header { height: 4rem; display: flex; align-items: center; padding: 0 2rem;
         box-shadow: 0 .125rem .25rem 0 rgba(0,0,0,.11); background: #fff; }
header .brand { font-weight: 700; font-size: 1.25rem; color: var(--fg); text-decoration: none; }
header .where { margin-left: 2rem; color: var(--muted); }
main { max-width: 64rem; margin: 0 auto; padding: 2rem 2rem 4rem; }
h1 { font-size: 2.2rem; font-weight: 400; margin: 0 0 1rem; }
a { color: var(--primary); text-decoration: underline;
    text-decoration-thickness: max(1px, .0625rem); }
a:hover { color: #085c6a; text-decoration-thickness: max(3px, .1875rem, .12em); }
p.lead { color: var(--muted); margin-top: 0; }
code { font-family: SFMono-Regular, Menlo, Consolas, "Liberation Mono", monospace;
       font-size: .875em; color: #912583; }
ol.lessons { list-style: none; padding: 0; margin: 1.5rem 0; border-top: 1px solid var(--line); }
ol.lessons li { display: grid; grid-template-columns: 1fr auto; gap: .25rem 1.5rem;
                padding: .9rem .25rem; border-bottom: 1px solid var(--line); }
ol.lessons .title { font-size: 1.15rem; }
ol.lessons .paper { color: var(--muted); font-size: .9rem; grid-column: 1; }
ol.lessons .state { grid-column: 2; grid-row: 1 / span 2; align-self: center; text-align: right;
                    font-size: .9rem; color: var(--muted); white-space: nowrap; }
.badge { display: inline-block; padding: .1rem .55rem; border-radius: .8rem; color: #fff;
         font-size: .8rem; font-weight: 600; margin-left: .5rem; }
.badge.ok { background: var(--ok); } .badge.bad { background: var(--bad); }
.error { color: var(--bad); font-size: .9rem; grid-column: 1 / span 2; white-space: pre-wrap; }
footer { color: var(--muted); font-size: .875rem; border-top: 1px solid var(--line);
         padding-top: 1rem; margin-top: 2rem; }
"""

#: MathJax 2.7 for the titles, as the lesson pages have it: ``$...$`` is inline math.
_INDEX_MATHJAX = """<script type="text/x-mathjax-config">
MathJax.Hub.Config({tex2jax: {inlineMath: [['$','$']], processEscapes: true,
                             ignoreClass: 'lead|paper|state|error', processClass: 'title'},
                   messageStyle: 'none'});
</script>
<script src="{url}"></script>"""


def _title_html(title: str, math: bool) -> str:
    """A lesson title as HTML: its TeX typeset by MathJax (``math``), else written plainly
    (``$M$`` -> *M*)."""
    text = html.escape(title)
    if math:
        return text
    return re.sub(r"\$([^$]+)\$", lambda m: f"<i>{m.group(1)}</i>", text)


def _index(results: Iterable[RunResult], out: Path, small: bool) -> Path:
    mathjax = offline_mathjax(out) if any(r.html for r in results) else None
    rows = []
    for r in results:
        title, paper = (_lesson_head(r.ipynb) if r.ipynb is not None else (r.name, ""))
        label = _title_html(title, mathjax is not None)
        link = f'<a href="{html.escape(r.html.name)}">{label}</a>' if r.html else label
        badge = ('<span class="badge ok">ran</span>' if r.ok
                 else '<span class="badge bad">failed</span>')
        note = " up to the first exercise" if r.stopped_at_stub else ""
        error = (f'<div class="error">{html.escape(r.error)}</div>' if not r.ok else "")
        paper_line = f"paper: {html.escape(paper)} · " if paper else "beyond the paper · "
        rows.append(
            f'<li><span class="title">{link}</span>'
            f'<span class="state">{r.seconds:.0f} s{note}{badge}</span>'
            f'<span class="paper">{paper_line}<code>{html.escape(r.name)}</code></span>'
            f"{error}</li>")
    size = ("at small size (<code>CSHAPE_SMALL=1</code>: small meshes, few eigenvalues)"
            if small else "at full size")
    head_math = _INDEX_MATHJAX.replace("{url}", html.escape(mathjax)) if mathjax else ""
    page = (
        "<!doctype html>\n<html lang='en'><head><meta charset='utf-8'>"
        "<meta name='viewport' content='width=device-width, initial-scale=1'>"
        f"<title>cshape lessons</title><style>{_INDEX_CSS}</style>{head_math}</head><body>"
        "<header><a class='brand' href='index.html'>cshape</a>"
        "<span class='where'>Lessons</span></header><main>"
        "<h1>Lessons</h1>"
        "<p class='lead'>The walkthrough notebooks follow Gao, Yu and Pang, <i>A compact "
        "shape descriptor for triangular surface meshes</i> (2014), section by section. "
        f"They ran here top to bottom, {size}. Open a lesson's page below: its 3-D views "
        "turn with the mouse and their sliders work without Python. To run a lesson "
        "yourself, open the executed <code>.ipynb</code> beside it in JupyterLab.</p>"
        f"<ol class='lessons'>{''.join(rows)}</ol>"
        "<footer>Made by <code>python -m cshape notebooks</code>. Lessons to change and run "
        "anywhere: <code>cshape lessons DIR</code>.</footer>"
        "</main></body></html>\n"
    )
    path = out / "index.html"
    atomic_write(path, lambda f: f.write(page), binary=False)
    return path


def run_notebooks(src: str | os.PathLike[str] | None = None,
                  out: str | os.PathLike[str] = "out/notebooks", *,
                  names: Iterable[str] | None = None, small: bool = False,
                  timeout: float = 1200, html: bool = True, stop_at_stub: bool = False,
                  progress: Callable[[str], object] | None = print,
                  n_jobs: int = 1) -> list[RunResult]:
    """Execute every notebook of ``src`` into ``out`` (executed ``.ipynb``, HTML, index.html).

    Parameters
    ----------
    src : str or os.PathLike, optional
        Folder of ``NN_*.ipynb`` (default: the checkout's ``notebooks/``).
    out : str or os.PathLike, default='out/notebooks'
        Folder of the executed notebooks, their HTML pages and ``index.html``, the page
        that lists them; created when missing.
    names : sequence of str, optional
        Run only these (see :func:`find_notebooks`).
    small : bool, default=False
        Run at small size (``CSHAPE_SMALL=1``), see :func:`run_notebook`.
    timeout : float, default=1200
        Seconds allowed for one cell.
    html : bool, default=True
        Also write each notebook's HTML page.
    stop_at_stub : bool, default=False
        End a notebook's run successfully at its first exercise stub, see
        :func:`run_notebook`.
    progress : callable or None, default=print
        Called with one line per notebook when it starts and when it ends.
    n_jobs : int, default=1
        Notebooks run at once, each on its own kernel.  Lessons that need the same
        generated collection wait for each other's builds (the data cache builds each mesh
        once).

    Returns
    -------
    list of RunResult
        In the order of the notebooks, whatever order they ended in.

    Raises
    ------
    FileNotFoundError
        If ``src`` holds no notebook ``NN_*.ipynb`` (of ``names``).
    """
    n_jobs = check_int("n_jobs", n_jobs, min=1)
    paths = find_notebooks(src, names)
    if not paths:
        raise FileNotFoundError(f"no notebooks named NN_*.ipynb in {str(src)!r}")
    out = Path(out)

    def one(p: Path) -> RunResult:
        if progress:
            progress(f"running {p.name} ...")
        r = run_notebook(p, out, small=small, timeout=timeout, html=html,
                         stop_at_stub=stop_at_stub)
        if progress:
            state = "ok" if r.ok else f"FAILED ({r.error.splitlines()[0] if r.error else ''})"
            if r.stopped_at_stub:
                state += ", stopped at the first exercise stub"
            if r.stderr:
                state += f", {len(r.stderr)} stderr output(s): {r.stderr[0].splitlines()[0]}"
            progress(f"  {p.name}: {state} in {r.seconds:.1f} s")
        return r

    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(max_workers=min(n_jobs, len(paths))) as pool:
        results = list(pool.map(one, paths))  # each thread waits on its kernel
    index = _index(results, out, small)
    if progress:
        what = "executed notebooks and HTML pages" if html else "executed notebooks"
        progress(f"{what} in {out}/")
        progress(f"open the lessons in a browser: {index.resolve().as_uri()}")
    return results
