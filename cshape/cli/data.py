"""``cshape data``: list, build and locate the collections of the data manifest.
"""

from __future__ import annotations

import time
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import argparse

    _SubParsers = argparse._SubParsersAction[Any]  # of the command line's parser class


# ============================================================================ data
def _cmd_data_list(args: argparse.Namespace) -> int:
    from ..data.manifest import load_manifest

    entries = load_manifest(args.manifest)
    rows = []
    for name, e in entries.items():
        n = len(e.get("items") or [])
        rows.append((name, e["kind"], str(n) if n else "-", " ".join(e["description"].split())))
    w0 = max(len(r[0]) for r in rows)
    print(f"{'name':<{w0}}  {'kind':<9}  {'items':>5}  description")
    for r in rows:
        desc = r[3] if len(r[3]) <= 70 else r[3][:67] + "..."
        print(f"{r[0]:<{w0}}  {r[1]:<9}  {r[2]:>5}  {desc}")
    return 0


def _cmd_data_build(args: argparse.Namespace) -> int:
    from ..data import build, load_collection

    t0 = time.perf_counter()
    folder = build(args.name, cache_dir=args.cache_dir, archive=args.archive,
                   manifest=args.manifest, progress=None)
    n = len(load_collection(args.name, cache_dir=args.cache_dir, manifest=args.manifest,
                            progress=False))
    print(f"{args.name}: {n} meshes ready in {time.perf_counter() - t0:.1f} s at {folder}")
    return 0


def _cmd_data_path(args: argparse.Namespace) -> int:
    from ..data.paths import collection_path

    print(collection_path(args.name, cache_dir=args.cache_dir, manifest=args.manifest))
    return 0


def add_data(sub: _SubParsers) -> None:
    """``cshape data {list, build NAME, path NAME}``: the collections of :mod:`cshape.data`."""
    import argparse

    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("--manifest", default=None, help="manifest file (default: the shipped one)")
    common.add_argument("--cache-dir", default=None,
                        help="cache folder (default: $CSHAPE_CACHE or ~/.cache/cshape)")
    p = sub.add_parser("data", help="list, build and locate shape collections")
    dsub = p.add_subparsers(dest="data_command", required=True)
    pl = dsub.add_parser("list", parents=[common], help="list the collections of the manifest")
    pl.set_defaults(func=_cmd_data_list)
    pb = dsub.add_parser(
        "build", parents=[common],
        help="build (generated), download (download) or check (package, local) a collection",
    )
    pb.add_argument("name", help="collection name (see `cshape data list`)")
    pb.add_argument("--archive", default=None,
                    help="a benchmark archive you downloaded by hand, to unpack into place")
    pb.set_defaults(func=_cmd_data_build)
    pp = dsub.add_parser("path", parents=[common], help="print the folder of a collection")
    pp.add_argument("name", help="collection name")
    pp.set_defaults(func=_cmd_data_path)
