"""Compiling untrusted code for the sandbox: a static check, RestrictedPython, size guards.

Three passes over the generated code's syntax tree: a static check refusing imports, ``try``,
``class``, ``global``, dangerous names (``eval``, ``exec``, ``open``, ``getattr``, ``globals``…),
private and dunder names, frame/code attributes and huge or computed f-string widths, with
messages the LLM can act on;
RestrictedPython's transformer, which guards every attribute read, item access, write and
iteration; and a rewrite of arithmetic into size-checked calls (:mod:`voxposer.lmp.sandbox_limits`).
"""

from __future__ import annotations

import ast
import re
import sys
import types
from typing import Final

from RestrictedPython.transformer import RestrictingNodeTransformer

from voxposer.errors import SandboxError

#: File name given to sandboxed code objects (the time limit traces only these frames).
SANDBOX_FILENAME: Final = "<voxposer-lmp>"
#: Names generated code may not mention, with the reason shown to the model.
REFUSED_NAMES: Final[dict[str, str]] = {
    **dict.fromkeys(("exec", "eval", "compile"), "running dynamic code"),
    **dict.fromkeys(("getattr", "setattr", "delattr", "hasattr", "vars", "dir"), "reflection"),
    **dict.fromkeys(("globals", "locals"), "access to namespaces"),
    **dict.fromkeys(("open", "input", "breakpoint", "help", "exit", "quit", "memoryview"), "I/O"),
    **dict.fromkeys(("type", "object", "super", "classmethod", "staticmethod", "property"),
                    "type manipulation"),
    "__import__": "imports", "__builtins__": "access to builtins",
}
#: Attribute names refused on any object (frames, code, generators, formatting tricks, files).
REFUSED_ATTRS: Final = frozenset({
    "format", "format_map", "mro", "tofile", "dump", "dumps", "ctypes", "ljust",
    "rjust", "center", "zfill", "expandtabs",
})
REFUSED_ATTR_PREFIXES: Final = ("_", "f_", "gi_", "cr_", "ag_", "tb_", "co_", "func_")
#: Widest f-string field (width or precision) generated code may ask for [characters].
MAX_FORMAT_WIDTH: Final = 10_000
_SPEC_NUMBERS: Final = re.compile(r"\d+")


# ------------------------------------------------------------------------ static check
class _StaticCheck(ast.NodeVisitor):
    """Refuses constructs before RestrictedPython sees the code (clear messages for the LLM)."""

    _REFUSED_NODES: Final = {
        ast.Import: "import statements", ast.ImportFrom: "import statements",
        ast.Global: "global statements", ast.Nonlocal: "nonlocal statements",
        ast.Try: "try/except", ast.ClassDef: "class definitions", ast.With: "with statements",
        ast.AsyncFunctionDef: "async code", ast.AsyncWith: "async code",
        ast.AsyncFor: "async code", ast.Await: "async code",
    }

    def generic_visit(self, node: ast.AST) -> None:
        for kind, what in self._REFUSED_NODES.items():
            if isinstance(node, kind):
                raise SandboxError(f"refused: {what} are not allowed (line "
                                   f"{getattr(node, 'lineno', '?')})")
        if sys.version_info >= (3, 11) and type(node).__name__ == "TryStar":
            raise SandboxError("refused: try/except is not allowed")
        super().generic_visit(node)

    def visit_Name(self, node: ast.Name) -> None:
        if node.id in REFUSED_NAMES:
            raise SandboxError(f"refused: `{node.id}` ({REFUSED_NAMES[node.id]}) is not allowed "
                               f"(line {node.lineno})")
        if node.id.startswith("_") and node.id != "_":
            raise SandboxError(f"refused: private or dunder name `{node.id}` (line {node.lineno})")

    def visit_Attribute(self, node: ast.Attribute) -> None:
        check_attr_name(node.attr, f" (line {node.lineno})")
        self.generic_visit(node)

    def visit_FormattedValue(self, node: ast.FormattedValue) -> None:
        """f-string fields: a constant spec only, its width/precision at most 10,000."""
        spec = node.format_spec
        if spec is not None:
            parts = spec.values if isinstance(spec, ast.JoinedStr) else [spec]
            if not all(isinstance(p, ast.Constant) for p in parts):
                raise SandboxError(f"refused: a computed format spec in an f-string (line "
                                   f"{node.lineno}); write the width as a number")
            text = "".join(str(p.value) for p in parts if isinstance(p, ast.Constant))
            widest = max((int(n) for n in _SPEC_NUMBERS.findall(text)), default=0)
            if widest > MAX_FORMAT_WIDTH:
                raise SandboxError(f"size limit: the f-string field width {widest} (line "
                                   f"{node.lineno}) is above {MAX_FORMAT_WIDTH:,}")
        self.visit(node.value)


def check_attr_name(name: str, where: str = "") -> None:
    """Refuse private/dunder/frame attribute names and :data:`REFUSED_ATTRS` on any object.

    Runs at compile time and again at run time, before the attribute allowlist
    (:mod:`voxposer.lmp.sandbox_attrs`) looks at the object.
    """
    if name.startswith(REFUSED_ATTR_PREFIXES):
        kind = "dunder" if name.startswith("__") else "private or internal"
        raise SandboxError(f"refused: {kind} attribute `.{name}`{where}")
    if name in REFUSED_ATTRS:
        raise SandboxError(f"refused: attribute `.{name}`{where}")


class _AugAssignToAssign(ast.NodeTransformer):
    """``a[k] += v`` → ``a[k] = a[k] + v`` (RestrictedPython refuses item augmented assignment)."""

    def visit_AugAssign(self, node: ast.AugAssign) -> ast.AST:
        if not isinstance(node.target, ast.Subscript):
            return node
        load = ast.Subscript(value=node.target.value, slice=node.target.slice, ctx=ast.Load())
        binop = ast.BinOp(load, node.op, node.value)
        new = ast.Assign(targets=[node.target], value=binop)
        for made in (load, binop, new):
            ast.copy_location(made, node)
        return new


_OP_SYMBOLS: Final = {
    ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/", ast.FloorDiv: "//", ast.Mod: "%",
    ast.Pow: "**", ast.LShift: "<<", ast.RShift: ">>", ast.BitAnd: "&", ast.BitOr: "|",
    ast.BitXor: "^", ast.MatMult: "@",
}


class _GuardBinOps(ast.NodeTransformer):
    """``a <op> b`` → ``_binop_("<op>", a, b)`` (size-checked arithmetic)."""

    def visit_BinOp(self, node: ast.BinOp) -> ast.AST:
        self.generic_visit(node)
        call = ast.Call(func=ast.Name("_binop_", ast.Load()),
                        args=[ast.Constant(_OP_SYMBOLS[type(node.op)]), node.left, node.right],
                        keywords=[])
        return ast.copy_location(call, node)


def compile_sandboxed(code: str) -> types.CodeType:
    """Compile generated code for :meth:`Sandbox.run`.

    Raises:
        SyntaxError: the code does not parse (shown to the model as is).
        SandboxError: the code uses a refused construct (the message names it).
    """
    tree = ast.parse(code, SANDBOX_FILENAME, "exec")
    _StaticCheck().visit(tree)
    tree = _AugAssignToAssign().visit(tree)
    errors: list[str] = []
    RestrictingNodeTransformer(errors, [], {}).visit(tree)
    if errors:
        raise SandboxError("refused: " + "; ".join(errors))
    tree = ast.fix_missing_locations(_GuardBinOps().visit(tree))
    return compile(tree, SANDBOX_FILENAME, "exec")
