"""The results JSONL: reading records, their identity, and which code versions they come from.

A record's identity (:func:`record_key`) is (method, llm, instruction split, task, attribute
split, seed, disturbed); ``--resume`` skips the jobs whose identity the file already has. Its code version
is ``code_hash`` (:mod:`voxposer.bench.version`); records written before versions were stamped
count as version ``"unknown"``. Neither a resumed file nor a report mixes versions unless asked
to (``--allow-mixed-versions``).

Each record is appended as one line in one unbuffered write (:func:`append_record`), so a
stopped run leaves whole lines; a run killed during a write (``kill -9``, a power cut) can leave
a torn last line, which :func:`load_records` skips and :func:`repair_torn_tail` removes before
more lines are appended.
"""

from __future__ import annotations

import json
import logging
from collections.abc import Iterable
from pathlib import Path
from typing import Any, BinaryIO, Final

from voxposer.errors import ConfigError

log = logging.getLogger(__name__)

#: the code version of records that carry none (written before versions were recorded).
UNKNOWN_VERSION: Final = "unknown"
MIXED_FLAG: Final = "--allow-mixed-versions"


def load_records(path: Path) -> list[dict[str, Any]]:
    """Records of a results JSONL (a torn last line from an interruption is skipped)."""
    if not path.is_file():
        return []
    out = []
    for line in path.read_text(encoding="utf-8").splitlines():
        try:
            out.append(json.loads(line))
        except json.JSONDecodeError:
            log.warning("skipping a torn line in %s", path)
    return out


def repair_torn_tail(path: Path) -> int:
    """Make ``path`` end with a whole line before more are appended: a last line without its
    newline that is a whole record gets the newline, a torn one is cut off (else the next record
    would be glued to it and lost too). Returns the number of bytes cut (0: nothing torn)."""
    if not path.is_file():
        return 0
    data = path.read_bytes()
    if not data or data.endswith(b"\n"):
        return 0
    cut = data.rfind(b"\n") + 1
    with path.open("r+b") as fh:
        try:
            json.loads(data[cut:])
        except ValueError:
            fh.truncate(cut)
            log.warning("%s: cut off a torn last line (%d bytes; an episode being written when "
                        "the run was killed)", path, len(data) - cut)
            return len(data) - cut
        fh.seek(0, 2)
        fh.write(b"\n")
    return 0


def append_record(fh: BinaryIO, record: dict[str, Any]) -> None:
    """Append ``record`` to ``fh`` (a results file opened ``"ab", buffering=0``) as one line, in
    one write where the OS allows."""
    view = memoryview((json.dumps(record) + "\n").encode("utf-8"))
    while view:
        written = fh.write(view)
        if not written:
            raise OSError(f"could not append a record to {getattr(fh, 'name', fh)!r}")
        view = view[written:]


def record_key(r: dict[str, Any]) -> tuple[Any, ...]:
    """The identity of a record (matches :attr:`EpisodeJob.key`); records without an
    instruction split were run with seen instructions, records without ``disturbed`` static."""
    return (r["method"], r["llm"], r.get("instructions", "seen"), r["task"], r["split"],
            r["seed"], bool(r.get("disturbed", False)))


def record_version(r: dict[str, Any]) -> str:
    """The code hash of a record (:data:`UNKNOWN_VERSION` when it has none)."""
    return str(r.get("code_hash") or UNKNOWN_VERSION)


def code_versions(records: Iterable[dict[str, Any]]) -> dict[str, dict[str, Any]]:
    """code hash → {"episodes", "commits", "prompts" (prompt hashes, sorted), "dirty" (any
    record from a dirty checkout)}."""
    out: dict[str, dict[str, Any]] = {}
    for r in records:
        v = out.setdefault(record_version(r), {"episodes": 0, "commits": set(), "prompts": set(),
                                               "dirty": False})
        v["episodes"] += 1
        for name, value in (("commits", r.get("git_commit")), ("prompts", r.get("prompt_hash"))):
            if value:
                v[name].add(str(value))
        v["dirty"] = v["dirty"] or bool(r.get("git_dirty"))
    for v in out.values():
        v["commits"], v["prompts"] = sorted(v["commits"]), sorted(v["prompts"])
    return out


def check_resumable(path: Path, old: list[dict[str, Any]], current: str,
                    allow_mixed: bool = False) -> None:
    """Refuse to append episodes of code version ``current`` to records of other versions.

    Raises:
        ConfigError: ``old`` holds records whose code hash is not ``current`` (names both, and
            the flag that allows it), unless ``allow_mixed``.
    """
    others = sorted({record_version(r) for r in old} - {current})
    if others and not allow_mixed:
        raise ConfigError(f"{path} holds episodes of code version {', '.join(others)}, but the "
                          f"running code is version {current}; resuming would mix versions in "
                          f"one file. Choose another --out, or pass {MIXED_FLAG} to resume "
                          "anyway")
    if others:
        log.warning("resuming %s (code %s) with code %s", path, ", ".join(others), current)


def check_single_version(records: Iterable[dict[str, Any]], allow_mixed: bool = False) -> None:
    """Refuse to aggregate records of more than one code version unless ``allow_mixed``.

    Raises:
        ConfigError: names the versions found and the flag that allows mixing them.
    """
    versions = sorted(code_versions(records))
    if len(versions) > 1 and not allow_mixed:
        raise ConfigError(f"the records come from {len(versions)} code versions "
                          f"({', '.join(versions)}); a report aggregates one version. Report "
                          f"each separately, or pass {MIXED_FLAG} (allow_mixed=True) to "
                          "aggregate them anyway")
