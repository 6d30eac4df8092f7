"""Sparse LU factors from Intel MKL PARDISO, which keep their symbolic analysis across refactorizations.

SciPy's SuperLU orders and analyses the matrix again at every factorization.
The cap tangent's sparsity pattern never changes, so PARDISO's analysis
(phase 11: nested-dissection ordering and symbolic factorization) runs once
per pattern and each refactorization is numeric only (phase 22); solves are
phase 33. On a paper case's tangent (19.5k DOF) the numeric phase takes
25-40 ms against SuperLU's 75-140 ms, and a solve 4-6 ms against 3.4-6 ms
(one thread; docs/performance.md).

MKL is not a dependency: ``pip install mkl`` (x86-64) provides the runtime
library ``libmkl_rt``, which is called here through ctypes. Settings:
real unsymmetric matrix (type 11), zero-based CSR indices, pivots perturbed
to 1e-13 of the norm (a preconditioner need not be exact), no iterative
refinement, and no scaling or weighted matching, so that the analysis depends
on the pattern alone. With ``single=True`` the numeric factorization and the
solves run in single precision (iparm[27] = 1; the matrix and vectors are
passed as float32): a preconditioner for GMRES, which runs in double.
PARDISO runs on one thread, whatever MKL_NUM_THREADS says: with two, a fresh
factorization and a refactorization of the same matrix differed in the last
bits, and a resumed case must repeat the uninterrupted one bit for bit.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import functools
import glob
import os
import sys
import weakref

import numpy as np
import scipy.sparse as sp

__all__ = ["PardisoFactors", "mkl_runtime", "PardisoUnavailable"]

_INT = np.int32  # MKL_INT of mkl_rt's default LP64 interface
_MATRIX_TYPE = 11  # real and unsymmetric
_MKL_DOMAIN_PARDISO = 4
_PHASE_ANALYSIS, _PHASE_NUMERIC, _PHASE_SOLVE, _PHASE_FREE = 11, 22, 33, -1
_ERRORS = {-1: "input inconsistent", -2: "not enough memory", -3: "reordering problem",
           -4: "zero pivot, numerical factorization or iterative refinement problem", -5: "unclassified internal error",
           -6: "reordering failed", -7: "diagonal matrix is singular", -8: "32-bit integer overflow",
           -9: "not enough memory for the out-of-core solver", -10: "error opening out-of-core files",
           -11: "read/write error with out-of-core files", -12: "wrong pardiso_64 call"}


class PardisoUnavailable(ImportError):
    """The MKL runtime library was not found."""


@functools.cache
def mkl_runtime() -> ctypes.CDLL | None:
    """The MKL runtime library (``libmkl_rt``) of this Python environment, or found by the loader; None when absent."""
    candidates = sorted(glob.glob(os.path.join(sys.prefix, "lib", "libmkl_rt.so*")))
    found = ctypes.util.find_library("mkl_rt")
    for path in candidates + ([found] if found else []):
        try:
            lib = ctypes.CDLL(path)
        except OSError:
            continue
        ints = np.ctypeslib.ndpointer(_INT, flags="C_CONTIGUOUS")
        lib.MKL_Domain_Set_Num_Threads.argtypes = [ctypes.c_int, ctypes.c_int]
        lib.MKL_Domain_Set_Num_Threads(1, _MKL_DOMAIN_PARDISO)  # one thread: the same factors in every run
        lib.pardiso.restype = None
        lib.pardiso.argtypes = [np.ctypeslib.ndpointer(np.int64, flags="C_CONTIGUOUS"), ints, ints, ints, ints, ints,
                                ctypes.c_void_p, ints, ints, ctypes.c_void_p, ints, ints, ints, ctypes.c_void_p,
                                ctypes.c_void_p, ints]  # the matrix and vectors: float64, or float32 in single precision
        return lib
    return None


def _settings(single: bool = False) -> np.ndarray:
    """PARDISO's iparm (0-based positions of the 1-based manual's entries)."""
    iparm = np.zeros(64, dtype=_INT)
    iparm[0] = 1  # these settings, not the defaults
    iparm[1] = 2  # nested-dissection ordering (METIS)
    iparm[7] = 0  # no iterative refinement
    iparm[9] = 13  # perturb pivots below 1e-13 ||A||
    iparm[10] = 0  # no scaling
    iparm[12] = 0  # no weighted matching: the analysis depends on the pattern alone
    iparm[17] = -1  # report the fill of L + U
    iparm[18] = -1  # report the numeric factorization's flops (in millions)
    iparm[27] = 1 if single else 0  # single or double precision
    iparm[34] = 1  # zero-based indices
    return iparm


def _release(lib, handle: np.ndarray, n: int, single: bool) -> None:
    """Free PARDISO's memory of ``handle`` (phase -1)."""
    one, error = np.ones(1, dtype=_INT), np.zeros(1, dtype=_INT)
    empty_i = np.zeros(1, dtype=_INT)
    lib.pardiso(handle, one, one, np.array([_MATRIX_TYPE], dtype=_INT), np.array([_PHASE_FREE], dtype=_INT),
                np.array([n], dtype=_INT), None, empty_i, empty_i, None, one, _settings(single),
                np.zeros(1, dtype=_INT), None, None, error)


class PardisoFactors:
    """LU factors of a square CSR matrix, in double precision or with ``single`` in single; :meth:`refactor` with a
    matrix of the same pattern redoes only the numeric factorization. ``solve(b)`` takes one right-hand side (n,) or
    several (n, k) and returns float64."""

    def __init__(self, A: sp.csr_matrix, single: bool = False):
        lib = mkl_runtime()
        if lib is None:
            raise PardisoUnavailable("MKL PARDISO needs the MKL runtime library: pip install mkl (x86-64 only)")
        self._lib = lib
        self.n = A.shape[0]
        self._handle = np.zeros(64, dtype=np.int64)  # PARDISO's internal pointers
        self.single = single
        self._real = np.float32 if single else np.float64
        self._iparm = _settings(single)
        A = self._csr(A)
        self._indptr, self._indices = A.indptr.astype(_INT), A.indices.astype(_INT)
        self._data = np.ascontiguousarray(A.data, dtype=self._real)
        self._call(_PHASE_ANALYSIS)
        weakref.finalize(self, _release, lib, self._handle, self.n, single)
        self._call(_PHASE_NUMERIC)

    @staticmethod
    def _csr(A) -> sp.csr_matrix:
        A = sp.csr_matrix(A)
        if A.shape[0] != A.shape[1]:
            raise ValueError(f"PARDISO needs a square matrix, got {A.shape}")
        if not A.has_sorted_indices:
            A = A.sorted_indices()
        return A

    @property
    def fill(self) -> int:
        """Entries of L + U."""
        return int(self._iparm[17])

    @property
    def factorization_flops(self) -> float:
        """Floating-point operations of one numeric factorization, as counted by the analysis."""
        return float(self._iparm[18]) * 1e6

    def same_pattern(self, A: sp.csr_matrix) -> bool:
        return (sp.issparse(A) and A.format == "csr" and A.shape == (self.n, self.n) and np.array_equal(A.indptr, self._indptr)
                and np.array_equal(A.indices, self._indices))

    def refactor(self, A: sp.csr_matrix) -> None:
        """New numeric factors of A, which must have the analysed pattern."""
        A = self._csr(A)
        if not self.same_pattern(A):
            raise ValueError("refactor needs the sparsity pattern of the analysed matrix")
        self._data = np.ascontiguousarray(A.data, dtype=self._real)
        self._call(_PHASE_NUMERIC)

    def solve(self, b: np.ndarray) -> np.ndarray:
        b = np.ascontiguousarray(b, dtype=self._real)
        if b.shape[0] != self.n:
            raise ValueError(f"right-hand side of length {b.shape[0]} for a matrix of size {self.n}")
        x = np.empty_like(b)
        nrhs = 1 if b.ndim == 1 else b.shape[1]
        if nrhs > 1:  # PARDISO takes the right-hand sides as columns stored one after the other
            bt, xt = np.ascontiguousarray(b.T), np.empty((nrhs, self.n), dtype=self._real)
            self._call(_PHASE_SOLVE, bt, xt, nrhs)
            return np.ascontiguousarray(xt.T, dtype=np.float64)
        self._call(_PHASE_SOLVE, b, x, 1)
        return x.astype(np.float64, copy=False)

    def _call(self, phase: int, b: np.ndarray | None = None, x: np.ndarray | None = None, nrhs: int = 1) -> None:
        one, error = np.ones(1, dtype=_INT), np.zeros(1, dtype=_INT)
        self._lib.pardiso(self._handle, one, one, np.array([_MATRIX_TYPE], dtype=_INT), np.array([phase], dtype=_INT),
                          np.array([self.n], dtype=_INT), self._data.ctypes.data, self._indptr, self._indices, None,
                          np.array([nrhs], dtype=_INT), self._iparm, np.zeros(1, dtype=_INT),
                          None if b is None else b.ctypes.data, None if x is None else x.ctypes.data, error)
        if error[0] != 0:
            code = int(error[0])
            raise np.linalg.LinAlgError(f"PARDISO phase {phase}: error {code} ({_ERRORS.get(code, 'unknown')})")
