"""MuJoCo 3.x as a peer: the oscillator as a robotics user builds it, a one-DoF slide joint,
stepped at a fixed time step (protocol: ``cross_check.score``; the map only).

How the library is used
-----------------------
The model (MJCF, built per scene and time step)::

    <option timestep="dt" gravity="0 0 0" integrator="Euler"/>
    <body> <joint type="slide" limited="true" range="l r" frictionloss="f" damping="c"
                  solreflimit="-K -1e-12" solimplimit="0.9999 0.9999 0.001"
                  solreffriction="2dt 1" solimpfriction="0.9999 0.9999 0.001"/>
           <inertial mass="1" .../> </body>

* the **walls** are the joint's limited ``range``; the **friction** is the joint's
  ``frictionloss`` (a Coulomb friction of size ``f``); viscous **damping** is the joint's
  ``damping``; the body's mass is 1;
* the **forcing** ``F cos(w t)`` goes into ``qfrc_applied``, sampled at the midpoint of each
  step (held constant over a step, a force sampled at the step's start costs one digit: measured
  on ``fig:many:2pi/f=0.2``, median 5.2 against 6.0 digits at ``dt = 1e-5``).  The starts are
  stepped together by ``mujoco.rollout`` (open-loop controls in C, ``control_spec =
  mjSTATE_QFRC_APPLIED``), in chunks of ``CHUNK`` steps so that the state history it writes
  stays small;
* the period ``T = 2 pi / w`` is cut into ``n = ceil(T / dt)`` equal steps (``dt' = T/n <= dt``),
  so that the last step ends exactly at ``t = T``.

Where MuJoCo's soft constraints depart from the model (why it grades Phi only, to a few
digits, and declares neither restitution nor position forcing):

* **impacts are springs**: a joint limit is a soft constraint: the body passes the wall and a
  reference acceleration ``-K (x - r) - B v`` pushes it back.  With MuJoCo's defaults
  (``solref = 0.02 1``: critically damped over 0.02 s) an impact loses almost all its speed.
  To make it as elastic as possible the limit uses the direct form ``solref = (-K, -B)`` with
  ``B = 1e-12`` (MuJoCo needs both negative; ``B = 0`` is read as "mixed format" and replaced by
  the default) and ``K = (pi / (10 dt))^2``: an undamped half-oscillation of ten steps.  The
  number of steps trades the spring's two errors, measured on a free bounce (``v = 1``, no
  forcing or friction): the semi-implicit Euler step over a stiff spring returns the speed too
  large by 0.2% at ten steps (1.6% at five, 9% at three, 47% at two; 0.025% at twenty), while
  the time spent in the wall shifts the position by up to ~``10 dt |v|`` (twenty steps: twice
  that).  The ``timeconst`` form with a small damping ratio is stiffer still and blows up (MuJoCo
  then resets the state to zero with a warning, which it also appends to ``MUJOCO_LOG.TXT`` in the
  working directory; ``step`` checks the time and raises).  ``solimp``
  near 1 (0.9999) makes the constraint near-hard.  So **restitution** ``e < 1`` is not exact (it
  would be a damping ratio) and is not declared; a grazing impact, a chatter run and an impact
  at ``t = kT`` are smeared over the spring's ten steps;
* **sticking is regularised**: ``frictionloss`` is a soft constraint too: the friction force is
  clamped to ``[-f, f]`` and drives ``v`` to zero over the time constant ``2 dt``
  (``solreffriction``; MuJoCo clamps any smaller one), so a stuck body creeps and a stick ends
  when the force exceeds ``f`` only to within that regularisation;
* **position forcing** ``F cos(k x) cos(w t)`` depends on the state, which open-loop controls
  cannot follow (a Python callback per step would be ~5 us x 10^6 steps): not declared;
* the semi-implicit Euler step is first order: at best ~1 digit per factor 10 in ``dt``.

No events (MuJoCo has no event detection: its constraints act at step ends) and no Jacobian.
Settings: ``dt`` in ``[1e-6, 1e-2]`` (the league runs 1e-3, 1e-4, 1e-5).
"""
from __future__ import annotations

import math

import numpy as np

EFFECTS = frozenset({"walls", "forcing", "friction", "damping"})
#: steps per rollout call (the rollout writes the state after every step: chunks keep it small)
CHUNK = 20_000
#: steps of the wall spring's half-oscillation (K = (pi / (CONTACT_STEPS dt))^2)
CONTACT_STEPS = 10
#: impedance of the soft constraints (near 1: near-hard)
SOLIMP = "0.9999 0.9999 0.001"


def mjcf(params: dict, dt: float) -> str:
    """The MJCF text of the slide joint for ``params`` at time step ``dt`` (module docstring)."""
    K = (math.pi / (CONTACT_STEPS * dt)) ** 2
    p = params
    return f"""<mujoco model="vibro-impact slide">
  <option timestep="{dt!r}" gravity="0 0 0" integrator="Euler"/>
  <worldbody>
    <body>
      <joint name="slide" type="slide" axis="1 0 0" limited="true" range="{p['l']!r} {p['r']!r}"
             frictionloss="{p['f']!r}" damping="{p['damping']!r}" armature="0"
             solreflimit="{-K!r} -1e-12" solimplimit="{SOLIMP}"
             solreffriction="{2 * dt!r} 1" solimpfriction="{SOLIMP}"/>
      <inertial pos="0 0 0" mass="1" diaginertia="1 1 1"/>
    </body>
  </worldbody>
</mujoco>"""


class MujocoSlideAdapter:
    """MuJoCo's slide joint at time step ``dt`` (module docstring).  Pickles as its settings."""

    effects = EFFECTS

    def __init__(self, dt: float = 1e-4):
        if not (isinstance(dt, (int, float)) and 1e-6 <= dt <= 1e-2):
            raise ValueError(f"dt must be a number of seconds in [1e-6, 1e-2], got {dt!r}")
        self.dt = float(dt)
        self.name = f"mujoco dt {dt:.0e}"

    def step(self, params, x, v, periods):
        import mujoco
        from mujoco import rollout

        if params.get("wavenumber") is not None or params["restitution"] != 1.0:
            raise ValueError("mujoco slide: position forcing and restitution e < 1 are not modelled")
        T = 2 * math.pi / params["omega"]
        n = math.ceil(T / self.dt * (1 - 1e-12))
        model = mujoco.MjModel.from_xml_string(mjcf(params, T / n))
        data = mujoco.MjData(model)
        spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
        state = np.zeros((len(x), mujoco.mj_stateSize(model, spec)))
        for i, (a, b) in enumerate(zip(x, v)):
            mujoco.mj_resetData(model, data)
            data.qpos[0], data.qvel[0] = a, b
            mujoco.mj_getState(model, data, state[i], spec)
        mid = (np.arange(n) + 0.5) * (T / n)          # the forcing at each step's midpoint
        force = (params["F"] * np.cos(params["omega"] * mid))[None, :, None]
        for _ in range(periods):
            time0 = state[:, 0].copy()
            for a in range(0, n, CHUNK):
                out, _ = rollout.rollout(model, data, state, force[:, a:a + CHUNK],
                                         control_spec=mujoco.mjtState.mjSTATE_QFRC_APPLIED)
                state = out[:, -1].copy()
            if not np.allclose(state[:, 0] - time0, T, rtol=1e-9):
                raise RuntimeError(f"mujoco slide: the rollout stopped early (a reset after an unstable step?) "
                                   f"at times {state[:, 0].tolist()[:5]}")
        qpos, qvel = _slots(model, spec)
        return state[:, qpos].copy(), state[:, qvel].copy()


def _slots(model, spec):
    """The columns of ``qpos[0]`` and ``qvel[0]`` in a FULLPHYSICS state vector (time, qpos, qvel, ...)."""
    return 1, 1 + model.nq


__all__ = ["EFFECTS", "MujocoSlideAdapter", "mjcf"]
