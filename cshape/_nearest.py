"""Exact nearest rows in spectral space, the one engine of maps and signature matches.

It serves the vertex maps of :mod:`cshape.maps` and :func:`cshape.signatures.match_points`.

Up to 3 dimensions a k-d tree; above (k-d and ball trees degrade to a scan in 30-100
dimensions) blocks of dense matrix products, shared among threads with one BLAS thread each,
or scikit-learn's brute-force search for big problems.
"""

from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from ._eigensolver.threads import one_blas_thread

#: Query rows per matrix product: a block holds ``NN_BLOCK x n_S`` distances
#: (512 x 60,000 x 8 bytes = 0.25 GB).
NN_BLOCK = 512

#: Threads sharing the blocks (at most the CPUs).
NN_THREADS = 2

#: From this many (query, point) pairs on, the blocks are shared among threads (below, starting
#: the threads costs more than they gain).
NN_THREAD_PAIRS = 4 * 10**6

#: From this many (query, point) pairs on, scikit-learn's brute-force search (the full-size
#: map of 10K-vertex meshes and up); below, the blocks above.
NN_SKLEARN_PAIRS = 10**8


def nearest_rows(queries, points, block=None, single=False):
    """Index of the nearest row of ``points`` for every row of ``queries``, exactly.

    Up to 3 dimensions a k-d tree.  Above (k-d and ball trees degrade to a scan in 30-100
    dimensions), scikit-learn's brute-force search for big problems (at least
    ``NN_SKLEARN_PAIRS`` query-point pairs: its OpenMP threads cost more than they gain on
    small ones), else blocks of ``|p|^2 - 2 q.p`` (``|q|^2`` does not change the argmin), each
    block one matrix product ``[q, 1] [-2 p, |p|^2]^T`` and its row-wise argmin; the blocks
    are shared among threads with one BLAS thread each, so that no BLAS worker spins.

    ``single=True``: the blocks in single precision (twice as fast; a query whose two nearest
    rows are within round-off of single precision may get either), for the searches of an
    iteration that only needs a good map, not the exact one.
    """
    block = NN_BLOCK if block is None else block
    if points.shape[1] <= 3:
        from scipy.spatial import cKDTree

        return cKDTree(points).query(queries)[1].astype(np.int64)
    if len(queries) * len(points) >= NN_SKLEARN_PAIRS:
        # the same products, tiled and reduced in compiled code on every core
        from sklearn.neighbors import NearestNeighbors

        nn = NearestNeighbors(n_neighbors=1, algorithm="brute").fit(points)
        return nn.kneighbors(queries, return_distance=False)[:, 0].astype(np.int64)
    dtype = np.float32 if single else np.float64
    P = np.empty((points.shape[1] + 1, len(points)), dtype=dtype)
    P[:-1] = -2.0 * points.T
    P[-1] = np.einsum("ij,ij->i", points, points)
    Q = np.empty((len(queries), queries.shape[1] + 1), dtype=dtype)
    Q[:, :-1] = queries
    Q[:, -1] = 1.0
    out = np.empty(len(queries), dtype=np.int64)

    def run(s):
        out[s:s + block] = np.argmin(Q[s:s + block] @ P, axis=1)

    starts = range(0, len(queries), block)
    threads = min(len(starts), NN_THREADS, os.cpu_count() or 1)
    if len(queries) * len(points) < NN_THREAD_PAIRS:
        threads = 1
    with one_blas_thread():
        if threads > 1:
            with ThreadPoolExecutor(threads) as pool:
                list(pool.map(run, starts))
        else:
            for s in starts:
                run(s)
    return out

