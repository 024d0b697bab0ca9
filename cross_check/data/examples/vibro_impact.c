/* An integrator of x'' + f sgn(x') = F cos(w t) between walls l < x < r, in C (C99, standard
 * library only): the example of the results-file protocol (FORMAT.md beside this file).
 *
 *     cc -O2 -o vibro_impact vibro_impact.c -lm
 *     python -m cross_check score --export-problems problems --scenes ...
 *     ./vibro_impact problems/problems.csv results.csv
 *     python -m cross_check score --results results.csv --scenes ...
 *
 * Event-driven, on the base model's closed-form flights (plus restitution e: v -> -e v at a wall):
 * in a flight of direction s, v(t) = v0 + (F/w)(sin wt - sin wt0) - s f (t - t0), x its integral.
 * It ends at the wall ahead or where v = 0 (the other wall cannot come first).
 * An event is found by subdividing the flight: since |x''| <= F + f, a part of it
 * where x - r cannot reach 0 is excluded with certainty, a part where the event function is
 * monotone holds at most one root (found by bisection); so no root is skipped.  At v = 0 the
 * motion turns if |F cos wt| > f, else it sticks until |F cos wt| > f (the release, solved in
 * closed form).  A bounce too slow to rise 1e-13 from the wall, against a force that pushes into
 * it, ends a chatter: the particle rests on the wall until the force pulls it off (|F cos wt| > f).
 * Rows with damping or position forcing get status "failed": not modelled here.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_EVENTS 100000          /* per start: more is a failure, never an endless loop */
#define MAX_DEPTH 80               /* subdivision depth of an event search */
#define NCOL 15
static const double PI = 3.14159265358979323846;

typedef struct { double F, f, w, l, r, e, M; } P;                /* M = F + f bounds |x''| */
typedef struct { double t0, x0, v0, s; } Flight;                 /* a flight from (t0, x0, v0) */

static double force(const P *p, double t) { return p->F * cos(p->w * t); }

/* The state of flight g at time t: the closed form, differences of sin and cos taken as products
 * (no cancellation when t is close to t0). */
static void at(const P *p, const Flight *g, double t, double *x, double *v) {
    double h = t - g->t0, w = p->w, sh = sin(0.5 * w * h), mid = 0.5 * w * (t + g->t0);
    double dsin = 2.0 * cos(mid) * sh, dcos = -2.0 * sin(mid) * sh;
    *v = g->v0 + p->F / w * dsin - g->s * p->f * h;
    *x = g->x0 + (g->v0 - p->F / w * sin(w * g->t0)) * h - p->F / (w * w) * dcos - 0.5 * g->s * p->f * h * h;
}

/* Event function k at t: 0: x - r, 1: l - x, 2: -s v (an event where it rises to 0); its slope. */
static double ev(const P *p, const Flight *g, int k, double t, double *slope) {
    double x, v;
    at(p, g, t, &x, &v);
    if (k == 0) { *slope = v; return x - p->r; }
    if (k == 1) { *slope = -v; return p->l - x; }
    *slope = -g->s * (force(p, t) - g->s * p->f);
    return -g->s * v;
}

/* The first root of event k in (a, b], or -1.  A wall's function has |g''| <= M, so g(a + h) <=
 * g(a) + g'(a) h + M h^2 / 2: below 0 on [a, b] means no root there; |g'(a)| > M h means g is
 * monotone on [a, b] (at most one root: bisection).  The v event likewise with |g'| <= M and
 * |g''| <= F w.  Anything else is halved, left half first. */
static double first_root(const P *p, const Flight *g, int k, double a, double b, int depth) {
    double sa, sb, ga = ev(p, g, k, a, &sa), gb = ev(p, g, k, b, &sb), h = b - a;
    double reach = k == 2 ? ga + p->M * h : ga + sa * h + 0.5 * p->M * h * h;
    if (ga < 0.0 && reach < 0.0) return -1.0;                  /* cannot reach 0 on [a, b] */
    if (fabs(sa) > (k == 2 ? p->F * p->w : p->M) * h || depth >= MAX_DEPTH) {
        if (gb < 0.0) return -1.0;
        for (int i = 0; i < 200 && b - a > 2e-16 * fmax(1.0, fabs(b)); i++) {
            double m = 0.5 * (a + b), s;
            if (ev(p, g, k, m, &s) >= 0.0) b = m; else a = m;
        }
        return b;
    }
    double m = 0.5 * (a + b), t = first_root(p, g, k, a, m, depth + 1);
    return t >= 0.0 ? t : first_root(p, g, k, m, b, depth + 1);
}

/* The first time after t where cos(w t) crosses c going down (dir -1) or up (dir +1); HUGE_VAL if
 * it never does (|c| >= 1). */
static double next_crossing(const P *p, double t, double c, int dir) {
    if (fabs(c) >= 1.0) return HUGE_VAL;
    double phase = dir < 0 ? acos(c) : 2.0 * PI - acos(c), now = fmod(p->w * t, 2.0 * PI);
    return (phase + 2.0 * PI * (floor((now - phase) / (2.0 * PI)) + 1.0) + p->w * t - now) / p->w;
}

/* Phi^periods of (x, v) at t_end: 0 on success, -1 when the events run over MAX_EVENTS.
 * rest: 0 in flight, 1 stuck (v = 0 inside), 2 resting on r, 3 resting on l. */
static int strobe(const P *p, double t_end, double *x, double *v) {
    double t = 0.0, a = force(p, 0.0), s = *v != 0.0 ? copysign(1.0, *v) : copysign(1.0, a);
    /* a bounce this slow rises 1e-13 from the wall (float64 positions near it are quantized): a chatter */
    double slow = sqrt(2e-13 * p->M * fmax(1.0, fmax(fabs(p->l), fabs(p->r)))), eps = 1e-6 * 2.0 * PI / p->w, c = p->F > 0.0 ? p->f / p->F : 2.0;
    int rest = *v == 0.0 && fabs(a) <= p->f;
    for (int n = 0; n < MAX_EVENTS; n++) {
        if (t >= t_end) return 0;                      /* an event at the strobe time: the state after it */
        if (rest) {                                    /* until |F cos wt| > f, away from a wall */
            double up = next_crossing(p, t, c, +1), down = next_crossing(p, t, -c, -1);
            double t1 = rest == 2 ? down : rest == 3 ? up : fmin(up, down);
            *v = 0.0;
            if (t1 >= t_end) return 0;
            s = t1 == up ? 1.0 : -1.0;
            t = t1;
            rest = 0;
        }
        Flight g = {t, *x, *v, s};
        double te = t_end;
        int which = -1;
        for (int k = s > 0.0 ? 0 : 1; k <= 2; k += s > 0.0 ? 2 : 1) {   /* the wall ahead, and v = 0 */
            double from = k == 2 && *v == 0.0 ? fmin(t + eps, t_end) : t;  /* not the root it starts on */
            double r = first_root(p, &g, k, from, te, 0);
            if (r >= 0.0 && r <= te) { te = r; which = k; }
        }
        at(p, &g, te, x, v);
        t = te;
        if (which < 0) return 0;                       /* the strobe time */
        a = force(p, t);
        if (which == 2) {                              /* v = 0: a stick, or a turn (onto a wall: rest) */
            *v = 0.0;
            s = copysign(1.0, a);
            if (fabs(a) <= p->f) rest = 1;
            else if (s > 0.0 ? *x >= p->r : *x <= p->l) rest = s > 0.0 ? 2 : 3;
            continue;
        }
        *x = which == 0 ? p->r : p->l;
        *v = -p->e * *v;
        s = -s;
        if (fabs(*v) <= slow && (which == 0 ? a >= -p->f : a <= p->f)) rest = which == 0 ? 2 : 3;
    }
    return -1;
}

/* Split a CSV line in place into at most n fields (double quotes allowed around a field). */
static int split(char *line, char **field, int n) {
    int k = 0;
    char *c = line;
    while (k < n) {
        int quoted = *c == '"';
        field[k++] = quoted ? ++c : c;
        char *w = c;
        for (; *c && (quoted || (*c != ',' && *c != '\n' && *c != '\r')); c++) {
            if (quoted && *c == '"') { if (c[1] == '"') c++; else { quoted = 0; continue; } }
            *w++ = *c;
        }
        int end = *c != ',';
        *w = '\0';
        if (end) break;
        c++;
    }
    return k;
}

int main(int argc, char **argv) {
    static const char *want[NCOL] = {"id", "scene", "case", "input", "periods", "F", "f", "omega", "l", "r",
                                      "restitution", "damping", "wavenumber", "x", "v"};
    char line[8192], *field[64];
    int col[NCOL];
    if (argc != 3) { fprintf(stderr, "usage: %s problems.csv results.csv\n", argv[0]); return 2; }
    FILE *in = fopen(argv[1], "r"), *out = fopen(argv[2], "w");
    if (!in || !out) { perror("vibro_impact"); return 2; }
    if (!fgets(line, sizeof line, in)) { fprintf(stderr, "%s: empty\n", argv[1]); return 2; }
    int n = split(line, field, 64);
    for (int j = 0; j < NCOL; j++) {
        col[j] = -1;
        for (int i = 0; i < n; i++) if (strcmp(field[i], want[j]) == 0) col[j] = i;
        if (col[j] < 0) { fprintf(stderr, "%s: no column %s\n", argv[1], want[j]); return 2; }
    }
    fprintf(out, "id,x,v,status\n");
    while (fgets(line, sizeof line, in)) {
        if (split(line, field, 64) < n) { fprintf(stderr, "%s: short row\n", argv[1]); return 2; }
        double d[NCOL];
        for (int j = 4; j < NCOL; j++) d[j] = field[col[j]][0] ? strtod(field[col[j]], NULL) : NAN;
        P p = {d[5], d[6], d[7], d[8], d[9], d[10], d[5] + d[6]};
        double x = d[13], v = d[14], t_end = d[4] * 2.0 * PI / p.w;
        if (d[11] != 0.0 || !isnan(d[12])) { fprintf(out, "%s,,,failed\n", field[col[0]]); continue; }
        if (strobe(&p, t_end, &x, &v) != 0 || !isfinite(x) || !isfinite(v))
            fprintf(out, "%s,,,failed\n", field[col[0]]);
        else
            fprintf(out, "%s,%.17g,%.17g,ok\n", field[col[0]], x, v);
    }
    return fclose(out) == 0 && fclose(in) == 0 ? 0 : 1;
}
