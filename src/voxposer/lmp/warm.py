"""Pre-evaluate every program's few-shot prefix so the first instruction pays only for its queries.

A local model reads each LMP's prompt prefix (system text + examples, 1–2k tokens) once, at about
50 tokens/s on 2 CPU cores; the backend keeps the resulting state on disk, keyed by model and
prompt. ``scripts/setup.sh`` runs this once after installing the model (``python -m
voxposer.lmp.warm``), like compiling ahead of time: already-saved prefixes are skipped, so re-runs
take seconds. Backends without prefix states (endpoints, replay) have nothing to warm.

Only the default prompts are warmed: an "unseen instruction" fold (``LMPConfig.held_out_task``)
evaluates its changed prefixes on first use, under their own prefix id and disk key, and reuses
them from disk afterwards; ``--held-out TASK`` warms one fold ahead of time.
"""

from __future__ import annotations

import argparse
import logging
import sys
import time
from typing import Any

from voxposer.lmp.backends import LLMConfig, make_backend
from voxposer.lmp.backends.base import LLMRequest
from voxposer.lmp.prompt import load_prompt
from voxposer.lmp.prompt_tags import TASK_NAMES
from voxposer.lmp.registry import LMP_SPECS, LMPConfig

log = logging.getLogger(__name__)


def _innermost(backend: Any) -> Any:
    while hasattr(backend, "inner"):
        backend = backend.inner
    return backend


def warm_prefixes(backend: Any, config: LMPConfig | None = None) -> dict[str, str]:
    """Evaluate (or find on disk) the prefix of every LMP's prompt (of the fold holding out
    ``config.held_out_task`` when set; each under the id the runtime sends it with).

    Returns:
        LMP name → how its prefix was obtained ("evaluated", "disk", …), or "unsupported" when
        the backend keeps no prefix states.
    """
    cfg = config or LMPConfig()
    target = _innermost(backend)
    if not hasattr(target, "warm_prefix"):
        return dict.fromkeys(LMP_SPECS, "unsupported")
    out: dict[str, str] = {}
    for name in LMP_SPECS:
        prompt = load_prompt(name, cfg.prompt_dir, held_out_task=cfg.held_out_task)
        request = LLMRequest(
            messages=prompt.messages("# Query: (warm-up)"),
            temperature=cfg.temperature,
            max_tokens=cfg.max_tokens,
            stop=cfg.stop,
            prefix_id=prompt.prefix_id,
        )
        info = target.warm_prefix(request)
        out[name] = str(info.get("prefix", info)) if isinstance(info, dict) else str(info)
    return out


def main(argv: list[str] | None = None) -> int:
    """``python -m voxposer.lmp.warm``: warm the configured backend's prefixes; print a summary."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--held-out", metavar="TASK", choices=TASK_NAMES, default=None,
                        help="warm the fold without this benchmark task's examples instead of "
                             "the default prompts")
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.WARNING)
    start = time.perf_counter()
    config = LMPConfig(held_out_task=args.held_out)
    backend = make_backend(LLMConfig.from_env())
    try:
        result = warm_prefixes(backend, config)
    finally:
        backend.close()
    print(
        f"prefixes of {len(result)} programs ready in {time.perf_counter() - start:.0f} s: "
        + ", ".join(f"{k}={v}" for k, v in result.items()),
        file=sys.stderr,
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
