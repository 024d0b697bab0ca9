"""Compile options of ``fast``, in one place (numba-stats' pattern).

Every compiled function of ``fast`` is decorated with :func:`kernel`:

* ``cache=True``: the machine code is written next to the source (``__pycache__``), so a
  process after the first one loads it instead of compiling (numba falls back to a
  user-wide cache directory where the package directory is not writable);
* ``nogil=True``: the batch driver runs chunks of states on threads;
* ``error_model="numpy"``: a division by zero gives ``inf``/``nan`` as in numpy, no Python
  exception check on every division (the kernels test their own results);
* ``fastmath=False`` (numba's default, written out): the double-double arithmetic of
  ``fast.dd`` relies on every operation being rounded as IEEE 754 says; reassociation or
  contraction would silently destroy the error-free transformations.

:func:`fma` is the fused multiply-add ``a * b + c`` with one rounding (LLVM's
``llvm.fma.f64``: one instruction on x86-64 with FMA3, a correctly rounded library call
elsewhere), the basis of the two-operation exact product ``fast.dd.two_prod``.
"""
from __future__ import annotations

import numba
from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic

OPTIONS = dict(cache=True, nogil=True, error_model="numpy", fastmath=False)


def kernel(fn):
    """``numba.njit`` with ``fast``'s options (module docstring)."""
    return numba.njit(**OPTIONS)(fn)


@intrinsic
def fma(typingctx, a, b, c):
    """``a * b + c`` rounded once (float64 arguments)."""
    sig = types.float64(types.float64, types.float64, types.float64)

    def codegen(context, builder, signature, args):
        fnty = ir.FunctionType(ir.DoubleType(), [ir.DoubleType()] * 3)
        fn = cgutils.get_or_insert_function(builder.module, fnty, "llvm.fma.f64")
        return builder.call(fn, args)

    return sig, codegen
