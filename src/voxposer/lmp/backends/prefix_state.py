"""Evaluated few-shot prefixes (a model's KV state) kept in memory and on disk.

Each language model program sends the same long prefix (API reference + examples) before every
query. Evaluating it costs ~30 s on two cores; its state is ~28 KB per token for the default
model (≈45 MB for 1,550 tokens). A :class:`PrefixState` is that state as raw bytes plus the
prefix's tokens; :class:`PrefixStateStore` saves it under a key made of the model file's
identity, the runtime version, the context size and the prefix text, so a new process restores
it in well under a second instead of re-evaluating. Old files are pruned (least recently used)
beyond a size budget.
"""

from __future__ import annotations

import hashlib
import json
import logging
import os
import re
import struct
from dataclasses import dataclass
from pathlib import Path

import numpy as np

log = logging.getLogger(__name__)

_MAGIC = b"VXPREFIX1\n"
_SUFFIX = ".kv"


@dataclass(frozen=True)
class PrefixState:
    """A model context right after evaluating a prefix.

    Attributes:
        key: the store key (see :func:`prefix_key`).
        tokens: the prefix's token ids, shape (n_tokens,), int32.
        data: the runtime's opaque state blob (KV cache and bookkeeping).
    """

    key: str
    tokens: np.ndarray
    data: bytes

    @property
    def n_tokens(self) -> int:
        """Number of prefix tokens."""
        return int(self.tokens.shape[0])

    @property
    def nbytes(self) -> int:
        """Memory held [bytes]."""
        return len(self.data) + int(self.tokens.nbytes)


def file_fingerprint(path: Path, known_sha256: str | None = None) -> str:
    """Cheap identity of a model file: its sha256 if known, else size + first/last MiB hashed."""
    if known_sha256:
        return known_sha256
    path = Path(path)
    size = path.stat().st_size
    digest = hashlib.sha256(str(size).encode())
    with open(path, "rb") as f:
        digest.update(f.read(1 << 20))
        f.seek(max(0, size - (1 << 20)))
        digest.update(f.read(1 << 20))
    return "fp-" + digest.hexdigest()


def prefix_key(model_fingerprint: str, runtime: str, n_ctx: int, prefix_text: str) -> str:
    """Store key of a prefix: sha256 of model identity, runtime version, n_ctx and the text."""
    blob = json.dumps([model_fingerprint, runtime, n_ctx, prefix_text], ensure_ascii=False)
    return hashlib.sha256(blob.encode()).hexdigest()


class PrefixStateStore:
    """Prefix states on disk, one file each, pruned to a size budget.

    Args:
        directory: where the ``*.kv`` files live (created when missing).
        max_bytes: total size kept [bytes]; the least recently used files go first.
    """

    def __init__(self, directory: Path, max_bytes: int = 2 << 30) -> None:
        self.directory = Path(directory)
        self.max_bytes = int(max_bytes)

    def _path(self, key: str, prefix_id: str | None) -> Path:
        label = re.sub(r"[^A-Za-z0-9_.-]+", "_", prefix_id or "prefix")[:40]
        return self.directory / f"{label}-{key[:24]}{_SUFFIX}"

    def _find(self, key: str) -> Path | None:
        if not self.directory.is_dir():
            return None
        matches = list(self.directory.glob(f"*-{key[:24]}{_SUFFIX}"))
        return matches[0] if matches else None

    def load(self, key: str) -> PrefixState | None:
        """The stored state for ``key``, or None (a corrupt file is deleted)."""
        path = self._find(key)
        if path is None:
            return None
        try:
            with open(path, "rb") as f:
                if f.read(len(_MAGIC)) != _MAGIC:
                    raise ValueError("bad magic")
                (header_len,) = struct.unpack("<Q", f.read(8))
                header = json.loads(f.read(header_len))
                if header["key"] != key:
                    raise ValueError("key mismatch")
                n = int(header["n_tokens"])
                tokens = np.frombuffer(f.read(4 * n), dtype="<i4").astype(np.int32)
                data = f.read()
            if tokens.shape[0] != n or len(data) != int(header["data_bytes"]):
                raise ValueError("truncated")
        except (OSError, ValueError, KeyError, struct.error) as exc:
            log.warning("discarding unreadable prefix state %s (%s)", path, exc)
            path.unlink(missing_ok=True)
            return None
        os.utime(path)  # mark as recently used
        return PrefixState(key=key, tokens=tokens, data=data)

    def save(self, state: PrefixState, prefix_id: str | None = None) -> Path:
        """Write ``state`` atomically, then prune to the size budget."""
        self.directory.mkdir(parents=True, exist_ok=True)
        path = self._path(state.key, prefix_id)
        header = json.dumps(
            {
                "key": state.key,
                "prefix_id": prefix_id,
                "n_tokens": state.n_tokens,
                "data_bytes": len(state.data),
            }
        ).encode()
        tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
        try:
            with open(tmp, "wb") as f:
                f.write(_MAGIC)
                f.write(struct.pack("<Q", len(header)))
                f.write(header)
                f.write(state.tokens.astype("<i4").tobytes())
                f.write(state.data)
            os.replace(tmp, path)
        except BaseException:
            tmp.unlink(missing_ok=True)
            raise
        self.prune()
        return path

    def prune(self) -> None:
        """Delete least recently used files until the total fits ``max_bytes``."""
        files = sorted(self.directory.glob(f"*{_SUFFIX}"), key=lambda p: p.stat().st_mtime)
        total = sum(p.stat().st_size for p in files)
        for path in files:
            if total <= self.max_bytes:
                break
            total -= path.stat().st_size
            log.info("pruning prefix state %s", path.name)
            path.unlink(missing_ok=True)
