"""The pytest plugin of the golden data (entry point ``pytest11``: ``vibro_impact_golden``).

A third party's test file asks for the ``golden_case`` fixture and gets one test per golden
case (the float64 input of each; ``cross_check.score.golden.GoldenCase``)::

    def test_mine(golden_case):
        x, v = my_integrator(golden_case.params, golden_case.x, golden_case.v)
        golden_case.assert_close(x, v)

``assert_close`` holds ``Phi`` to the named tolerance ``golden_case_float64`` (or another name of
``cross_check.tolerances``), relative to ``max(1, |Phi|)``, widened by the exact map's own
one-ulp floor where a graze makes it larger; a case in the near-grazing band is skipped with that
reason (its itinerary is not fixed by a float64 start).  ``--golden-scenes NAME ...`` narrows the
scenes; ``--golden-kinds KIND ...`` the kinds (``score.golden.KINDS``); ``--golden-dir DIR`` takes
the golden data of DIR (a user's own scenes, as ``python -m cross_check verify`` writes it) instead
of the shipped data: ``pytest --golden-dir DIR`` in a user's CI.

**A time budget that a loop cannot ignore.**  The plugin does not own the integrator call (the
test body does), so it runs the whole test function of each golden case in a worker process
(``score.isolate.Worker``, ``spawn``), one per session: the test module is imported there by its
path and name, the test's arguments are pickled over, and the call gets ``--golden-timeout``
seconds (default 10).  Over it, the process is killed -- whatever the test is doing, in Python or
in C -- and the test fails with the scorecard's message: the case, its kind, what usually causes
a timeout there (``golden.timeout_message``).  The session goes on in a fresh process, warmed by
replaying the last test that passed (its outcome thrown away).  The first time a test function
meets a set of effects, it is first run on a case with those effects that neither sticks nor
chatters (its outcome thrown away, within ``runner.FIRST_CALL_TIMEOUT``): a JIT compiling there
does not eat a case's budget.  Output printed by the test comes back with its result.  In the
worker, bare ``assert`` statements are not rewritten by pytest (their message is Python's);
``assert_close`` says everything itself.

**Fail fast per kind** (``score.cutoff``): after ``--golden-kind-timeouts`` K (default 2; 0: off)
timeouts of one test on one kind of case in a scene, its other cases of that kind there fail at
once with the reason ``not run: kind KIND timed out K times in this scene`` (a failure, never a
silent skip); a kind cut in 3 scenes running gets one probe case per later scene.  A failing kind
ends in a few budgets.

Run here instead, with the budget checked after the test returns (a test that never returns
hangs the session): ``--golden-in-process``, and tests the worker cannot take -- a fixture that
acts on pytest's process (``request``, ``monkeypatch``, ``capsys``, ...: a patch made here would
not reach the worker), arguments that do not pickle, a test defined inside a function, an async
test, a module that does not import in the worker (each with a warning saying why).
"""
from __future__ import annotations

import contextlib
import importlib
import importlib.util
import inspect
import io
import os
import pickle
import sys
import time
import traceback

import pytest

from cross_check.score import cutoff, isolate, runner

_STATE = pytest.StashKey()
_RUN = "cross_check.score.plugin:worker_run"
#: pytest's fixtures that act on pytest's own process: a test using one runs there
_HERE = frozenset({"request", "pytestconfig", "monkeypatch", "capsys", "capsysbinary", "capfd", "capfdbinary",
                   "caplog", "recwarn"})
_IMPORT = "cross_check.score.plugin:worker_import"


class _Checked:
    """A ``GoldenCase`` with the assertion a test needs."""

    def __init__(self, case):
        self.case = case

    def __getattr__(self, name):
        if name.startswith("__") or name == "case":     # pickling looks for dunders before __dict__ is set
            raise AttributeError(name)
        return getattr(self.case, name)

    def assert_close(self, x, v, tolerance: str = "golden_case_float64"):
        """``(x, v)`` within the named tolerance of the golden ``Phi`` (module docstring)."""
        from cross_check.tolerances import tol

        if self.case.band:
            pytest.skip(f"{self.case.id}: in the near-grazing band (itinerary not fixed by a float64 start)")
        t = tol(tolerance)
        err, floor = self.case.map_error(x, v)
        assert err <= max(t.rtol, floor), (
            f"{self.case.id} [{self.case.kind}]: Phi = ({float(x)!r}, {float(v)!r}), golden "
            f"({self.case.phi[0][:20]}, {self.case.phi[1][:20]}): relative error {err:.2e} > "
            f"{tolerance} {t.rtol:g} (4 x one-ulp floor {floor:.1e})")


def pytest_addoption(parser):
    group = parser.getgroup("vibro-impact golden data")
    group.addoption("--golden-scenes", nargs="+", default=None, metavar="NAME",
                    help="golden_case: only these scenes (default: all)")
    group.addoption("--golden-kinds", nargs="+", default=None, metavar="KIND",
                    help="golden_case: only these kinds of case (cross_check.score.golden.KINDS)")
    group.addoption("--golden-dir", default=None, metavar="DIR",
                    help="golden_case: the golden data in DIR (written by `python -m cross_check verify` or "
                         "`golden`; default: the data shipped with the suite)")
    group.addoption("--golden-timeout", type=runner.positive_seconds, default=runner.CASE_TIMEOUT,
                    metavar="SECONDS", help=f"golden_case: seconds per test (default {runner.CASE_TIMEOUT:g}), "
                    "enforced by running it in a worker process that is killed when it runs over")
    group.addoption("--golden-kind-timeouts", type=cutoff.kind_timeouts_arg, default=cutoff.KIND_TIMEOUTS,
                    metavar="K", help="golden_case: after K timeouts of one test on one kind of case in a scene, its "
                    "other cases of that kind there fail at once with 'not run: ...'; a kind cut in "
                    f"{cutoff.SCENES_RUNNING} scenes running gets one probe case per later scene (default "
                    f"{cutoff.KIND_TIMEOUTS}; 0: every case runs)")
    group.addoption("--golden-in-process", action="store_true",
                    help="golden_case: run the tests in this process; the budget is then checked after each "
                         "test returns, so a test that never returns hangs the session")


def pytest_generate_tests(metafunc):
    if "golden_case" not in metafunc.fixturenames:
        return
    from cross_check.score.golden import all_cases

    try:
        cases = all_cases(metafunc.config.getoption("golden_scenes"), metafunc.config.getoption("golden_dir"))
    except ValueError as exc:             # no such directory, no golden file there, a scene it lacks
        raise pytest.UsageError(f"golden_case: {exc}") from None
    kinds = metafunc.config.getoption("golden_kinds")
    if kinds:
        cases = [c for c in cases if c.kind in kinds]
    metafunc.parametrize("golden_case", [_Checked(c) for c in cases], ids=[c.id for c in cases])


class _Session:
    """The session's worker and what it has been given."""

    def __init__(self, budget: float, golden_dir=None, kind_timeouts: int = cutoff.KIND_TIMEOUTS):
        self.budget, self.worker, self.golden_dir = budget, isolate.Worker(), golden_dir
        self.imported, self.here = set(), {}      # module paths in the worker; paths run here -> why
        self.warmed = set()                       # (module path, test[, effects]) seen
        self.kind_timeouts = kind_timeouts
        self.cutoffs: dict = {}                   # (module path, test) -> [KindCutoff, scene, SceneCut]

    def scene_cut(self, test, scene: str) -> cutoff.SceneCut:
        """The per-kind cut-off of ``test`` (module path, name) in ``scene``; a test's first case of a
        new scene closes its last scene (the cases come scene by scene: ``pytest_generate_tests``)."""
        entry = self.cutoffs.setdefault(test, [cutoff.KindCutoff(self.kind_timeouts), None, None])
        if entry[1] != scene:
            if entry[2] is not None:
                entry[2].close()
            entry[1], entry[2] = scene, entry[0].scene(scene)
        return entry[2]

    def first(self, key) -> bool:
        """Whether ``key`` (module path, test[, effects]) comes for the first time (and note it)."""
        new = key not in self.warmed
        self.warmed.add(key)
        return new

    def close(self):
        self.worker.close()


def pytest_unconfigure(config):
    state = config.stash.get(_STATE, None)
    if state is not None:
        state.close()


def _job(item):
    """What the worker needs to run ``item``: ``(path, module name, qualname, is method, pickled
    arguments)``, or ``(None, why not)``."""
    fn = getattr(item.obj, "__func__", item.obj)
    if inspect.iscoroutinefunction(fn) or inspect.isasyncgenfunction(fn):
        return None, "it is an async test"
    if "<locals>" in fn.__qualname__:
        return None, "it is defined inside a function"
    args = {a: item.funcargs[a] for a in item._fixtureinfo.argnames}
    bound = sorted(set(args) & _HERE)
    if bound:
        return None, f"its fixture(s) {', '.join(bound)} act on this process"
    try:
        blob = pickle.dumps(args)
    except Exception as exc:  # noqa: BLE001 -- any object that does not pickle
        bad = [a for a, value in args.items() if not _pickles(value)]
        return None, f"its argument(s) {', '.join(bad) or '?'} do not pickle ({type(exc).__name__})"
    return (item.module.__file__, item.module.__name__, fn.__qualname__, item.cls is not None, blob), None


def _pickles(value) -> bool:
    try:
        pickle.dumps(value)
        return True
    except Exception:  # noqa: BLE001
        return False


@pytest.hookimpl(tryfirst=True)
def pytest_pyfunc_call(pyfuncitem):
    case = pyfuncitem.funcargs.get("golden_case")
    if not isinstance(case, _Checked):
        return None
    config = pyfuncitem.config
    if _STATE not in config.stash:
        config.stash[_STATE] = _Session(config.getoption("golden_timeout"), config.getoption("golden_dir"),
                                        config.getoption("golden_kind_timeouts"))
    state = config.stash[_STATE]
    test = (pyfuncitem.module.__file__, pyfuncitem.originalname)
    cut = state.scene_cut(test, case.scene)
    reason = cut.reason(case.kind, not case.band)
    if reason is not None:           # the per-kind cut-off: a failure, not a silent skip
        pytest.fail(f"{case.id} [{case.kind}]: {reason}", pytrace=False)
    job, why = (None, "--golden-in-process") if config.getoption("golden_in_process") else _job(pyfuncitem)
    if job is not None and job[0] not in state.here and _in_worker(state, job, case, cut):
        return True
    budget = max(state.budget, runner.FIRST_CALL_TIMEOUT) if state.first((*test, case.effects)) else state.budget
    why = state.here.get(job[0], why) if job is not None else why
    if why != "--golden-in-process" and state.first(test):        # once per test function
        pyfuncitem.warn(pytest.PytestWarning(f"golden_case: {pyfuncitem.originalname} runs in this process "
                                             f"({why}); its time budget is checked after it returns"))
    if inspect.iscoroutinefunction(pyfuncitem.obj):
        return None                                  # pytest's own handling of async tests
    t0 = time.perf_counter()
    pyfuncitem.obj(**{a: pyfuncitem.funcargs[a] for a in pyfuncitem._fixtureinfo.argnames})
    took = time.perf_counter() - t0
    cut.record(case.kind, not case.band, took > budget)
    if took > budget:
        pytest.fail(_timeout(case, budget, f"it took {took:.3g} s; in process the budget is checked after the "
                                           "test"), pytrace=False)
    return True


def _timeout(case, budget, how) -> str:
    from cross_check.score.golden import timeout_message
    return timeout_message(case.id, case.kind, budget, how)


def _warm_up(state, job, case):
    """The first time a test meets a set of effects (a JIT may compile a new code path), run it
    within ``runner.FIRST_CALL_TIMEOUT`` on a case with those effects that neither sticks nor
    chatters (``golden.warmup_case``), its outcome thrown away, so the case itself gets its plain
    budget whatever it is (the scorer's ``runner.warm_up``)."""
    if not state.first((job[0], job[2], case.effects)):
        return
    from cross_check.score.golden import warmup_case

    warm = warmup_case(case.effects, state.golden_dir)
    if warm is None:          # no case with these effects in the data: the case runs cold
        return
    args = pickle.loads(job[4])
    args["golden_case"] = _Checked(warm)
    try:
        state.worker.call(_RUN, *job[:4], pickle.dumps(args), budget=max(state.budget, runner.FIRST_CALL_TIMEOUT))
    except (isolate.CallTimeout, isolate.WorkerDied, isolate.RemoteError):
        pass


def _in_worker(state, job, case, cut) -> bool:
    """Run ``job`` in the session's worker and turn its outcome into this test's (noted by the
    scene's cut-off ``cut``); ``False`` if its module does not import there (the test then runs
    here)."""
    path, name = job[0], job[1]
    worker, budget = state.worker, state.budget
    if path not in state.imported:
        worker.setup.append((_IMPORT, (path, name)))        # every fresh process imports it first
        state.imported.add(path)
        try:
            worker.call(_IMPORT, path, name, budget=worker.setup_budget)
        except (isolate.RemoteError, isolate.CallTimeout, isolate.WorkerDied) as exc:
            worker.setup.remove((_IMPORT, (path, name)))
            state.here[path] = f"its module does not import in a worker process: {exc}"
            return False
    _warm_up(state, job, case)
    failed, timed_out = None, False
    try:
        (status, text, out, err), _ = worker.call(_RUN, *job, budget=budget)
    except isolate.CallTimeout:
        failed, timed_out = _timeout(case, budget, "the worker process was stopped"), True
    except isolate.WorkerDied as exc:
        failed = f"{case.id} [{case.kind}]: the worker process died during the test ({exc})"
    except isolate.RemoteError as exc:
        failed = f"{case.id} [{case.kind}]: the worker could not run the test: {exc}\n{exc.traceback}"
    cut.record(case.kind, not case.band, timed_out)
    if failed is not None:                 # raised here, not in the handler: no chained traceback
        pytest.fail(failed, pytrace=False)
    sys.stdout.write(out)
    sys.stderr.write(err)
    if status == "passed":
        worker.warmups[path] = (_RUN, job)
    elif status == "skipped":
        pytest.skip(text)
    elif status == "xfailed":
        pytest.xfail(text)
    else:
        pytest.fail(text, pytrace=False)
    return True


# --- the worker process's side -------------------------------------------------------------
_MODULES: dict = {}


def worker_import(path: str, name: str) -> bool:
    """Import the test module at ``path`` (as ``name`` where that is the same file, else from
    the path) in the worker."""
    module = sys.modules.get(name)
    if module is None or not _same(getattr(module, "__file__", None), path):
        try:
            module = importlib.import_module(name)
        except ImportError:
            module = None
        if module is None or not _same(getattr(module, "__file__", None), path):
            spec = importlib.util.spec_from_file_location(name, path)
            module = importlib.util.module_from_spec(spec)
            sys.modules[name] = module
            spec.loader.exec_module(module)
    _MODULES[path] = module
    return True


def _same(a, b) -> bool:
    try:
        return a is not None and os.path.samefile(a, b)
    except OSError:
        return False


def worker_run(path, name, qualname, is_method, blob):
    """Run one test function in the worker -> ``(status, text, stdout, stderr)``; ``status``:
    ``passed`` | ``skipped`` | ``xfailed`` | ``failed`` (``text``: the reason or the traceback)."""
    if path not in _MODULES:
        worker_import(path, name)
    out, err = io.StringIO(), io.StringIO()
    try:
        kwargs = pickle.loads(blob)
        target = _MODULES[path]
        parts = qualname.split(".")
        for i, part in enumerate(parts):
            target = getattr(target, part)
            if i == 0 and is_method:
                target = target()                    # a fresh instance per test, as pytest makes
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            target(**kwargs)
    except pytest.skip.Exception as exc:
        return "skipped", exc.msg, out.getvalue(), err.getvalue()
    except pytest.xfail.Exception as exc:
        return "xfailed", exc.msg, out.getvalue(), err.getvalue()
    except BaseException as exc:  # noqa: BLE001 -- every outcome goes back to the session
        tb = exc.__traceback__.tb_next or exc.__traceback__      # from the test's own frame on
        head = "".join(traceback.format_exception_only(type(exc), exc)).strip()    # pytest's summary line
        return ("failed", head + "\n\n" + "".join(traceback.format_exception(type(exc), exc, tb)),
                out.getvalue(), err.getvalue())
    return "passed", "", out.getvalue(), err.getvalue()
