"""Code versions: the package content hash, records stamped with it, ``--resume`` refusing a file
of another version, and ``--fresh-cache``'s own response cache (no simulation here)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import voxposer
from voxposer.bench import BenchConfig, EpisodeJob, EpisodeRecord, run_bench
from voxposer.bench.runner import _with_fresh_cache, fresh_cache_dir
from voxposer.bench.version import code_version, git_state, package_hash, prompts_hash
from voxposer.bench.workers import worker_llm_config
from voxposer.errors import ConfigError
from voxposer.lmp.backends.base import ChatMessage, LLMRequest, LLMResponse
from voxposer.lmp.backends.cache import ResponseCache
from voxposer.lmp.backends.config import LLMConfig
from voxposer.lmp.backends.factory import RESPONSE_CACHE_FILE


def _package(root: Path) -> Path:
    (root / "lmp" / "prompts").mkdir(parents=True)
    (root / "a.py").write_text("x = 1\n")
    (root / "data.json").write_text("{}")
    (root / "lmp" / "prompts" / "planner.txt").write_text("### system\nplan\n")
    return root


def test_code_hash_follows_the_source_content_only(tmp_path: Path) -> None:
    root = _package(tmp_path / "pkg")
    code, prompts = package_hash(root), prompts_hash(root)
    (root / "results.jsonl").write_text("{}\n")  # not source: same version
    (root / "__pycache__").mkdir()
    (root / "__pycache__" / "a.py").write_text("compiled")
    assert package_hash(root) == code
    (root / "a.py").write_text("x = 2\n")
    assert package_hash(root) != code and prompts_hash(root) == prompts
    (root / "lmp" / "prompts" / "planner.txt").write_text("### system\nplan better\n")
    assert prompts_hash(root) != prompts
    assert git_state(tmp_path) == (None, None)  # not a git checkout


def test_the_version_is_computed_once_and_stamped_on_records() -> None:
    version = code_version()
    assert code_version() is version
    assert version.code_hash == package_hash(Path(voxposer.__file__).resolve().parent)
    rec = EpisodeRecord.for_job(EpisodeJob("push_to_pos", "unseen", 100_003, llm="default",
                                           instructions="unseen", seed_set="test")).to_json()
    assert (rec["code_hash"], rec["prompt_hash"]) == (version.code_hash, version.prompt_hash)
    assert (rec["git_commit"], rec["git_dirty"]) == (version.commit, version.dirty)
    assert (rec["seed_set"], rec["instructions"]) == ("test", "unseen")


def _write(path: Path, code_hash: str) -> dict:
    job = BenchConfig(tasks=("move_to_region",), splits=("seen",), episodes=1).jobs()[0]
    rec = EpisodeRecord.for_job(job).to_json() | {"code_hash": code_hash, "success": True}
    path.write_text(json.dumps(rec) + "\n")
    return rec


def test_resume_refuses_another_code_version(tmp_path: Path) -> None:
    results = tmp_path / "episodes.jsonl"
    _write(results, "0123456789abcdef")
    cfg = BenchConfig(tasks=("move_to_region",), splits=("seen",), episodes=1, workers=1)
    current = code_version().code_hash
    with pytest.raises(ConfigError, match=rf"0123456789abcdef.*{current}.*--allow-mixed-versions"):
        run_bench(cfg, results, resume=True)
    records = run_bench(cfg, results, resume=True, allow_mixed_versions=True)
    assert len(records) == 1  # the one job was already there: nothing ran


def test_resume_of_the_same_version_continues(tmp_path: Path) -> None:
    results = tmp_path / "episodes.jsonl"
    old = _write(results, code_version().code_hash)
    cfg = BenchConfig(tasks=("move_to_region",), splits=("seen",), episodes=1, workers=1)
    started = []
    records = run_bench(cfg, results, resume=True, on_start=lambda *a: started.append(a))
    assert records == [old] and started == [(0, 1)]


def _fill(directory: Path) -> None:
    cache = ResponseCache(directory / RESPONSE_CACHE_FILE)
    request = LLMRequest(messages=(ChatMessage("user", "hi"),))
    cache.put(request.key("openai", "m"), "openai", request, LLMResponse("ret_val = 1", "m"))
    cache.close()


def test_fresh_cache_must_start_empty(tmp_path: Path) -> None:
    results = tmp_path / "episodes.jsonl"
    _fill(fresh_cache_dir(results))
    cfg = BenchConfig(tasks=("move_to_region",), splits=("seen",), episodes=1, workers=1,
                      fresh_cache=True)
    with pytest.raises(ConfigError, match=r"already holds 1 cached responses.*--resume"):
        run_bench(cfg, results)
    _write(results, code_version().code_hash)
    assert len(run_bench(cfg, results, resume=True)) == 1  # resuming that run is fine
    wired = _with_fresh_cache(cfg, results, resume=True)  # what the workers are given
    assert wired.llm_overrides["cache_dir"] == tmp_path / "cache"


def test_a_run_cache_keeps_the_shared_prefix_states(tmp_path: Path) -> None:
    shared = LLMConfig.from_env().resolved_prefix_cache_dir
    config = worker_llm_config("openai", {"model": "m", "cache_dir": tmp_path / "cache"})
    assert config.resolved_cache_dir == tmp_path / "cache"
    assert config.resolved_prefix_cache_dir == shared != tmp_path / "cache"
    plain = worker_llm_config("openai", {"model": "m"})
    assert plain.resolved_prefix_cache_dir == plain.resolved_cache_dir
