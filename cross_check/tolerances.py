"""The one table of tolerances, used by the tests and the reports alike.

Every entry says where its number comes from (precision, conditioning, event-time
sensitivity).  Comparisons follow numpy's ``assert_allclose`` convention: an error
counts as ``|actual - desired| <= atol + rtol * |desired|`` with the reference as
``desired``.  Nothing here is ever loosened to make a test pass: if a test fails, the
numerics or the code are wrong, and that is what gets fixed.
"""
from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Tol:
    """A tolerance with its justification."""

    rtol: float
    atol: float
    why: str


def dps_tol(dps: int, lost_digits: int = 5) -> float:
    """Agreement expected of a ``dps``-digit mpmath computation.

    ``lost_digits`` covers the event-time conditioning of a period with a handful of
    impacts and turning points: each event time is found to working precision, and the
    sensitivity of the state to an event time is at most ``|x''| <= F + f`` times the
    period, i.e. a few digits for the paper's scenes.
    """
    return 10.0 ** (-(dps - lost_digits))


#: float64 unit roundoff
EPS = 2.0 ** -52

TOLERANCES = {
    # --- reference against an independent high-precision computation -----------------
    "ref_map_dps50": Tol(
        rtol=0.0, atol=1e-30,
        why="issue 2 acceptance: 50 working digits minus up to 20 digits lost to "
            "event-time conditioning on the hardest states (grazing excluded)"),
    "ref_jacobian_dps50": Tol(
        rtol=0.0, atol=1e-20,
        why="issue 2 acceptance: the reflection term 2 F cos(w t*)/v(t*-) amplifies "
            "errors by 1/|v| near grazing; 30 digits of headroom"),
    # --- reference self-checks (tests/test_reference_*.py; owner: reference) -----------
    "ref_self_dps30": Tol(
        rtol=0.0, atol=1e-25,
        why="reference at dps 30 against dps 50 on a few periods: 30 digits, results rounded "
            "to 30 digits, minus dps_tol's 5 digits of event-time conditioning (|dPhi/dt_k| "
            "<= (F + f) T ~ 10 per event, a handful of events per period)"),
    "ref_fd_jacobian": Tol(
        rtol=1e-25, atol=1e-25,
        why="central differences of Phi at dps 80 with step h = 1e-30: truncation "
            "h^2 |Phi'''| / 6 ~ 1e-60 x (1/v-)^3, rounding 1e-80 / h = 1e-50; against the "
            "Table 1 product at dps 60; 1e-25 leaves >= 20 digits for 1/|v-| and event "
            "conditioning, and is still 10^25 times smaller than the effect of taking v+ "
            "instead of v- (an O(1) change of the lower-left entry)"),
    "ref_identity_dps40": Tol(
        rtol=0.0, atol=1e-32,
        why="metamorphic identities (energy balance, symmetry, translation, semigroup, time "
            "reversal) of reference runs at dps 40: each side carries 40 digits rounded, "
            "minus dps_tol's 5 digits of event conditioning, minus 3 for the amplification "
            "of a few periods (|Phi'| <~ 10^3 over the orbits used)"),
    # --- fast (float64) against reference at 50 digits --------------------------------
    "fast_one_period_max": Tol(
        rtol=1e-13, atol=1e-13,
        why="issue 3: a period has up to ~20 events each found to a few ulp; "
            "errors scaled by max(1, |value|)"),
    "fast_one_period_median": Tol(
        rtol=3e-15, atol=3e-15,
        why="issue 3: the typical state carries ~10 ulp of rounding over a period"),
    "fast_ten_period_ulp_factor": Tol(
        rtol=3.0, atol=0.0,
        why="issue 3: ten-period error within 3x the rounding floor: the larger of the "
            "spread of the exact map under a one-ulp move of the start (the one-ulp floor; "
            "chaos amplifies it by up to 1e7) and the error of the exact map rounded to "
            "float64 after every period (on neutral or contracting directions -- sticking, "
            "wall contact -- the one-ulp floor is below the half-ulp that every float64 "
            "output carries, so no float64 engine meets it there; the report gives both)"),
    # --- golden data (cross_check.golden; owner: cross_check front door) --------------
    "golden_self_agreement": Tol(
        rtol=1e-40, atol=1e-40,
        why="golden values are written with 40 significant digits from a dps-90 run; the "
            "dps-90 and dps-110 runs must agree to those 40 digits (errors scaled by "
            "max(1, |value|)): dps_tol(90, lost_digits=50) = 1e-40.  dps 90 was chosen when "
            "the reference's chatter accumulation time carried only ~dps/2 + 4 digits "
            "(measured on R=20, f=0.1: dps 60 -> 34, 90 -> 49); since reference commit "
            "71a882a it is good to working precision (dps 50 -> 51 digits), so the 50 digits "
            "are now margin; everything else loses at most the 20 ref_map_dps50 allows"),
    "golden_proved_agreement": Tol(
        rtol=1e-40, atol=1e-40,
        why="issue 33: a position-forced golden input's values may come from a dps-50 run "
            "instead of the dps-90 one, if its proof (192 bits, Phi' to the working precision: "
            "balls ~1e-47 wide) puts the true value of every written number within 1e-40 "
            "max(1, |value|) of it (Phi' within that times kappa): golden_self_agreement's "
            "40 digits, established by a proof in place of the dps-110 run's agreement"),
    "golden_reference_state": Tol(
        rtol=1e-30, atol=1e-30,
        why="reference at dps 50 against the 40-digit golden data: ref_map_dps50's 1e-30 "
            "(50 digits minus 20 for event-time conditioning), applied to Phi, event times "
            "and event states, scaled by max(1, |value|)"),
    "golden_reference_jacobian": Tol(
        rtol=1e-20, atol=1e-20,
        why="reference Jacobian at dps 50 against golden: ref_jacobian_dps50's 1e-20, but "
            "relative (max(1, |value|)): near grazing the entry 2A/v- is as large as 1e13 "
            "and carries the relative error of v-, not an absolute one"),
    "golden_reference_chatter_time": Tol(
        rtol=1e-30, atol=1e-30,
        why="the chatter accumulation time t_inf of the reference at dps 50 against golden: "
            "the same 1e-30 as golden_reference_state (since reference commit 71a882a t_inf "
            "is summed to working precision: 51 digits at dps 50, measured on R=20, f=0.1; "
            "before it carried ~dps/2 + 4 digits, which is why this entry exists apart)"),
    "golden_fast_phi_per_cond": Tol(
        rtol=1e-13, atol=1e-13,
        why="fast's Phi and event times against golden, error scaled by max(1,|value|) and "
            "divided by max(1, max |J_ij|) (golden Jacobian): the forward error of a "
            "backward-stable float64 integrator is the condition times its backward error; "
            "away from grazing |J| ~ 1-10 and this is fast_one_period_max; near grazing "
            "|J| ~ 2|A|/|v-| grows and so does the achievable error"),
    "golden_fast_chatter_time": Tol(
        rtol=1.5e-8, atol=1.5e-8,
        why="fast's chatter accumulation time: in float64 the late bounce times are "
            "near-tangential roots, accurate to sqrt(eps) ~ 1.5e-8 at best (the reference "
            "shows the same square-root loss: golden_reference_chatter_time)"),
    "golden_fast_jacobian_per_kappa": Tol(
        rtol=1e-13, atol=1e-13,
        why="fast Jacobian against golden, error scaled by max(1,|J_ij|) and divided by "
            "max(1, max|J|) kappa^2, kappa = max(1, max over impacts of (F/w)/|v-|).  "
            "max|J|: an error in one factor of the Table 1 product is carried by the rest of "
            "the product (measured worst without it: 2.6x the bound, 2pi f=0.01, |J| = 25; "
            "with it, 0.1x over all golden float64 inputs).  kappa^2: the saltation entry "
            "2A/v- carries the relative error of v-; near grazing the impact is a nearly "
            "tangential root located to dt ~ eps (F/w)/|v-|, so v- = |a| dt is off by "
            "eps (F/w)^2/|v-| (|a| <= F + f), a relative error eps kappa^2 (measured: v- = "
            "1e-6 gives 3e-4); 1e-13 is fast_one_period_max's bound for the rest"),
    # --- cross_check.agreement.compare ----------------------------------------------------------
    "compare_band_ulps": Tol(
        rtol=4.0, atol=0.0,
        why="near-grazing band: a state is in the band if its event itinerary changes when "
            "x or v moves by up to rtol (=4) ulps, the size of the rounding a float64 "
            "integrator makes in an event time over a period (fast_one_period_median ~10 "
            "ulp spread over ~3 events)"),
    # --- the paper's closed forms and claims (reference/paper.py, cross_check/paper/claims/) ---
    "paper_identity_dps50": Tol(
        rtol=0.0, atol=1e-40,
        why="closed forms of reference/paper.py at 50 digits: each identity (wall hit, "
            "reflection, periodicity, ODE residual by mpmath.diff at raised precision) is a few "
            "dozen operations on numbers <= ~1e2 (C T for R = 20), rounding ~1e-47; 1e-40 "
            "leaves 7 digits of headroom"),
    "paper_fd_jacobian_dps80": Tol(
        rtol=0.0, atol=1e-40,
        why="central differences with step 1e-25 at 80 digits: truncation O(h^2 |third "
            "derivative|) ~1e-50 x O(10), rounding O(eps |Phi| / h) ~1e-55 x 20 (eps = 1e-80)"),
    "paper_fold_dps50": Tol(
        rtol=0.0, atol=1e-20,
        why="at the fold f = 2F/pi the roots psi_{1,2} depend on sqrt(1 - (pi f/2F)^2): a "
            "rounding of 1e-50 in f moves them by ~sqrt(1e-50) = 1e-25; 1e-20 leaves headroom"),
    "claim_fixed_point": Tol(
        rtol=0.0, atol=1e-9,
        why="brief/acceptance: fixed points stated to 1e-9; reference Newton at 50 digits "
            "gives ~1e-30, float64 Newton (fast) ~1e-13 (fast_one_period_max amplified by "
            "|(Phi' - I)^-1| <= ~1e2 on the paper's non-degenerate fixed points)"),
    "claim_multiplier": Tol(
        rtol=0.0, atol=1e-8,
        why="brief/acceptance: multipliers to 1e-8; the Jacobian is evaluated at the fixed "
            "point refined to 1e-30 (reference) or ~1e-13 (fast); Table-1 entries scale as "
            "F/|v| <= ~1e1 on the paper's fixed points, so float64 gives ~1e-11"),
    "claim_threshold": Tol(
        rtol=0.0, atol=1e-9,
        why="brief/acceptance: thresholds (R*, f_crit) to 1e-8 or better; bisection/secant on "
            "a closed form or on the trace of a fixed point found to 1e-30 at 50 digits"),
    "claim_unit_det": Tol(
        rtol=0.0, atol=1e-9,
        why="Omega_pres test |det Phi'| = 1 in float64: det is a product of O(10) Table-1 "
            "matrices each exact to ~1e-14 relative; a turning point gives "
            "(|A|-f)/(|A|+f) <= 1 - 2f/(F+f), i.e. <= 1 - 1e-2 for the paper's f >= 0.005, "
            "so 1e-9 separates the classes with 7 decades to spare"),
    "claim_unit_det_clear": Tol(
        rtol=1e-6, atol=2.5e-10,
        why="the |det Phi'| a coarse map (fast's steps_per_period; verify.portrait.PORTRAIT_STEPS) "
            "settles a class with on its own: within atol (a quarter of claim_unit_det) of 1, or "
            "below 1 - rtol (Omega_dissip's dets are at most 1 - 2f/(F+f) after a turn, e^(-cT) "
            "or e per impact: far below); any other state is classed again on the default map. "
            "Measured on random position-forced scenes (issue 33): the coarse det strays from the "
            "default's by up to ~1e-9 where a period has hundreds of impacts (gap 0.2, omega 0.5), "
            "so a margin below claim_unit_det is needed, and by ~1e-10 elsewhere"),
    # --- position-dependent forcing flights: reference/taylor.py, fast/ode_flight.py ------
    "taylor_closed_form_dps50": Tol(
        rtol=0.0, atol=1e-45,
        why="Taylor flight with k = 0 against the closed-form flight at 50 digits: each step's "
            "truncation is proved below 2^-(prec+12), arithmetic runs at prec+32 bits, a unit "
            "time takes ~30 steps whose errors grow at most like exp(L t), L <= ~3: ~1e-52 "
            "for |x|, |v| <= ~10; dps_tol(50, lost_digits=5) leaves 7 digits of headroom"),
    "taylor_odefun_dps30": Tol(
        rtol=0.0, atol=1e-25,
        why="Taylor flight at 30 digits against mpmath.odefun at 40 digits (its own Taylor "
            "method, tolerance ~1e-40): the Taylor flight's error is ~1e-32 (as above at 30 "
            "digits); dps_tol(30, lost_digits=5)"),
    "taylor_identity_dps30": Tol(
        rtol=0.0, atol=1e-25,
        why="Liouville det = exp(-c t), energy balance (mpmath.quad of the dense output, "
            "Gauss-Legendre converging to ~1e-30 on an analytic integrand) and the jerk "
            "against mpmath.diff, at 30 digits: each is a few hundred operations on "
            "numbers <= 1e2 after a flight accurate to ~1e-32; dps_tol(30, lost_digits=5)"),
    "taylor_fd_jacobian_dps50": Tol(
        rtol=0.0, atol=1e-26,
        why="variational flight matrix against central differences with step 1e-15 at 50 "
            "digits: truncation h^2/6 |third derivative of the flow| ~1e-30 x O(1e2) (the "
            "flow's derivatives grow with k^3 |v|^3 over a unit time), rounding "
            "1e-50/1e-15 = 1e-35"),
    "ode_vs_taylor_flight": Tol(
        rtol=1e-13, atol=1e-13,
        why="fast DOP853 flight (128 steps per 2 pi / Lambda, order 8, compensated: "
            "fast.compensated) against the Taylor flight at 30 digits, for |v| <= 4 and up to "
            "one period, x, v and the flight matrix: measured ~1e-15 (before issue 33's "
            "compensation: order-8 local error (h Lambda)^9 with Lambda = max(w, k |v|, "
            "sqrt(F k)), h Lambda = 2 pi/96, plus ~1e2 ulp of rounding; the flight matrix is "
            "not compensated); 1e-13 is fast_one_period_max's budget for a flight.  Also the "
            "period Jacobian of fast.ode's event loop against differences of the reference map "
            "(Table 1's event matrices are a few exact float products on top)"),
    "ode_event_residual": Tol(
        rtol=0.0, atol=1e-13,
        why="the reference event function (wall distance or velocity, from the Taylor flight) "
            "at the fast event time: the root is polished on the dense output to a few ulp "
            "and moved by a Newton step from a compensated step onto it (fast.compensated."
            "event), the state's error is that of ode_vs_taylor_flight; measured in g's own "
            "units, so free of the 1/|g'| conditioning of the event time"),
}


def tol(name: str) -> Tol:
    """Look a tolerance up by name (KeyError lists the known names)."""
    try:
        return TOLERANCES[name]
    except KeyError:
        raise KeyError(f"unknown tolerance {name!r}; known: {', '.join(sorted(TOLERANCES))}") from None

# --- figures (cross_check/paper/figures/, issue 7) ------------------------------------------
TOLERANCES.update({
    "fig_birkhoff_regular": Tol(
        rtol=1e-3, atol=0.0,
        why="issue 7 orbit classifier: an orbit is regular when the weighted Birkhoff averages of "
            "cos(pi (x-l)/R) and v^2 over its two halves agree to rtol relative to the observable's "
            "spread. Phi is only piecewise smooth (the lifted force jumps at the walls), so on an "
            "invariant curve they converge like a power of 1/N, not faster; measured on the r = 20 "
            "frictionless grid (fig:nofriction d): invariant curves agree to 3.0-4.2 digits at N = 60 "
            "and 3.2-6 at N = 200 iterates per half, chaotic orbits to <= 2.2 and <= 2.7 digits "
            "(~N^(-1/2)); 3 digits separates the two at both resolutions"),
    "fig_fold_f": Tol(
        rtol=0.0, atol=1e-8,
        why="issue 7 fold by continuation vs the closed form f/F = 2/pi: fixed points solved to "
            "1e-11 (Newton), trace of Phi' to ~1e-10; the branch is f = f* - c s^2 near the fold, "
            "so bisection on tr = 2 in arclength s to 1e-13 leaves an f error far below 1e-8"),
    "fig_resonance_R": Tol(
        rtol=0.0, atol=1e-4,
        why="issue 7 3:1 resonance tr Phi' = -1 vs the paper's R* ~ 0.8932 (4 decimals): the "
            "computed R* = 0.893300 (fast and an independent time-stepped map agree to 1e-8) rounds "
            "to 0.8933, so the paper truncated; a truncated 4-decimal value is within one unit of the "
            "last digit below the true value, 0 <= R* - 0.8932 < 1e-4"),
})

# --- fast (float64 engine, issue 3): its own property tests ----------------------------
TOLERANCES.update({
    "fast_metamorphic": Tol(
        rtol=2e-12, atol=2e-12,
        why="issue 3 properties comparing two float64 runs over <= 2 periods (symmetry, "
            "semigroup, wall translation): each run is within fast_one_period_max (1e-13) of "
            "the exact map per period and a moved input enters amplified by |Phi'|; the "
            "tests scale this tolerance by (1 + |Phi'|) of the state, so 2e-12 leaves ~10x "
            "headroom over the 1e-13 per period of two runs"),
    "fast_energy_balance": Tol(
        rtol=1e-12, atol=1e-12,
        why="issue 3 energy balance over one period, dE = work of F cos(w t) - f * distance: "
            "each of <= ~30 event times carries ~eps T, the work integrand |A v| <= F vmax "
            "turns that into ~30 eps F vmax T ~ 1e-13 for the paper's scenes; 30-point "
            "Gauss-Legendre on each flight segment adds < 1e-15; scaled by (1 + vmax^2)"),
    "fast_jacobian_fd": Tol(
        rtol=1e-6, atol=1e-6,
        why="issue 3 Phi' vs central differences with step d = 1e-6 on states whose event "
            "itinerary is the same at +-d: truncation |Phi'''| d^2 ~ 1e-12 |Phi'''| plus "
            "rounding ~1e-13 / d = 1e-7 (one-period error of fast_one_period_max over d); "
            "scaled by max(1, |Phi'|)"),
    "fast_jacobian_vs_reference": Tol(
        rtol=1e-10, atol=1e-10,
        why="issue 3 Phi' (Table 1 product) against reference at dps 30, scaled by "
            "max(1, |Phi'|): each impact factor 2 A / v- moves by ~|dt| |A'| / |v-| + "
            "2 |A| |dv| / v-^2 for event-time and velocity errors ~1e-15, so ~1e-13 / v-^2 "
            "per impact; 1e-10 admits impacts down to |v-| ~ 0.03 (fixed states, no grazing)"),
})

# --- reference chatter and the issue 6 effects (tests/test_reference_chatter.py,
#     tests/test_effect_claims.py; owner: reference chatter/effects) ---------------------
TOLERANCES.update({
    "ref_chatter_time_dps50": Tol(
        rtol=0.0, atol=1e-45,
        why="issue 6: chatter accumulation time at dps 50 against dps 80.  The bounces are "
            "solved wall-relative (chatter.wall_bounce), so impact times and speeds keep "
            "full relative precision (62 working digits); the tail extrapolation has a "
            "Lebesgue constant <= 2^(prec/5) ~ 1e12 on its nodes and stops when two "
            "extrapolations agree to 1e-50 T: 1e-62 x 1e12 = 1e-50; 1e-45 leaves 5 digits "
            "(measured 1e-52..1e-53 on e in {0.5, 0.9, 0.99}, f/F in {0.3, 0.01, 0.001})"),
    "ref_chatter_time_dps30": Tol(
        rtol=0.0, atol=1e-25,
        why="ref_chatter_time_dps50's derivation at dps 30 (42 working digits): Lebesgue "
            "constant <= 2^(prec/5) ~ 1e8 and the agreement test at 1e-30 T; 1e-25 leaves 5 "
            "digits, as at dps 50"),
    "ref_chatter_bounce_rel_dps50": Tol(
        rtol=1e-55, atol=0.0,
        why="one wall-relative bounce (duration, height, speed) at dps 50 (62 working "
            "digits) against dps 80, relative: each is a root of a difference-free closed "
            "form found to 2^-(prec-8) relative, ~1e-59; 1e-55 leaves 4 digits for the "
            "conditioning of the two-phase bounce (|d t_impact / d t_turn| ~ 1)"),
    "effects_det_identity": Tol(
        rtol=1e-40, atol=0.0,
        why="det of the reference Table 1 product (dps 50) against the closed form "
            "e^(2 n) exp(-c T): each factor is exact to 62 digits, the product of ~10 "
            "factors and the 2x2 determinant lose a few; relative 1e-40 leaves 20 digits"),
    "effects_det_fd": Tol(
        rtol=1e-20, atol=1e-20,
        why="det of a central-difference Jacobian (ref_fd_jacobian's 1e-25 per entry, "
            "entries up to ~10^2 on the orbits used: det error <= 4 x 1e-25 x 10^2 x 10^2 "
            "~ 4e-21) against the closed form; 1e-20"),
})

# --- figures (cross_check/paper/figures/, issue 7), continued ------------------------------
TOLERANCES.update({
    "fig_caption_4_decimals": Tol(
        rtol=0.0, atol=5e-5,
        why="issue 7: a number printed in a caption with 4 decimals (fig:fig's multipliers 0.3159, "
            "3.1659) is the true value rounded, within half a unit of the last digit; the computed "
            "multipliers carry ~1e-10 (Newton residual 1e-11 times the saddle's conditioning)"),
})

# --- fast chatter tail and damped flights (tests/test_fast_chatter.py,
#     tests/test_fast_damping.py; owner: fast chatter/damping) -------------------------
TOLERANCES.update({
    "fast_chatter_time": Tol(
        rtol=0.0, atol=1e-12,
        why="fast's chatter accumulation time against reference (dps 30, accurate to >= 1e-16), "
            "in units of T: the bounces simulated one by one are located wall-relative, each "
            "impact time to a few ulp of t (~1e-15 T), and a few dozen of them add up to "
            "~1e-14 T; the summed tail's neglected terms are kept below 4 eps T by its own "
            "stopping rule (fast.modes); 1e-12 (issue 3 brief's bound) leaves >= 10x over the "
            "measured <= 1e-13 T"),
})

# --- the claims snapshot (tests/test_claims.py, issue 14) --------------------------------
TOLERANCES.update({
    "claims_snapshot": Tol(
        rtol=1e-10, atol=1e-12,
        why="issue 14: the claims' numbers may not move when the code is reorganised.  Verdicts, "
            "strings, integers and counts must match exactly; a float may differ only by a "
            "libm/LLVM rounding difference across machines: ~1e-16 relative, amplified by at most "
            "~1e5 (the conditioning of the saddles' Newton steps and of ten chaotic periods in "
            "the quick settings) to ~1e-11 -- so 1e-10 relative (1e-12 absolute near zero) "
            "separates a rounding difference from a changed computation, which moves the fixed "
            "points' last digits by >= 1e-9"),
})

# --- the scorecard's grades (cross_check/score/, issue 16) -------------------------------
TOLERANCES.update({
    "score_grade_a": Tol(
        rtol=1e-13, atol=1e-13,
        why="grade A: the worst one-period error outside the band within 1e-13 (13 digits), the "
            "accuracy of a float64 event-driven engine with closed-form flights (fast: >= 14 digits "
            "outside the band, fast_one_period_max = 1e-13)"),
    "score_grade_b": Tol(
        rtol=1e-10, atol=1e-10,
        why="grade B: 10 digits, what a general-purpose integrator at its tightest tolerance "
            "(scipy DOP853, rtol 1e-10 ... 1e-12) reaches on a period with a few events"),
    "score_flag": Tol(
        rtol=1e-8, atol=1e-8,
        why="below 8 digits a kind is flagged (grade F), as is any missed or invented event or "
            "failure outside the band: a physics fault (friction's sign, a skipped graze, a "
            "doubled restitution) moves Phi by >= 1e-6 on the cases of its kind, while a correct "
            "integrator at rtol 1e-10 keeps >= 8 digits over one period (the report's work-precision "
            "table); the margin of 2 decades on either side separates the two"),
    "golden_case_float64": Tol(
        rtol=1e-12, atol=1e-12,
        why="the pytest plugin's default for a float64 integrator against a golden case outside "
            "the band: 1e-12 relative to max(1, |Phi|), i.e. within ~1e4 ulp of the 40-digit "
            "answer (fast holds 1e-13, fast_one_period_max)"),
})

# --- the reference's precision on very short flights (tests/test_short_flights.py, issue 18) ---
TOLERANCES.update({
    "reference_short_flight_lost_digits": Tol(
        rtol=100.0, atol=0.0,
        why="issue 18: a dps-digit run of the reference agrees with a (dps + 20)-digit run to "
            "10^(2 - dps) (rtol = 10^2 is the factor over 10^-dps), relative to max(1, |Phi|), "
            "on states whose flights are very short -- chatter bounces, exact grazing, release "
            "at the stick-slip boundary, gaps of 1e-6 -- at dps 20, 50 and 100 (so that guard "
            "digits cannot hide a loss).  Measured: within 10^(-dps - 1.2) on every such state "
            "of the test; 2 digits of slack cover the conditioning of the tiny-gap scene "
            "(~1e3 impacts a period, each located to working precision)"),
})

# --- the sensitivity checks (cross_check/sensitivity/, issue 18) ---------------------------
TOLERANCES.update({
    "sensitivity_event_time": Tol(
        rtol=1e-11, atol=0.0,
        why="issue 18: the times of the canonical events of a golden case outside the band, in "
            "units of T: fast locates each event to a few ulp of t and carries the state in "
            "double-double (<= 1e-14 T), a chatter accumulation to fast_chatter_time = 1e-12 T; "
            "1e-11 T leaves a decade over the worst of them, far below what a wrong event (a "
            "chatter cut short: >= 1e-6 T) moves"),
    "sensitivity_jacobian": Tol(
        rtol=1e-8, atol=0.0,
        why="issue 18: Phi' against the golden 40-digit Jacobian, relative to max(1, |J|), "
            "outside the band and away from grazing: a product of Table 1 matrices whose "
            "entries carry float64 event times (1/v- amplifies them by <= ~1e3 on these cases; "
            "measured worst 4e-11); a wrong factor changes J by O(1)"),
})

# --- enclosures (reference.enclosure, issue 17) --------------------------------------------
TOLERANCES.update({
    "enclosure_vs_reference_dps60": Tol(
        rtol=1e-50, atol=1e-50,
        why="issue 17: a proved ball must contain the true value; the reference at dps 60 (72 "
            "working digits) is within dps_tol(60) = 1e-55 of it on these states (a handful of "
            "events, no grazing), so the reference may lie outside the ball by at most that: "
            "1e-50 (relative to max(1, |value|)) is 5 decades of headroom, and a wrong ball "
            "(a missed event, a wrong saltation factor) misses by O(1)"),
    "golden_enclosure_rel": Tol(
        rtol=1e-40, atol=0.0,
        why="issue 17 acceptance: a proved golden case has relative radius <= 1e-40 for Phi "
            "(the 40 written digits are then theorems up to their last-digit rounding)"),
    "golden_enclosure_floor": Tol(
        rtol=1e-43, atol=1e-60,
        why="issue 17: the stored ball is the proved one widened to at least 1e-43 relative "
            "(atol 1e-60 for exact zeros): still a proof (a superset of a proved ball), and an "
            "independent 50-digit integrator (error ~1e-48 after a period's conditioning) "
            "lands inside it; 1e-43 keeps 3 decades under golden_enclosure_rel"),
})

# --- issue 29: the engines on extreme scenes (tests/test_engine_ranges.py) -------------------
TOLERANCES.update({
    "engines_scaled_one_period": Tol(
        rtol=0.0, atol=1e-13,
        why="issue 29: fast_one_period_max in the scene's own units: position errors over "
            "max(|l|, |r|, r - l, F/w^2), velocity errors over F/w + (r - l) w + f T -- the "
            "scales of both engines' noise floors.  A scene rescaled in length and time is the "
            "same problem (the paper's rescalings), so float64 carries the same few ulp per "
            "event of these scales as at the paper's units; a wrong event misses by O(1)"),
})

# --- issue 24: fast's float64 flight values and their series (tests/test_fast_noise.py) -------
TOLERANCES.update({
    "fast_flight_trig_abs": Tol(
        rtol=0.0, atol=8 * EPS,
        why="issue 24: cos wt, sin wt of fast.flight.evaluate from the start's sin, cos (w t0) "
            "(correctly rounded: 0.5 ulp) and the half angle's S, C (fast.dd.sincos64: within "
            "2.2 eps, fast_sincos64_abs): cs0 - 2 S Qs carries 0.5 + 2 (2.2 + 2.2 + 1) eps of "
            "rounding and input error < 8 eps (measured: 4 eps); they set the curvature of the "
            "search's local minorants"),
    "fast_flow_flight": Tol(
        rtol=EPS, atol=0.0,
        why="issue 24: fast.flow of an event-free flight is the double-double flight "
            "(fast.flight.evaluate_dd, each term to ~1e-22 of its size) rounded once to float64: "
            "within half an ulp plus 1e-22, i.e. eps relative (measured: 0.5 eps)"),
    "fast_flight_series_rel": Tol(
        rtol=3 * EPS, atol=0.0,
        why="issue 24: Horner's rule on the alternating series of theta - sin theta (7 terms, "
            "theta <= 1/2: terms fall by >= 20x) and of phi2 = (exp(-y) - 1 + y)/y^2 (15 terms, "
            "y <= 1/2: by >= 6x): each step's rounding is damped by the next multiplication, so "
            "the error is ~2 roundings of the result's size, plus the final products: <= 2.5 eps "
            "(measured 1.7 and 0.4 eps); a term dropped from the first series leaves 5 eps at "
            "theta = 1/2, two terms 4000 eps, three from phi2 25 eps"),
    "fast_theta_minus_sin_direct_rel": Tol(
        rtol=64 * EPS, atol=0.0,
        why="issue 24: theta - 2 S C above theta = 1/2: 2 S C carries ~2.5 eps relative (S, C from "
            "sincos64, one product), magnified by theta / (theta - sin theta) <= 24.3: <= 61 eps "
            "(measured 27 eps; the docstring's 24 eps takes S, C exact)"),
    "fast_phi2_direct_rel": Tol(
        rtol=8 * EPS, atol=0.0,
        why="issue 24: phi2 above y = 1/2 as (expm1(-y) + y)/y^2: expm1 to 1 ulp, the sum "
            "magnified by y / (y - 1 + exp(-y)) <= 4.7, two more roundings: < 8 eps (measured "
            "1.2 eps)"),
    "fast_sincos64_abs": Tol(
        rtol=0.0, atol=4 * EPS,
        why="issue 24: fast.dd.sincos64: the table's sin, cos (k pi/32) correctly rounded, the "
            "reduced argument's series in float64 (first omitted term < 1e-17) and three "
            "roundings of the combination: < 3.5 eps absolute (measured 2.2 eps: the docstring's "
            "'2 ulp' is 2.2 eps)"),
})
TOLERANCES.update({
    "reference_short_flight_rel": Tol(
        rtol=100.0, atol=0.0,
        why="issue 24: one flight of the reference (reference.flows, base or damped) shorter "
            "than 1e-7 T, from rest at x0 = 0, agrees with the plain closed forms at 3 dps + 40 "
            "digits to 10^(2 - dps) relative to x and v themselves (rtol = 10^2 is the factor "
            "over 10^-dps): its cancelling brackets (1 - cos theta, theta - sin theta, "
            "exp(-c h) - 1 + c h, 1 - exp(-c h)) are formed at raised precision, so only a few "
            "roundings of the result's own size remain (measured: within 10^(1 - dps)); "
            "a bracket at working precision loses log10(1/h) digits or more"),
})

# --- issue 25: validated flights under position forcing (reference.enclosure.lohner) -------
TOLERANCES.update({
    "validated_flight_radius": Tol(
        rtol=1e-30, atol=0.0,
        why="issue 25 acceptance: a validated flight over one period at 200 bits (60 digits) "
            "has relative radius <= 1e-30. Each Taylor step's Lagrange remainder is below "
            "2^-200 of the state's scale and the rounding of ~100-term series ~1e3 ulp; ~15 steps "
            "a period in the Lohner QR frame grow the box by about |Phi'| <= ~10, so ~1e-57 is "
            "expected: 1e-30 leaves 27 decades, and a lost remainder or a wrapping blow-up "
            "(an axis box over a period) would not be caught by it, only by containment"),
    "near_columns_width_factor": Tol(
        rtol=2.0, atol=0.0,
        why="issue 33 (tests/test_series_near.py): the flow derivative's columns over a box, "
            "from the centre's sin(kx) series and its gradient over a box 4 times as wide "
            "(series.Field.variational_near), are at most this factor as wide as the box's own "
            "recurrence's, plus the working precision. The first-order widths are the same "
            "gradient times the same box; the wider box raises only the second-order part. "
            "Worst ratio measured on 150 random cases (every effect, boxes 2^-40 to 2^-8): 1.14"),
    "tracked_centre_width_factor": Tol(
        rtol=4.0, atol=0.0,
        why="issue 33 (tests/test_tracked_centre.py): Phi at a box's centre as the box's walk "
            "tracks it (lohner.ValidatedFlight.point_state: the set's own recurrence on the "
            "centre's offsets, through hand-offs, stops and slips) is at most this factor as "
            "wide as a walk from the centre alone, for boxes of at most 2^-(prec/3 + 8), where "
            "the second- and third-order terms of the box (the spread of slip times, the "
            "derivative over the box in the events' Newton steps) stay below the working "
            "precision. Worst ratio measured on 240 random cases at 64 and 128 bits, every "
            "effect: 2.7 (most 0.7 to 1.5: the point walk's own steps differ)"),
})

# --- issue 33: fast under position forcing (tests/test_ode_accuracy.py) ----------------------
TOLERANCES.update({
    "fast_xpot_per_cond_mean": Tol(
        rtol=1.0, atol=0.0,
        why="issue 33: fast.ode's one-period error over its conditioning, max over x, v of "
            "|fast - ref| / max(1, |ref|) / (eps max(1, max |Phi'_ij|)), eps = 2^-52 (the "
            "measure of golden_fast_phi_per_cond), mean over a batch of states of one scene: "
            "the float64 floor is the final rounding (half an ulp: up to 1 eps relative, "
            "~0.3 on average) plus each event's rounding moved by the rest of the period; "
            "the closed-form engine's golden inputs show mean <= 0.33, its k = 0 runs 0.2 - "
            "1.2 on the issue's random scenes.  Measured (compensated flights, fast."
            "compensated): 0.21 mean over 40 random scenes x 8 states (worst scene 0.43), "
            "0.08 on fig:xpotno; the float64 flights before: 13 (worst scene 159)"),
    "fast_xpot_per_cond_max": Tol(
        rtol=4.0, atol=0.0,
        why="issue 33: the same measure's max over a batch: a few roundings, each moved by "
            "the conditioning of what follows it in the period (a stick or a contact zeroes "
            "Phi' but not the flights after it).  Measured: 1.5 over 40 random scenes x 8 "
            "states, 0.23 on fig:xpotno; before: 208"),
})

# --- issue 27: the per-core baseline (tests/benchmarks/test_bench_per_core.py) -------------
TOLERANCES.update({
    "plain_kernel_vs_fast": Tol(
        rtol=0.0, atol=1e-10,
        why="issue 27: the plain float64 kernel (no double-double) against fast over one "
            "period, per unit of 1 + |Phi'|, on states with |Phi'| <= 1e4 and no summed chatter "
            "tail: the plain kernel accepts an event where its function is within its rounding "
            "noise (8 eps of the flight's terms, <= 1e-14 on the benchmark scenes), which moves "
            "a state by ~1e-14 per event before |Phi'| amplifies it (measured worst 1.1e-13 per "
            "unit); a missed or invented event moves it by O(0.01..1)"),
})

# --- issue 32: the league's peers (tests/test_peers.py) ------------------------------------
TOLERANCES.update({
    "peer_mujoco_flight": Tol(
        rtol=0.5, atol=0.0,
        why="issue 32: MuJoCo's slide joint (semi-implicit Euler, forcing sampled at each step's "
            "midpoint) on a start without an impact: error of Phi relative to max(1, |Phi|), in "
            "units of T (F + f) dt.  The velocity update is exact to O(dt^2) per period with the "
            "midpoint forcing; the position uses the new velocity, dt^2 a / 2 per step with |a| <= "
            "F + f, so T (F + f) dt / 2 over a period: rtol = 1/2.  Measured on the smooth flights "
            "of four scenes at dt 1e-3 and 1e-4: <= 0.24; an impact (a spring over ten steps) "
            "costs ~10 (F + f) dt |v| more, a forcing of the wrong phase or a missing friction "
            "O(T^2 F)"),
})
