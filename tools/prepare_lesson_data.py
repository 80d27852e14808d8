"""Write the eigenvalues that the lessons use prepared at full size.

``cshape/course/creatures-dev-spectra.npz``: ``batch.describe`` of the ``creatures-dev``
collection (12 classes x 10 members), ``N = 100``, the defaults of ``describe``.  The meshes are
built one by one (``n_jobs=1``), in a fresh cache folder, as the test that checks the file
rebuilds them.  Run it when the creature recipes or the eigensolver change:

    python tools/prepare_lesson_data.py
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from cshape import batch, data  # noqa: E402
from cshape.course.teaching import PREPARED_RETRIEVAL  # noqa: E402


def main() -> None:
    with tempfile.TemporaryDirectory() as cache:
        coll = data.load_collection("creatures-dev", cache_dir=cache, progress=True, n_jobs=1)
        table = batch.describe(coll, N=100, cache_dir=False, progress=True)
    if table.failures:
        raise SystemExit(f"some shapes failed: {table.failures}")
    out = REPO / "cshape" / "course" / PREPARED_RETRIEVAL
    # the timings and cache flags of this machine mean nothing to a reader of the lessons
    table = batch.DescriptorTable(table.names, table.lam, table.areas, table.labels,
                                  bc=table.bc, mass=table.mass, refine=table.refine,
                                  components=table.components)
    table.save(out)
    print(f"wrote {out} ({len(table)} shapes, N = {table.N})")


if __name__ == "__main__":
    main()
