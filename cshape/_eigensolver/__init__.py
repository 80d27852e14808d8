"""The eigensolver behind :mod:`cshape.spectrum` (private): one module by job.

* ``shift``   - the shift of shift-invert and its one sparse factorisation, below or inside
  the spectrum (Sylvester's inertia counts the eigenvalues below an inside shift);
* ``lanczos`` - block shift-invert Lanczos on that factorisation;
* ``threads`` - the thread policy (how many threads the solves and products use);
* ``cholmod`` - the sparse Cholesky backends (CHOLMOD through ctypes, else SciPy's).

The public contract is :func:`cshape.spectrum.solve_eigenproblem`; the derivation is the
eigensolver guide of the documentation, the measured figures ``benchmarks/SCALE.md``.
"""
