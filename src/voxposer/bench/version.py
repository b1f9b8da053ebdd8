"""Which code produced an episode: a content hash of the ``voxposer`` package, plus git state.

The identity used for comparisons (``--resume``, the report's refusal to mix versions) is
:attr:`CodeVersion.code_hash`: SHA-256 over the installed package's source files (``*.py``,
prompt ``*.txt``, ``*.json``; relative path and bytes of each, in path order). It does not
depend on git, so committing result files under ``benchmarks/`` leaves it unchanged, while any
edit of the package's code or prompts changes it. The git commit and dirty flag (uncommitted
changes under ``src/``) are recorded for humans when the package runs from a git checkout.
"""

from __future__ import annotations

import functools
import hashlib
import logging
import subprocess
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import Final

log = logging.getLogger(__name__)

#: file suffixes that make up the package's code (the prompts are ``*.txt``).
SOURCE_SUFFIXES: Final = (".py", ".txt", ".json")
#: length of the hex digests kept in records [characters] (64 bits).
HASH_CHARS: Final = 16
_GIT_TIMEOUT_S: Final = 10.0


@dataclass(frozen=True)
class CodeVersion:
    """The code version stamped on every episode record.

    Attributes:
        code_hash: content hash of the package source (hex, :data:`HASH_CHARS` long).
        prompt_hash: content hash of the prompt files ``voxposer/lmp/prompts/*.txt``.
        commit: git commit of the checkout (None when not running from a git checkout).
        dirty: uncommitted changes under ``src/`` (None when not a git checkout).
    """

    code_hash: str
    prompt_hash: str
    commit: str | None = None
    dirty: bool | None = None

    def describe(self) -> str:
        """``"3f2a… (commit 1a2b3c4d, dirty)"`` for reports."""
        if self.commit is None:
            return f"{self.code_hash} (not a git checkout)"
        return f"{self.code_hash} (commit {self.commit[:10]}{', dirty' if self.dirty else ''})"


def _digest(root: Path, files: Iterable[Path]) -> str:
    h = hashlib.sha256()
    for path in sorted(files, key=lambda p: p.relative_to(root).as_posix()):
        h.update(path.relative_to(root).as_posix().encode() + b"\0")
        h.update(path.read_bytes() + b"\0")
    return h.hexdigest()[:HASH_CHARS]


def source_files(root: Path) -> list[Path]:
    """The package's source files under ``root`` (no ``__pycache__``)."""
    return [p for p in root.rglob("*") if p.is_file() and p.suffix in SOURCE_SUFFIXES
            and "__pycache__" not in p.parts]


def package_hash(root: Path) -> str:
    """Content hash of the source files under ``root`` (see the module docstring)."""
    return _digest(root, source_files(root))


def prompts_hash(root: Path) -> str:
    """Content hash of ``root/lmp/prompts/*.txt``."""
    prompts = root / "lmp" / "prompts"
    return _digest(root, [p for p in prompts.glob("*.txt") if p.is_file()])


def _git(cwd: Path, *args: str) -> str | None:
    try:
        done = subprocess.run(["git", "-C", str(cwd), *args], capture_output=True, text=True,
                              timeout=_GIT_TIMEOUT_S, check=False)
    except (OSError, subprocess.TimeoutExpired) as exc:
        log.debug("git %s failed: %s", " ".join(args), exc)
        return None
    return done.stdout.strip() if done.returncode == 0 else None


def git_state(src: Path, package: str = "voxposer") -> tuple[str | None, bool | None]:
    """(commit, dirty) of the git checkout holding ``src`` — dirty when anything under ``src``
    differs from the commit (untracked files included); (None, None) when ``src/<package>`` is
    not tracked by git (an installed copy, even one inside an ignored folder of a checkout)."""
    if not _git(src, "ls-files", "--", f"{package}/__init__.py"):
        return None, None
    commit = _git(src, "rev-parse", "HEAD")
    status = _git(src, "status", "--porcelain", "--", ".")
    return commit, (None if status is None else bool(status))


@functools.cache
def code_version() -> CodeVersion:
    """The running package's version, computed once per process."""
    import voxposer

    root = Path(voxposer.__file__).resolve().parent
    commit, dirty = git_state(root.parent)
    return CodeVersion(package_hash(root), prompts_hash(root), commit, dirty)
