"""Safe arithmetic expressions of one variable, with exact first and second derivatives.

A user's text such as ``"90*sin(2*pi*t)"`` is parsed by Python's ``ast`` module and every node is
checked against a whitelist: numbers, the variable, ``pi`` and ``e``, ``+ - * / **``, unary signs
and calls of the functions in ``FUNCTIONS``. Nothing is ever passed to ``eval`` or ``exec``.

Evaluation is vectorised over a numpy array of the variable and carries second-order Taylor jets
(f, f', f'') through every operation (forward-mode automatic differentiation: the chain and product
rules applied to numbers, not to symbols), so the derivatives are exact up to rounding.
"""

from __future__ import annotations

import ast
import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from linkstress.errors import InputError
from linkstress.messages import quoted

MAX_LENGTH = 1000
"""Longest expression text accepted [characters]."""

MAX_DEPTH = 100
"""Deepest nesting of operations accepted (evaluation recurses once per level)."""

QUOTED = 60
"""Characters of an expression (or a piece of one) a message quotes at most."""

CONSTANTS = {"pi": math.pi, "e": math.e}

Jet = tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]
"""(f, f', f'') of an expression at every value of the variable."""


def _d1_tan(x):
    return 1 + np.tan(x) ** 2


def _d1_tanh(x):
    return 1 - np.tanh(x) ** 2


# name: (f, f', f'') as functions of the argument
FUNCTIONS = {
    "sin": (np.sin, np.cos, lambda x: -np.sin(x)),
    "cos": (np.cos, lambda x: -np.sin(x), lambda x: -np.cos(x)),
    "tan": (np.tan, _d1_tan, lambda x: 2 * np.tan(x) * _d1_tan(x)),
    "exp": (np.exp, np.exp, np.exp),
    "log": (np.log, lambda x: 1 / x, lambda x: -1 / (x * x)),
    "sqrt": (np.sqrt, lambda x: 0.5 / np.sqrt(x), lambda x: -0.25 / (x * np.sqrt(x))),
    "asin": (np.arcsin, lambda x: 1 / np.sqrt(1 - x * x), lambda x: x / (1 - x * x) ** 1.5),
    "acos": (np.arccos, lambda x: -1 / np.sqrt(1 - x * x), lambda x: -x / (1 - x * x) ** 1.5),
    "atan": (np.arctan, lambda x: 1 / (1 + x * x), lambda x: -2 * x / (1 + x * x) ** 2),
    "sinh": (np.sinh, np.cosh, np.sinh),
    "cosh": (np.cosh, np.sinh, np.cosh),
    "tanh": (np.tanh, _d1_tanh, lambda x: -2 * np.tanh(x) * _d1_tanh(x)),
    "abs": (np.abs, np.sign, np.zeros_like),
}

_OPERATORS = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/", ast.Pow: "**"}


class ExpressionError(InputError):
    """An expression that is not allowed or cannot be evaluated."""


@dataclass(frozen=True)
class Expression:
    """A checked expression of ``variable``; ``where`` names it in error messages (a scene key)."""

    text: str
    variable: str = "t"
    where: str = "expression"
    tree: ast.expr = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "tree", _parse(self.text, self.variable, self.where))

    def __call__(self, values: ArrayLike) -> NDArray[np.float64]:
        """The expression's value at each of ``values``."""
        return self.jet(values)[0]

    def jet(self, values: ArrayLike) -> Jet:
        """(f, df/dx, d2f/dx2) at each of ``values`` (1-D); every entry finite, else an error."""
        x = np.atleast_1d(np.asarray(values, float))
        ones, zeros = np.ones_like(x), np.zeros_like(x)
        with np.errstate(all="ignore"):
            jet = _evaluate(self.tree, (x, ones, zeros), self.variable)
        jet = tuple(np.broadcast_to(np.asarray(part, float), x.shape) for part in jet)
        finite = np.isfinite(jet[0]) & np.isfinite(jet[1]) & np.isfinite(jet[2])
        if not finite.all():
            bad = float(x[~finite][0])
            raise ExpressionError(
                f"{self.where}: {quoted(self.text, QUOTED)} or its derivatives are not finite at "
                f"{self.variable} = {bad!r}; keep arguments of log/sqrt > 0, of asin/acos inside (-1, 1), "
                "and divisors away from 0"
            )
        return jet  # type: ignore[return-value]


def _parse(text: str, variable: str, where: str) -> ast.expr:
    if not isinstance(text, str) or not text.strip():
        raise ExpressionError(f"{where}: give the expression as a non-empty string, e.g. \"90*sin(2*pi*t)\"")
    if len(text) > MAX_LENGTH:
        raise ExpressionError(f"{where}: the expression is longer than {MAX_LENGTH} characters")
    try:
        tree = ast.parse(text.strip(), mode="eval").body
    except (SyntaxError, ValueError, RecursionError, MemoryError) as error:
        raise ExpressionError(f"{where}: {quoted(text, QUOTED)} is not a valid expression ({error.__class__.__name__})") from None
    if _depth(tree) > MAX_DEPTH:
        raise ExpressionError(f"{where}: the expression nests deeper than {MAX_DEPTH} levels")
    _check(tree, variable, where, text)
    return tree


def _depth(tree: ast.AST) -> int:
    deepest, stack = 0, [(tree, 1)]
    while stack:
        node, level = stack.pop()
        deepest = max(deepest, level)
        stack.extend((child, level + 1) for child in ast.iter_child_nodes(node))
    return deepest


def _allowed(variable: str) -> str:
    return (
        f"use numbers, {variable}, pi, e, + - * / ** and the functions "
        + ", ".join(sorted(FUNCTIONS))
    )


def _check(node: ast.AST, variable: str, where: str, text: str) -> None:
    """Refuse every node outside the whitelist, naming the offending piece."""
    callees = {id(sub.func) for sub in ast.walk(node) if isinstance(sub, ast.Call)}
    for sub in ast.walk(node):
        if isinstance(sub, (ast.Add, ast.Sub, ast.Mult, ast.Div, ast.Pow, ast.USub, ast.UAdd, ast.Load)):
            continue
        if isinstance(sub, ast.Constant) and type(sub.value) in (int, float):
            if abs(sub.value) > 1e300 or not math.isfinite(sub.value):
                raise ExpressionError(f"{where}: the number {sub.value!r:.40} in the expression is too large")
            continue
        if isinstance(sub, ast.Name) and (sub.id == variable or sub.id in CONSTANTS):
            continue
        if isinstance(sub, ast.BinOp) and type(sub.op) in _OPERATORS:
            continue
        if isinstance(sub, ast.UnaryOp) and isinstance(sub.op, (ast.USub, ast.UAdd)):
            continue
        if isinstance(sub, ast.Call):
            name = sub.func.id if isinstance(sub.func, ast.Name) else None
            if name in FUNCTIONS and len(sub.args) == 1 and not sub.keywords:
                continue
            callee = name or ast.unparse(sub.func)
            raise ExpressionError(
                f"{where}: call {quoted(callee, QUOTED)} in {quoted(text, QUOTED)} is not allowed; functions take one argument: "
                + ", ".join(sorted(FUNCTIONS))
            )
        if isinstance(sub, ast.Name) and id(sub) in callees and sub.id in FUNCTIONS:
            continue
        piece = ast.unparse(sub) if isinstance(sub, ast.expr) else type(sub).__name__
        raise ExpressionError(f"{where}: {quoted(piece, QUOTED)} in {quoted(text, QUOTED)} is not allowed; {_allowed(variable)}")


def _depends_on(node: ast.AST, variable: str) -> bool:
    return any(isinstance(sub, ast.Name) and sub.id == variable for sub in ast.walk(node))


def _evaluate(node: ast.expr, x: Jet, variable: str) -> Jet:
    if isinstance(node, ast.Constant):
        return _constant(float(node.value))
    if isinstance(node, ast.Name):
        return x if node.id == variable else _constant(CONSTANTS[node.id])
    if isinstance(node, ast.UnaryOp):
        u = _evaluate(node.operand, x, variable)
        return u if isinstance(node.op, ast.UAdd) else (-u[0], -u[1], -u[2])
    if isinstance(node, ast.Call):
        f, d1, d2 = FUNCTIONS[node.func.id]
        u = _evaluate(node.args[0], x, variable)
        return _compose(f, d1, d2, u)
    u = _evaluate(node.left, x, variable)
    if isinstance(node.op, ast.Pow) and not _depends_on(node.right, variable):
        return _power(u, float(_evaluate(node.right, x, variable)[0]))
    v = _evaluate(node.right, x, variable)
    if isinstance(node.op, ast.Add):
        return u[0] + v[0], u[1] + v[1], u[2] + v[2]
    if isinstance(node.op, ast.Sub):
        return u[0] - v[0], u[1] - v[1], u[2] - v[2]
    if isinstance(node.op, ast.Mult):
        return u[0] * v[0], u[1] * v[0] + u[0] * v[1], u[2] * v[0] + 2 * u[1] * v[1] + u[0] * v[2]
    if isinstance(node.op, ast.Div):
        w0 = u[0] / v[0]
        w1 = (u[1] - w0 * v[1]) / v[0]
        return w0, w1, (u[2] - 2 * w1 * v[1] - w0 * v[2]) / v[0]
    # u ** v with v depending on the variable: exp(v log u), defined for u > 0
    exp, log = FUNCTIONS["exp"], FUNCTIONS["log"]
    log_u = _compose(*log, u)
    product = (
        v[0] * log_u[0],
        v[1] * log_u[0] + v[0] * log_u[1],
        v[2] * log_u[0] + 2 * v[1] * log_u[1] + v[0] * log_u[2],
    )
    return _compose(*exp, product)


def _constant(value: float) -> Jet:
    return np.float64(value), np.float64(0.0), np.float64(0.0)


def _compose(f, d1, d2, u: Jet) -> Jet:
    """g(u): (g(u), g'(u) u', g''(u) u'^2 + g'(u) u'')."""
    g1 = d1(u[0])
    return f(u[0]), g1 * u[1], d2(u[0]) * u[1] * u[1] + g1 * u[2]


def _power(u: Jet, k: float) -> Jet:
    """u ** k for a constant k: (u^k, k u^(k-1) u', k (k-1) u^(k-2) u'^2 + k u^(k-1) u'')."""
    g1 = k * u[0] ** (k - 1) if k != 0 else np.zeros_like(u[0])
    g2 = k * (k - 1) * u[0] ** (k - 2) if k not in (0.0, 1.0) else np.zeros_like(u[0])
    return u[0] ** k, g1 * u[1], g2 * u[1] * u[1] + g1 * u[2]
