"""Compile options of ``fast``, in one place (numba-stats' pattern).

Every compiled function of ``fast`` is decorated with :func:`kernel`:

* ``cache=True``: the machine code is written next to the source (``__pycache__``), so a
  process after the first one loads it instead of compiling (numba falls back to a
  user-wide cache directory where the package directory is not writable).  numba stamps
  a cache entry with its function's own source file only, so a compiled caller would keep
  stale copies of callees from other modules; here every entry is stamped with the
  digest of all of ``fast``'s sources (``SOURCES_DIGEST``): any change recompiles all;
* ``nogil=True``: the batch driver runs chunks of states on threads;
* ``error_model="numpy"``: a division by zero gives ``inf``/``nan`` as in numpy, no Python
  exception check on every division (the kernels test their own results);
* ``fastmath=False`` (numba's default, written out): the double-double arithmetic of
  ``fast.dd`` relies on every operation being rounded as IEEE 754 says; reassociation or
  contraction would silently destroy the error-free transformations;
* one compiled copy of a function for every constant argument of a type (``_Dispatcher``): numba
  would compile a callee again for each literal flag or offset a caller passes;
* no inlining by numba (``inline="never"``): LLVM inlines at ``-O3`` what pays, on the linked
  module.  numba's own inlining (``inline="always"``, once on 47 small helpers) deep-copied and
  typed a helper's body again at every call site: issue 33, cold, fast's closed-form engine
  compiled in 25.3 CPU s without it against 33 with it, position forcing's in 15.4 against 20.3
  (2-core machine, one run each).  LLVM leaves about ten helpers as calls (``dd.sincos``,
  ``flight.evaluate``, ``roots.analyze`` among them); the run time is the same (best of five,
  eight alternations, four workloads of ``map_and_jacobian``: within 4%, either way), and so is
  every number, bit for bit (``fastmath`` is off: the operations are the same in the same order).

:func:`fma` is the fused multiply-add ``a * b + c`` with one rounding (LLVM's
``llvm.fma.f64``: one instruction on x86-64 with FMA3, a correctly rounded library call
elsewhere), the basis of the two-operation exact product ``fast.dd.two_prod``.
"""
from __future__ import annotations

import hashlib
import pathlib

from llvmlite import ir
from numba import types
from numba.core import caching, cgutils
from numba.core.registry import CPUDispatcher
from numba.extending import intrinsic

OPTIONS = dict(nogil=True, error_model="numpy", fastmath=False)
#: sha256 of every module of ``fast`` (the stamp of every compiled entry in the cache)
SOURCES_DIGEST = hashlib.sha256(b"".join(
    path.name.encode() + path.read_bytes()
    for path in sorted(pathlib.Path(__file__).parent.glob("*.py")))).hexdigest()


class _PackageStamp:
    """Cache locator mixin: the freshness stamp is the digest of the whole package."""

    def get_source_stamp(self):
        return SOURCES_DIGEST


class _InTreeLocator(_PackageStamp, caching.InTreeCacheLocator):
    pass


class _UserWideLocator(_PackageStamp, caching.UserWideCacheLocator):
    pass


class _UserProvidedLocator(_PackageStamp, caching.UserProvidedCacheLocator):
    pass


class _Impl(caching.CompileResultCacheImpl):
    _locator_classes = [_UserProvidedLocator, _InTreeLocator, _UserWideLocator]


class _Cache(caching.FunctionCache):
    _impl_class = _Impl


class _Dispatcher(CPUDispatcher):
    """numba's CPU dispatcher, which types a call from compiled code on the arguments' plain
    types: a constant argument (a flag, a slot offset, a tuple of slots) is an ``int64``, a
    ``bool`` or a ``UniTuple``, not a ``Literal`` that numba would compile a copy of the callee
    for.  The code is the same but for the constants' folding: ``fastmath`` is off, so every
    floating-point operation, and so every number, is the same.  Issue 33: cold, the two
    engines compiled six callees twice or thrice (``roots._plan`` for ``plan`` and
    ``plan_crawl``, ``loop._finish_flight``, ``dop853.step`` and ``rhs``, ``compensated.step``,
    ``ode_flight``'s root finders); with one copy each, cold, the closed-form engine took 33 CPU s
    instead of 40 and position forcing's 22 instead of 30 (two runs each, alternating), paid by
    every first run of a fresh clone."""

    def get_call_template(self, args, kws):
        return super().get_call_template(tuple(types.unliteral(a) for a in args),
                                         {k: types.unliteral(t) for k, t in kws.items()})


def kernel(fn):
    """``numba.njit`` with ``fast``'s options and the package-stamped cache (module
    docstring).  The dispatcher is :class:`_Dispatcher`: one compiled copy of a function for
    all constant arguments of a type."""
    options = {**OPTIONS, "nopython": True, "boundscheck": None, "inline": "never"}
    dispatcher = _Dispatcher(py_func=fn, locals={}, targetoptions=options)
    dispatcher._cache = _Cache(fn)          # what numba's enable_caching() does
    return dispatcher


@intrinsic
def fma(typingctx, a, b, c):
    """``a * b + c`` rounded once (float64 arguments)."""
    sig = types.float64(types.float64, types.float64, types.float64)

    def codegen(context, builder, signature, args):
        fnty = ir.FunctionType(ir.DoubleType(), [ir.DoubleType()] * 3)
        fn = cgutils.get_or_insert_function(builder.module, fnty, "llvm.fma.f64")
        return builder.call(fn, args)

    return sig, codegen


@intrinsic
def data_pointer(typingctx, arr):
    """The data pointer of a contiguous array (``CPointer``), indexed like the array.

    Every compiled call that takes an array updates the array's reference count at entry
    and exit (numba's runtime calls, atomic); the event loop makes a dozen such calls per
    event with the parameter array ``P`` and the state record ``st``.  Measured: a third
    of the loop's time.  A raw pointer carries no count.  The caller owns ``arr`` and keeps
    it alive (and contiguous) for as long as the pointer is used.
    """
    if not isinstance(arr, types.Array) or arr.layout != "C":
        return None

    def codegen(context, builder, signature, args):
        return context.make_array(signature.args[0])(context, builder, value=args[0]).data

    return types.CPointer(arr.dtype)(arr), codegen
