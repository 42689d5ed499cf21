"""A function ``y = f(x)`` written as text, read safely: ``"log10(x)"``, ``"x**2"``,
``"sin(pi*x/2)"``.

The text is parsed with :mod:`ast` and only a small whitelist is accepted: the variable ``x``,
numbers, the constants ``pi`` and ``e``, ``+ - * / **`` and unary minus, and calls of the
functions in :data:`FUNCTIONS` (numpy's, which also take CasADi symbols). Nothing is evaluated
while parsing, and no name outside the whitelist (no attribute, no subscript, no keyword) gets
through: the text can compute a number and nothing else.

>>> f = parse_function("log10(x)")
>>> float(f(100.0))
2.0
"""

from __future__ import annotations

import ast
import operator

import numpy as np

from ..errors import MechanismError

__all__ = ["FUNCTIONS", "parse_function", "Expression"]

#: functions an expression may call
FUNCTIONS = {
    "sin": np.sin,
    "cos": np.cos,
    "tan": np.tan,
    "arcsin": np.arcsin,
    "arccos": np.arccos,
    "arctan": np.arctan,
    "asin": np.arcsin,
    "acos": np.arccos,
    "atan": np.arctan,
    "sinh": np.sinh,
    "cosh": np.cosh,
    "tanh": np.tanh,
    "exp": np.exp,
    "log": np.log,
    "ln": np.log,
    "log10": np.log10,
    "log2": np.log2,
    "sqrt": np.sqrt,
    "abs": np.abs,
}
_CONSTANTS = {"pi": np.pi, "e": np.e}
_BINARY = {
    ast.Add: operator.add,
    ast.Sub: operator.sub,
    ast.Mult: operator.mul,
    ast.Div: operator.truediv,
    ast.Pow: operator.pow,
}
_UNARY = {ast.USub: operator.neg, ast.UAdd: operator.pos}
_MAX_TEXT = 1000


class Expression:
    """A parsed ``f(x)``: call it with numbers, numpy arrays or CasADi symbols.

    Attributes
    ----------
    text : the expression as given.
    """

    def __init__(self, text: str, tree: ast.AST):
        self.text = text
        self._tree = tree

    def __call__(self, x):
        return _eval(self._tree, x)

    def __repr__(self) -> str:
        return f"Expression({self.text!r})"


def _eval(node, x):
    if isinstance(node, ast.Expression):
        return _eval(node.body, x)
    if isinstance(node, ast.Constant):
        return float(node.value)
    if isinstance(node, ast.Name):
        return x if node.id == "x" else _CONSTANTS[node.id]
    if isinstance(node, ast.BinOp):
        return _BINARY[type(node.op)](_eval(node.left, x), _eval(node.right, x))
    if isinstance(node, ast.UnaryOp):
        return _UNARY[type(node.op)](_eval(node.operand, x))
    # a call (the only node left after checking)
    return FUNCTIONS[node.func.id](_eval(node.args[0], x))


def _check(node, text: str) -> None:
    """Raise MechanismError unless every node of ``node`` is on the whitelist."""
    where = f"function {text!r}"
    if isinstance(node, ast.Expression):
        return _check(node.body, text)
    if isinstance(node, ast.Constant):
        if isinstance(node.value, bool) or not isinstance(node.value, (int, float)):
            raise MechanismError(f"{where}: only real numbers may appear, got {node.value!r}")
        return None
    if isinstance(node, ast.Name):
        if node.id != "x" and node.id not in _CONSTANTS:
            hint = " (a function needs its argument in parentheses)" if node.id in FUNCTIONS else ""
            raise MechanismError(
                f"{where}: unknown name {node.id!r}{hint}; the variable is x, the constants "
                "pi and e"
            )
        return None
    if isinstance(node, ast.BinOp):
        if type(node.op) not in _BINARY:
            raise MechanismError(
                f"{where}: operator {type(node.op).__name__} not allowed (use + - * / **)"
            )
        _check(node.left, text)
        return _check(node.right, text)
    if isinstance(node, ast.UnaryOp):
        if type(node.op) not in _UNARY:
            raise MechanismError(f"{where}: operator {type(node.op).__name__} not allowed")
        return _check(node.operand, text)
    if isinstance(node, ast.Call):
        name = node.func.id if isinstance(node.func, ast.Name) else None
        if name not in FUNCTIONS:
            raise MechanismError(
                f"{where}: unknown function {ast.unparse(node.func)!r}; allowed: "
                f"{', '.join(sorted(FUNCTIONS))}"
            )
        if len(node.args) != 1 or node.keywords:
            raise MechanismError(f"{where}: {name}() takes exactly one argument")
        return _check(node.args[0], text)
    raise MechanismError(
        f"{where}: {type(node).__name__} not allowed; write an expression in x with numbers, "
        "+ - * / **, pi, e and the functions " + ", ".join(sorted(FUNCTIONS))
    )


def parse_function(text) -> Expression:
    """``text`` (an expression in ``x``) as a callable :class:`Expression`, or MechanismError
    naming what is wrong (a syntax error, an unknown name or function, a disallowed construct).
    ``^`` is read as a power, as in most calculators."""
    if not isinstance(text, str):
        raise MechanismError(f"function must be an expression in x (a str), got {text!r}")
    if not text.strip():
        raise MechanismError("function is empty: give an expression in x, e.g. 'log10(x)'")
    if len(text) > _MAX_TEXT:
        raise MechanismError(f"function: at most {_MAX_TEXT} characters, got {len(text)}")
    src = text.strip().replace("^", "**")
    try:
        tree = ast.parse(src, mode="eval")
    except SyntaxError as exc:
        raise MechanismError(
            f"function {text!r} cannot be parsed ({exc.msg} at column {exc.offset})"
        ) from None
    _check(tree, text)
    return Expression(text, tree)
