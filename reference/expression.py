"""Scene values read from text: exact decimals and expressions in ``pi``, with bounded work.

A scene value may come from a file written by someone else, so reading it must end quickly
in a value or a ``ValueError`` -- whatever the text.  Python's AST gives the syntax; a
whitelist (numbers, ``pi``, unary ``+ -``, binary ``+ - * / **``, parentheses) rules out
code; the limits below rule out unbounded work (``"10**10**10"``, ``"9**9**9**9"``,
``"1e999999999"`` each take no time to refuse):

* the text: at most ``MAX_TEXT_LENGTH`` characters;
* the tree: at most ``MAX_NODES`` numbers, names and operations, nested at most
  ``MAX_DEPTH`` deep;
* every number in it (literal, intermediate or final): zero or ``2^-B <= |x| < 2^(B+1)``
  (``floor(log2 |x|)`` within ``+-B``), ``B = MAX_EXPONENT_BITS``, checked on the literal's decimal exponent before the exact
  rational is built (``Fraction("1e999999999")`` alone would build a billion-digit integer);
* a power ``a ** b``: ``|b| <= MAX_POWER_EXPONENT``, and the binary exponent of the result,
  ``b log2 |a|``, is estimated at 64 bits from the magnitudes (never by computing the power)
  and must be at most ``B`` in absolute value.

Beyond a limit the text is refused with a ``ValueError`` naming the limit; ``Scene`` adds
the parameter's name and the text.

``Expr`` keeps the (validated) tree and evaluates it in any arithmetic through ONE
evaluator, ``eval_tree``: mpmath at the caller's precision (``Expr.mpf``), and Arb balls
(``reference.enclosure.balls.parameter`` passes its constant maker and its ``pi``).  Every
arithmetic goes through the same checks, so no precision and no arithmetic can reach a
power the 113-bit probe did not see bounded.
"""
from __future__ import annotations

import ast
import math
from decimal import Decimal, InvalidOperation
from fractions import Fraction

import mpmath

#: Characters of a scene value (a decimal or an expression).  The paper's longest value,
#: ``"(2*pi)**2"``, has 9; a decimal with 40 significant digits (the golden data's) about 45;
#: 256 leave room for any physical constant written out with its conversion factors.
MAX_TEXT_LENGTH = 256
#: Numbers, names and operations in an expression.  ``"(2*pi)**2"`` has 5, a formula such as
#: ``"2*pi*0.35/(1 + 0.25*pi**2)"`` 13; no physical parameter needs a tenth of 128.
MAX_NODES = 128
#: Nesting depth of an expression (a sum of ``n`` terms nests ``n`` deep).  ``"(2*pi)**2"``
#: nests 3 deep; 32 allow a sum of 30 terms, and keep the evaluator's recursion short.
MAX_DEPTH = 32
#: Binary exponent bound: every number of a scene value, literal, intermediate or final, is
#: zero or between ``2^-4096`` and ``2^4096`` (about ``1e-1233`` to ``1e1233``) in absolute
#: value.  Physical constants in any system of units lie within ``1e-60 .. 1e60``, and
#: float64 within ``2^-1074 .. 2^1024``: four times float64's exponent range leaves the
#: reference (mpmath, any exponent) room to run scenes beyond float64, while the exact
#: rationals of the values stay a few thousand bits long (``Scene``'s order checks build them).
MAX_EXPONENT_BITS = 4096
#: Largest exponent ``|b|`` of a power ``a ** b``.  Exponents in physics are small rationals
#: (``2``, ``1/2``, ``-3``); ``10**-1233``, the smallest magnitude a value holds, needs 1233.
MAX_POWER_EXPONENT = 4096
#: Bits of the numerator and of the denominator of an exact rational input (``Fraction``,
#: ``int``, the mantissa of an ``mpf``): twice the reference's largest working precision
#: (``reference.api.MAX_DPS`` = 10000 digits, about 33,200 bits), so every value the
#: reference can produce is accepted, while converting one stays a matter of microseconds.
MAX_RATIONAL_BITS = 65536

#: An expression is evaluated at ``PROBE_BITS`` and at ``KEY_BITS`` (``Scene``'s order checks)
#: when read; the two values must agree to ``STABLE_BITS``.  An expression that cancels more
#: (``"pi - 3.14159265358979323846264338327950288"``, ``"1e20 + 1 - 1e20"``) has a value that
#: depends on the precision it is evaluated at (it may even divide by zero at one of them),
#: while ``Expr.mpf`` keeps only 20 guard bits: it is refused (write the value as a decimal).
PROBE_BITS, KEY_BITS, STABLE_BITS = 113, 400, 100

_ALLOWED_BINOPS = (ast.Add, ast.Sub, ast.Mult, ast.Div, ast.Pow)
_LOG2_10 = math.log2(10)


class LimitError(ValueError):
    """A scene value beyond one of this module's limits (the message names the limit)."""


def check_rational(value: Fraction) -> Fraction:
    """``value`` within ``MAX_RATIONAL_BITS`` and ``MAX_EXPONENT_BITS`` (``LimitError``)."""
    num, den = abs(value.numerator), value.denominator
    if max(num.bit_length(), den.bit_length()) > MAX_RATIONAL_BITS:
        raise LimitError(f"its exact rational has more than MAX_RATIONAL_BITS = "
                         f"{MAX_RATIONAL_BITS} bits in the numerator or denominator")
    if num:
        _check_exponent(num.bit_length() - den.bit_length(), "its magnitude")
    return value


def check_mpf_parts(man: int, exp: int) -> None:
    """An ``mpf`` ``man * 2^exp`` within the limits, checked before ``2^exp`` is built."""
    if man.bit_length() > MAX_RATIONAL_BITS:
        raise LimitError(f"its mantissa has more than MAX_RATIONAL_BITS = {MAX_RATIONAL_BITS} bits")
    if man:
        _check_exponent(exp + man.bit_length() - 1, "its magnitude")


def decimal_value(text: str):
    """The exact value of a decimal string, or ``None`` if ``text`` is not one; its decimal
    exponent is checked before the rational is built."""
    try:
        dec = Decimal(text)
    except InvalidOperation:
        return None
    if not dec.is_finite():
        raise ValueError("it must be finite")
    if dec.is_zero():
        return Fraction(0)
    _check_exponent(round(dec.adjusted() * _LOG2_10), "its magnitude")
    return Fraction(dec)


def _check_exponent(bits, what):
    if abs(bits) > MAX_EXPONENT_BITS:
        size = f"2^{bits}" if abs(bits) < 10 ** 6 else f"2^({mpmath.nstr(mpmath.mpf(bits), 3)})"
        raise LimitError(f"{what} is about {size}, beyond 2^(+-{MAX_EXPONENT_BITS}) "
                         f"(MAX_EXPONENT_BITS = {MAX_EXPONENT_BITS})")


# --- parsing ---------------------------------------------------------------------------
def parse(text: str) -> ast.Expression:
    """The checked tree of an expression: length, nodes, depth, whitelist, and literals
    replaced by their exact ``Fraction`` (read from the source text, not from Python's
    float: ``"2*0.1"`` is exactly 1/5, ``"2e400"`` is not infinity)."""
    if len(text) > MAX_TEXT_LENGTH:
        raise LimitError(f"it has {len(text)} characters, more than MAX_TEXT_LENGTH = {MAX_TEXT_LENGTH}")
    try:
        tree = ast.parse(text, mode="eval")
    except (SyntaxError, MemoryError, RecursionError) as exc:
        raise ValueError(f"it is not an expression ({type(exc).__name__})") from None
    nodes = [node for node in ast.walk(tree) if isinstance(node, ast.expr)]
    if len(nodes) > MAX_NODES:
        raise LimitError(f"it has {len(nodes)} numbers and operations, more than "
                         f"MAX_NODES = {MAX_NODES}")
    depth = _depth(tree.body)
    if depth > MAX_DEPTH:
        raise LimitError(f"it nests {depth} deep, more than MAX_DEPTH = {MAX_DEPTH}")
    for node in nodes:
        _check_node(node)
        if isinstance(node, ast.Constant):
            node.value = _literal(text, node)
    return tree


def _depth(root) -> int:
    """Nesting depth of an expression tree, without recursion."""
    deepest, stack = 0, [(root, 1)]
    while stack:
        node, level = stack.pop()
        deepest = max(deepest, level)
        stack.extend((child, level + 1) for child in ast.iter_child_nodes(node)
                     if isinstance(child, ast.expr))
    return deepest


def _check_node(node):
    ok = (isinstance(node, ast.Constant) and type(node.value) in (int, float)
          or isinstance(node, ast.Name) and node.id == "pi"
          or isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd))
          or isinstance(node, ast.BinOp) and isinstance(node.op, _ALLOWED_BINOPS))
    if not ok:
        raise ValueError(f"it contains {ast.unparse(node)!r}, which is not a number, pi or "
                         f"+ - * / **")


def _literal(text, node) -> Fraction:
    """A literal's exact value from its source text (hex, octal, binary ints from Python)."""
    source = ast.get_source_segment(text, node) or ""
    value = decimal_value(source.strip())
    if value is None:
        value = Fraction(node.value) if isinstance(node.value, int) else None
    if value is None:
        raise ValueError(f"it contains the number {source!r}, which is not a decimal")
    return check_rational(value)


# --- evaluation --------------------------------------------------------------------------
def _mp_number(value: Fraction) -> mpmath.mpf:
    return mpmath.mpf(value.numerator) / value.denominator


def eval_tree(node: ast.AST, number=_mp_number, pi=None):
    """Evaluate a tree from ``parse``; ``number`` turns a ``Fraction`` into the
    arithmetic's constant and ``pi`` is its pi (default: mpmath at the current precision).
    Every value is checked against ``MAX_EXPONENT_BITS``, every power before it is taken."""
    if isinstance(node, ast.Expression):
        return eval_tree(node.body, number, pi)
    if isinstance(node, ast.Constant) and isinstance(node.value, Fraction):
        return number(node.value)
    if isinstance(node, ast.Name) and node.id == "pi":
        return +mpmath.pi if pi is None else pi
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
        value = eval_tree(node.operand, number, pi)
        return -value if isinstance(node.op, ast.USub) else value
    if isinstance(node, ast.BinOp) and isinstance(node.op, _ALLOWED_BINOPS):
        a, b = eval_tree(node.left, number, pi), eval_tree(node.right, number, pi)
        op = node.op
        if isinstance(op, ast.Add):
            out = a + b
        elif isinstance(op, ast.Sub):
            out = a - b
        elif isinstance(op, ast.Mult):
            out = a * b
        elif isinstance(op, ast.Div):
            out = a / b
        else:
            _check_power(a, b)
            out = a ** b
        _magnitude(out)
        return out
    raise ValueError(f"unsupported element {ast.dump(node)}")


def _approx(value) -> mpmath.mpf:
    """``value`` (mpf, Fraction, or an Arb ball: its midpoint) as a 64-bit mpf."""
    if isinstance(value, mpmath.mpc):
        if value.imag != 0:
            raise ValueError("it is not real (a power of a negative number)")
        value = value.real
    with mpmath.workprec(64):
        if isinstance(value, mpmath.mpf):
            return +value
        if isinstance(value, Fraction):
            return mpmath.mpf(value.numerator) / value.denominator
        if hasattr(value, "mid"):                 # an Arb ball (python-flint)
            man, exp = value.mid().man_exp()
            return mpmath.ldexp(mpmath.mpf(int(man)), int(exp))
        return mpmath.mpf(value)


def _magnitude(value) -> mpmath.mpf:
    """``value`` as a 64-bit mpf after checking its binary exponent (``LimitError``) and, for
    an exact rational, its size (``NotExact`` beyond ``MAX_RATIONAL_BITS``)."""
    if isinstance(value, Fraction) and max(abs(value.numerator).bit_length(),
                                           value.denominator.bit_length()) > MAX_RATIONAL_BITS:
        raise NotExact
    x = _approx(value)
    if not mpmath.isfinite(x):
        raise ValueError("it is not finite")
    if x:
        man, exp = x.man_exp
        _check_exponent(int(exp) + int(man).bit_length() - 1, "a value in it")
    return x


class NotExact(Exception):
    """Raised in exact (``Fraction``) evaluation where the value is not a small rational: a
    non-integer power, or a rational beyond ``MAX_RATIONAL_BITS`` (``read`` then keeps the
    expression and evaluates it at each precision instead)."""


def _check_power(a, b):
    """``a ** b`` is refused unless ``|b| <= MAX_POWER_EXPONENT`` and ``|b log2 |a||`` (the
    result's binary exponent, estimated at 64 bits) is within ``MAX_EXPONENT_BITS``.  In
    exact arithmetic the exponent must be an integer and the result's numerator and
    denominator, of ``|b|`` times the base's bit lengths, within ``MAX_RATIONAL_BITS``
    (``NotExact`` otherwise) -- all checked before the power is taken."""
    x, y = _approx(a), _approx(b)
    if abs(y) > MAX_POWER_EXPONENT:
        raise LimitError(f"it has a power with exponent {mpmath.nstr(y, 5)}, beyond "
                         f"MAX_POWER_EXPONENT = {MAX_POWER_EXPONENT}")
    if isinstance(a, Fraction) and isinstance(b, Fraction):
        size = max(abs(a.numerator).bit_length(), a.denominator.bit_length())
        if b.denominator != 1 or size * abs(b.numerator) > MAX_RATIONAL_BITS:
            raise NotExact
    if not x or not y:
        return
    with mpmath.workprec(64):
        bits = y * mpmath.log(abs(x), 2)
    _check_exponent(int(mpmath.nint(bits)), f"the power {mpmath.nstr(x, 5)}**{mpmath.nstr(y, 5)}")


def _exact(tree):
    """The exact rational value of a tree without ``pi`` and with integer powers (``eval_tree``
    in ``Fraction`` arithmetic), or ``None``; sizes within ``MAX_RATIONAL_BITS``."""
    if any(isinstance(node, ast.Name) for node in ast.walk(tree)):
        return None
    try:
        value = eval_tree(tree, Fraction, Fraction(0))
        check_rational(value)
    except (NotExact, LimitError):
        return None
    return value


def read(text: str):
    """The value of ``text``, checked: ``parse``, then the exact ``Fraction`` where the
    expression is a small rational (no ``pi``, integer powers: ``"1/3"``, ``"2*0.1"``,
    ``"10**-5"``), else an ``Expr`` whose values at ``PROBE_BITS`` and ``KEY_BITS`` are
    finite, real and agree to ``STABLE_BITS`` (``ValueError`` otherwise)."""
    expr = Expr(text, parse(text))
    try:
        exact = _exact(expr._tree)
    except ZeroDivisionError:
        raise ValueError("it divides by zero") from None
    if exact is not None:
        return exact
    values = []
    for bits in (PROBE_BITS, KEY_BITS):
        with mpmath.workprec(bits):
            try:
                value = eval_tree(expr._tree)
            except ZeroDivisionError:
                raise ValueError(f"it divides by zero (at {bits} bits)") from None
        if not (isinstance(value, mpmath.mpf) and mpmath.isfinite(value)):
            raise ValueError("it is not finite and real")
        values.append(value)
    low, high = values
    with mpmath.workprec(KEY_BITS):
        if abs(low - high) > mpmath.ldexp(abs(high), -STABLE_BITS):
            raise ValueError(f"it cancels: its values at {PROBE_BITS} and {KEY_BITS} bits differ in "
                             f"the first {STABLE_BITS} bits (STABLE_BITS); write the value as a "
                             f"decimal")
    return expr


class Expr:
    """An exact real given by an arithmetic expression in ``pi`` (evaluated on demand)."""

    __slots__ = ("text", "_tree")

    def __init__(self, text: str, tree: ast.AST):
        self.text = text
        self._tree = tree

    def mpf(self) -> mpmath.mpf:
        """The value at the current mpmath precision (a few guard bits inside)."""
        with mpmath.workprec(mpmath.mp.prec + 20):
            try:
                value = eval_tree(self._tree)
            except ZeroDivisionError:
                raise ValueError(f"the scene value {self.text!r} divides by zero at "
                                 f"{mpmath.mp.prec} bits") from None
        return +value

    def evaluate(self, number, pi):
        """The value in another arithmetic: ``number(Fraction)`` makes a constant, ``pi`` is
        that arithmetic's pi (``reference.enclosure`` evaluates in arb balls this way)."""
        return eval_tree(self._tree, number, pi)

    def __float__(self) -> float:
        with mpmath.workprec(113):
            return float(eval_tree(self._tree))

    def __eq__(self, other):
        return isinstance(other, Expr) and other.text == self.text

    def __hash__(self):
        return hash(self.text)

    def __repr__(self):
        return repr(self.text)
