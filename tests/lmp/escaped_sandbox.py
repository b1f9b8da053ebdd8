"""A sandbox whose worker runs code with plain ``exec``: what a RestrictedPython escape would get.

Kept in its own small module because the process sandbox's worker imports it (by name, to build
its in-process sandbox); a test module would drag pytest into every worker.
"""

from __future__ import annotations

from typing import Any

from voxposer.lmp.sandbox import Sandbox


class EscapedSandbox(Sandbox):
    """Runs code unrestricted: only the process sandbox's OS limits apply."""

    def run(self, code: Any, variables: Any) -> dict[str, Any]:
        namespace = dict(variables)
        exec(code, namespace)
        return namespace
