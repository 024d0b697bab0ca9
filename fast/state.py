"""The record of one state in the compiled loop: a float64 array ``st`` with named slots.

=========  ==================================================================================
slot       meaning
=========  ==================================================================================
T0, T0LO   start time of the current flight segment (double-double)
X0, X0LO   position at the segment start (double-double: a chain of events within a period
           is never rounded to float64 between its links)
V0, V0LO   velocity at the segment start (double-double)
S          flight sign s (the sign of the velocity on the segment; +1 from rest)
SN0, SN0LO sin(w t0) at the segment start (double-double)
CS0, CS0LO cos(w t0) at the segment start (double-double)
D0         distance to the wall ahead at the start, ``s (W_s - x0)`` (from the double-double
           position: exact to relative rounding even a bounce height above a wall)
TT         trial time of the certified event search (float64)
C1, C2     certified ends: no root of the wall (C1) or velocity (C2) function in [T0, C_i)
P1, P2     the functions' predicted crossings at their last analysis (inf: none); a function
           whose certificate covers a trial is not analysed again there (``fast.roots``)
SPEC       1 while the trial is speculative (beyond min(C1, C2))
NFAIL      failed speculations on this segment (after 2 the trials stay within the
           certified ends)
NIT        search rounds on this segment (bounded by ``fast.loop.MAX_SEGMENT_ROUNDS``)
TLAST      the time of the last event, NSAME the events in a row at that very time
CHN        impacts in the current run at one wall, with the wall's sign (chatter count)
ZV         1 once the velocity has been zero on [0, t_end] (Omega_dissip)
NEV        events so far (the budget ``max_events`` bounds it)
J11..J22   Phi' so far, row-major (the product of the paper's Table 1 matrices)
XF, VF     the final state, once the state is finished
CAP        the capacity (rows) of the state's event buffer
PATHS      the code paths the state took (``PATH_*`` bits: what its scene's effects called for)
=========  ==================================================================================

The event log of the state goes to a second buffer ``ev`` of ``CAP`` rows of 6 (kind, t,
x, v, v_before, count; ``CAP = 0`` without a log), which ``fast.loop.run_range`` copies
into the caller's log.  The compiled functions get ``P``, ``st`` and ``ev`` as raw data
pointers (``fast.jit.data_pointer``): no reference counting on the hot path.

One record per state, reused for the next state of the same chunk; nothing in it depends
on another state.
"""
from __future__ import annotations

(T0, T0LO, X0, X0LO, V0, V0LO, S, SN0, SN0LO, CS0, CS0LO, D0, TT, C1, C2, SPEC, NFAIL, NIT,
 NSAME, CHN, ZV, NEV, J11, J12, J21, J22, XF, VF, P1, P2, CAP, TLAST, PATHS) = range(33)
SIZE = 33

#: event codes of the search (what the root of ``fast.roots.plan`` is)
NONE, IMPACT, VZERO, ATWALL = 0, 1, 2, 3
#: event kinds of the log (``fast.KINDS``, the same names as ``reference``)
KINDS = ("impact", "turn", "stick", "slip", "contact", "chatter", "release")
K_IMPACT, K_TURN, K_STICK, K_SLIP, K_CONTACT, K_CHATTER, K_RELEASE = range(7)
#: code paths (bits of ``PATHS``): friction's turn/stick logic, the summed chatter tail, the
#: damped flight, rest on a wall, restitution's impact law
PATH_FRICTION, PATH_CHATTER, PATH_DAMPED, PATH_WALL, PATH_RESTITUTION = 1, 2, 4, 8, 16
PATH_NAMES = {PATH_FRICTION: "friction", PATH_CHATTER: "chatter", PATH_DAMPED: "damped flight",
              PATH_WALL: "wall contact", PATH_RESTITUTION: "restitution"}
