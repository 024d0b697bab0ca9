"""Only what the scene calls for: which code paths each scene takes (issue 6).

A ``sys.setprofile`` hook records every Python function of ``reference`` (and of mpmath's
ODE module) that runs while a scene is integrated; ``fast``'s compiled loop records the code
paths it takes as bits.  The assertions say which paths a scene must reach and which it
must never reach:

* frictionless, elastic, undamped: no stick/turn logic, no chatter acceleration, no damped
  or Taylor flight;
* friction, on a sticking orbit: the stick/turn logic runs;
* restitution ``e < 1`` with ``f = 0``: the chatter acceleration runs (no friction logic);
* damping: the damped closed-form flight, never a numerical ODE solver (mpmath.odefun,
  the Taylor flight);
* position forcing: the Taylor flight; the scenes without it never reach it.
"""
import os
import sys

import numpy as np

import reference
from fast import api, batch, state
from reference import Scene

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
WATCHED = {os.path.join(ROOT, "reference"): "reference"}
ODES = os.path.join(os.path.dirname(sys.modules["mpmath"].__file__), "calculus", "odes.py")

ELASTIC = Scene(F=1, f=0, omega=1, l=0, r="0.8")
STICKING = Scene(F=1, f="0.5", omega=1, l=0, r=20)
RESTITUTION = Scene(F=1, f=0, omega=1, l=0, r=1, restitution="0.5")
DAMPED = Scene(F=1, f="0.1", omega=1, l=0, r="0.8", damping="0.3")
XPOT = Scene(F=1, f="0.1", omega="2*pi", l=-1, r=1, wavenumber="pi/2")

# (scene, states) whose runs are recorded; each state is (x, v)
RUNS = {
    "elastic": (ELASTIC, [("0.3", "0.5"), ("0.4", "0"), ("0", "0"), ("0.8", "0"), ("0.79", "0.3")]),
    "sticking": (STICKING, [("10", "0.1"), ("5", "0")]),
    "restitution": (RESTITUTION, [("1", "0.1"), ("0.5", "0.2")]),
    "damped": (DAMPED, [("0.3", "0.5"), ("0.7", "0")]),
    "xpot": (XPOT, [("0.3", "2.5"), ("0", "0.5")]),
}


def _record(fn):
    """Run ``fn()``; return the set of ``"module:qualname"`` of watched functions called."""
    seen = set()

    def hook(frame, event, arg):
        if event != "call":
            return
        path = frame.f_code.co_filename
        if path == ODES:
            seen.add("mpmath.odes:" + frame.f_code.co_qualname)
            return
        for prefix, package in WATCHED.items():
            if path.startswith(prefix):
                module = os.path.splitext(os.path.basename(path))[0]
                seen.add(f"{package}.{module}:{frame.f_code.co_qualname}")

    sys.setprofile(hook)
    try:
        fn()
    finally:
        sys.setprofile(None)
    return seen


_CACHE = {}


def reference_paths(name):
    if ("reference", name) not in _CACHE:
        scene, states = RUNS[name]

        def run():
            for x, v in states:
                reference.trajectory(scene, x, v, 2 * scene.period, dps=20)
        _CACHE["reference", name] = _record(run)
    return _CACHE["reference", name]


def reached(paths, *names):
    return {n for n in names if any(p == n or p.startswith(n + ".") for p in paths)}


def reached_module(paths, module):
    return {p for p in paths if p.split(":")[0] == module}


FRICTION_LOGIC = ("reference.integrator:_Machine.velocity_zero",
                  "reference.integrator:_Machine.slip_time",
                  "reference.events:VelocityZero.__init__")
CHATTER_ACCELERATION = ("reference.chatter:wall_bounce", "reference.chatter:BounceRun.extrapolate",
                        "reference.chatter:BounceRun.estimate")


def test_reference_elastic_frictionless_undamped_takes_the_base_path_only():
    paths = reference_paths("elastic")
    assert reached(paths, "reference.flows:BaseFlight.evaluate")
    assert not reached(paths, *FRICTION_LOGIC, *CHATTER_ACCELERATION)
    assert not reached(paths, "reference.flows:DampedFlight")
    assert not reached_module(paths, "reference.taylor")
    assert not reached_module(paths, "mpmath.odes")


def test_reference_friction_reaches_stick_and_turn_logic():
    paths = reference_paths("sticking")
    log = reference.trajectory(STICKING, "10", "0.1", 2 * STICKING.period, dps=20)
    assert {"stick", "slip"} <= {e.kind for e in log}
    assert reached(paths, *FRICTION_LOGIC) == set(FRICTION_LOGIC)
    assert not reached_module(paths, "reference.taylor")


def test_reference_restitution_reaches_chatter_acceleration():
    paths = reference_paths("restitution")
    log = reference.trajectory(RESTITUTION, "1", "0.1", 2 * RESTITUTION.period, dps=20)
    assert "chatter" in {e.kind for e in log}
    assert reached(paths, *CHATTER_ACCELERATION) == set(CHATTER_ACCELERATION)
    assert not reached(paths, *FRICTION_LOGIC)
    assert not reached_module(paths, "reference.taylor")


def test_reference_damping_is_closed_form_without_an_ode_solver():
    paths = reference_paths("damped")
    assert reached(paths, "reference.flows:DampedFlight.evaluate")
    assert not reached(paths, "reference.flows:BaseFlight.evaluate")
    assert not reached_module(paths, "reference.taylor")
    assert not reached_module(paths, "mpmath.odes")


def test_reference_position_forcing_reaches_taylor_and_only_it():
    paths = reference_paths("xpot")
    assert reached(paths, "reference.taylor:TaylorFlight.evaluate")
    assert not reached(paths, "reference.flows:BaseFlight.evaluate", "reference.flows:DampedFlight")
    for name in ("elastic", "sticking", "restitution", "damped"):
        assert not reached_module(reference_paths(name), "reference.taylor"), name


# --- fast: the same proof on its compiled loop ---------------------------------------------
# The compiled loop records, per state, the code paths it took (``fast.state.PATH_*``); the
# engine is chosen per scene (``fast.api._engine``: the numerical flights of ``fast.ode``
# only under position forcing).


def fast_paths(name):
    """``(engine name, set of path names)`` of the RUNS of ``name`` over two periods."""
    if ("fast", name) not in _CACHE:
        scene, states = RUNS[name]
        x = np.array([float(s[0]) for s in states])
        v = np.array([float(s[1]) for s in states])
        engine, P = api._engine(scene)
        bits = 0
        for _ in range(2):
            res = batch.run(engine, P, x, v, P[engine.p.T], P[engine.p.T_LO],
                                 max_events=10_000)
            bits |= int(np.bitwise_or.reduce(res.paths))
            x, v = res.x, res.v
        names = {n for b, n in state.PATH_NAMES.items() if bits & b}
        _CACHE["fast", name] = (engine.__name__, names)
    return _CACHE["fast", name]


def test_fast_elastic_frictionless_undamped_takes_the_base_path_only():
    engine, paths = fast_paths("elastic")        # two of its states rest on a wall at t = 0
    assert engine == "fast.loop"
    assert not paths & {"friction", "chatter", "damped flight", "restitution"}, paths


def test_fast_friction_reaches_stick_logic():
    engine, paths = fast_paths("sticking")
    assert engine == "fast.loop" and "friction" in paths
    assert not paths & {"chatter", "damped flight", "restitution"}, paths


def test_fast_restitution_reaches_chatter_tail():
    engine, paths = fast_paths("restitution")
    assert engine == "fast.loop" and {"chatter", "restitution"} <= paths
    assert "friction" not in paths and "damped flight" not in paths, paths


def test_fast_damping_is_closed_form_without_an_ode_solver():
    """Damping keeps flights closed-form: the damped flight, never fast.ode's solver."""
    engine, paths = fast_paths("damped")
    assert engine == "fast.loop" and "damped flight" in paths


def test_fast_position_forcing_takes_the_ode_engine_and_only_it():
    assert fast_paths("xpot")[0] == "fast.ode"
    for name in ("elastic", "sticking", "restitution", "damped"):
        assert fast_paths(name)[0] == "fast.loop", name
