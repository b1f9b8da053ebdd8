"""Getting code out of a model's answer: fenced blocks, or the largest parseable run of lines.

Chat models, especially when asked to correct an error, often wrap code in Markdown fences or
add prose around it.
"""

from __future__ import annotations

import ast
import re
from typing import Final

_FENCE: Final = re.compile(r"```[ \t]*([A-Za-z0-9_+-]*)[^\n]*\n(.*?)(?:```|\Z)", re.DOTALL)


def _is_code(text: str) -> bool:
    try:
        tree = ast.parse(text)
    except SyntaxError:
        return False
    return any(not isinstance(node, ast.Expr) or isinstance(node.value, ast.Call)
               for node in tree.body)


def extract_code(text: str) -> str:
    """The Python code in a model's answer (fenced ``python`` blocks preferred, else raw).

    When the raw text does not parse, the longest run of lines that does (and holds an
    assignment or a call) is returned; failing that, the raw text, so the syntax error is shown.
    """
    blocks = [(lang.lower(), body) for lang, body in _FENCE.findall(text)]
    if blocks:
        python = [b for lang, b in blocks if lang in ("python", "py", "python3")]
        chosen = python or [b for lang, b in blocks if not lang] or [blocks[0][1]]
        return "\n".join(b.strip("\n") for b in chosen).strip("\n") + "\n"
    raw = text.strip("\n")
    if _is_code(raw) or not raw.strip():
        return raw + "\n"
    lines = raw.splitlines()
    for length in range(len(lines), 0, -1):
        for start in range(0, len(lines) - length + 1):
            chunk = "\n".join(lines[start:start + length])
            if _is_code(chunk):
                return chunk + "\n"
    return raw + "\n"
