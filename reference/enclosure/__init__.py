"""Enclosures: the reference's numbers as theorems (ball arithmetic, python-flint's arb).

``enclose_map(scene, x, v, *, periods=1, x_radius=0, v_radius=0)`` re-proves the point
integrator's itinerary for every start state of a box and returns balls that provably
contain ``Phi^k`` and ``(Phi^k)'`` (``reference.enclosure.maps``); ``prove_periodic`` turns
that into a computer-assisted proof of a periodic orbit, ``prove_segment`` of a segment of
fixed points (the no-impact orbits, never isolated) (``reference.enclosure.orbits``).

What is proved, and what is not
-------------------------------
* Proved, for the scene's *exact* parameters and every start in the box: the itinerary (the
  kinds of the events in order), each event time in its ball, no other event, and ``Phi^k``,
  ``(Phi^k)'`` in their balls.  The model is the one of ``reference.integrator``: Filippov
  sticking, the reset ``v+ = -e v-``, chatter as the accumulation of infinitely many impacts
  followed by wall contact.  Under position forcing (``F cos(k x) cos(w t)``, damping too) the
  flights have no closed form: each is a validated Taylor flight (``lohner``: a Picard box
  verified to contract, the Lagrange remainder over it, a Lohner QR frame across steps, the
  flow derivative from the variational equations), and rests hold where
  ``|F cos(k x) cos(w t)| <= f`` is proved at the rest's ``x``.  There ``Phi'`` is enclosed
  to about half the working precision (~1e-48 at 320 bits), ``Phi`` to all of it.
* Not proved: a start on a grazing or a tangency (no box fixes the itinerary there), and the
  *nonlinear* stability of a neutral centre (elliptic multipliers are proved; stability
  needs KAM-type arguments).  A chatter accumulation time is enclosed
  to ~1e-7..1e-12 T only (the walk follows bounces in absolute coordinates while it can, then
  bounds the tail on both sides); the map does not depend on it.

Over parameter boxes
--------------------
A :class:`~reference.enclosure.params.ParamBox` (``F, f, omega, l, r, restitution, damping``,
each a number or an exact pair ``(lo, hi)``) in place of the scene makes both statements hold
for every parameter of the box at once: the same itinerary, the Krawczyk inclusion, the
multipliers (``boxes``: the parametric Krawczyk operator in multiple-shooting form,
``shooting``; ``sensitivity`` and ``centred``: derivatives in the parameters and mean-value
enclosures that keep a wide box tight).  ``impacts`` proves the paper's two-impact orbits in
impact coordinates (the impact phases and speeds as unknowns, closed-form flights, ``dual``
numbers for the derivatives): no ``1/V`` blow-up where the impacts are slow.  ``continuation`` covers
a box by sub-boxes and an interval by a chain of boxes (rigorous continuation).  A point box
is its scene: the point API is unchanged.

Modules: ``balls`` (precision, conversions, the scene as balls), ``motion`` (flights and
rests on balls, event functions), ``series`` (the position-forced flight's Taylor
coefficients on balls), ``picard`` (a priori boxes), ``lohner`` (validated flights, one start
tracked), ``handoff`` (a flight's set through an event), ``certify`` (exclusion and Krawczyk
roots), ``walk`` (the itinerary, event by event), ``tails`` (chatter tails), ``maps`` (``enclose_map``),
``orbits`` (``prove_periodic``); over parameter boxes ``params``, ``sensitivity``, ``centred``,
``shooting``, ``boxes``, ``dual``, ``impacts``, ``continuation``, ``branches``; the
invariance of ``Omega_dissip`` (``Phi(Omega_dissip)`` in ``Omega_dissip``): ``rest`` (the
return-to-rest certificate of a box of rest states) and ``invariance`` (the cover, and the
counterexample certificate over ``[0, 2T]``).
"""
from reference.enclosure.certify import Unproved
from reference.enclosure.impacts import prove_two_impacts
from reference.enclosure.maps import MapEnclosure, enclose_map
from reference.enclosure.orbits import OrbitProof, prove_periodic, prove_segment
from reference.enclosure.params import ParamBox

__all__ = ["enclose_map", "MapEnclosure", "prove_periodic", "prove_segment", "OrbitProof", "Unproved",
           "ParamBox", "prove_two_impacts"]
