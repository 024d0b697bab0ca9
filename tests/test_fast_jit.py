"""``fast.jit``: one compiled copy of a kernel for every constant argument of a type."""
from __future__ import annotations

from numba.core import caching

from fast import jit


def _pair(make):
    """A callee and a caller that passes it both constants of a flag, made by ``make``."""
    def scale(x, flag):
        return 2.0 * x if flag else x

    callee = make(scale)
    callee._cache = caching.NullCache()          # compile here, whatever a cache holds

    def both(x):
        return callee(x, True) + callee(x, False)

    caller = make(both)
    caller._cache = caching.NullCache()
    return callee, caller


def test_a_kernel_is_compiled_once_for_both_constants_of_a_flag():
    """``kernel``'s dispatcher types the constants ``True`` and ``False`` as ``bool``: one
    signature, the same result."""
    callee, caller = _pair(jit.kernel)
    assert caller(1.5) == 4.5
    assert [str(s) for s in callee.signatures] == ["(float64, bool)"]


def test_numbas_own_dispatcher_compiles_a_copy_per_constant():
    """The check can fail: numba's ``CPUDispatcher`` (options as ``kernel``'s) compiles the
    callee once per literal."""
    def make(fn):
        options = {**jit.OPTIONS, "nopython": True, "boundscheck": None, "inline": "never"}
        return jit.CPUDispatcher(py_func=fn, locals={}, targetoptions=options)

    callee, caller = _pair(make)
    assert caller(1.5) == 4.5
    assert len(callee.signatures) == 2


def test_no_kernel_is_inlined_by_numba():
    """Every compiled function of ``fast`` leaves inlining to LLVM (``fast.jit``'s docstring:
    numba's own inlining typed a helper's body again at every call site, a quarter of a cold
    compile).  The check can fail: numba's option ``inline="always"`` on any kernel."""
    import importlib
    import pkgutil

    import fast

    kernels = [obj for info in pkgutil.iter_modules(fast.__path__)
               for obj in vars(importlib.import_module(f"fast.{info.name}")).values()
               if isinstance(obj, jit._Dispatcher)]
    assert len({id(k) for k in kernels}) > 40
    assert {k.targetoptions["inline"] for k in kernels} == {"never"}
