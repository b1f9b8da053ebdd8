"""How much of the model's output prompt-lookup drafting would have guessed (offline, no decoding).

Prompt-lookup speculative decoding drafts the next ``k`` tokens by finding the context's last
``n`` tokens (n = 3, 2, 1) earlier in the context and copying what followed them; the model then
checks a whole draft in one decode and keeps the tokens it agrees with. It pays when drafts are
accepted often (the model's programs copy names and calls from their prompts) and a decode of
``k + 1`` tokens costs little more than one. This script measures the first factor on recorded
episodes: for each recorded program, the context is its prompt file (``lmp/prompts``) and its
query — the examples retrieved per query are left out, so matches are undercounted — and the
generated tokens are the recorded code, tokenised with the default model's vocabulary (loaded
without weights). It reports the share of generated tokens a draft would have supplied and the
decode calls needed per generated token. The second factor (the cost of a ``k + 1``-token
decode against one) is a separate timing on a quiet machine.

    python benchmarks/lookup_drafting.py RECORDS.jsonl [...] [--draft 8] [--match 3]
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from llama_cpp import Llama
from rich.console import Console

from voxposer.lmp.backends.config import default_model_dir
from voxposer.lmp.backends.default_model import installed_path

PROMPTS = Path(__file__).resolve().parents[1] / "src/voxposer/lmp/prompts"


def draft_after(seq: list[int], k: int, n_max: int) -> list[int]:
    """Up to ``k`` tokens that followed the latest earlier occurrence of ``seq``'s last n tokens
    (the longest n <= ``n_max`` that occurs); empty when none does."""
    for n in range(min(n_max, len(seq) - 1), 0, -1):
        pattern = seq[-n:]
        for j in range(len(seq) - n - 1, -1, -1):
            if seq[j:j + n] == pattern:
                return seq[j + n:j + n + k]
    return []


def decode_calls(context: list[int], generated: list[int], k: int, n_max: int
                 ) -> tuple[int, int]:
    """(decode calls, drafted tokens accepted) to generate ``generated`` after ``context`` with
    greedy verification: each call keeps the agreeing prefix of its draft plus one token."""
    calls = accepted = i = 0
    while i < len(generated):
        draft = draft_after(context + generated[:i], k, n_max)
        m = 0
        while m < len(draft) and i + m < len(generated) and draft[m] == generated[i + m]:
            m += 1
        calls += 1
        accepted += m
        i += m + 1
    return calls, accepted


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("records", nargs="+", type=Path, help="episodes.jsonl files")
    parser.add_argument("--draft", type=int, default=8, help="tokens per draft (k)")
    parser.add_argument("--match", type=int, default=3, help="longest n-gram looked up")
    args = parser.parse_args()
    console = Console(stderr=True)
    missing = [str(f) for f in args.records if not f.is_file()]
    if missing:
        raise SystemExit(f"no such records file: {', '.join(missing)} (give episodes.jsonl files)")
    path = installed_path(default_model_dir())
    if path is None:
        raise SystemExit("the default model is not installed; run the README's setup first")
    vocab = Llama(model_path=str(path), vocab_only=True, verbose=False)

    def tokens(text: str) -> list[int]:
        return list(vocab.tokenize(text.encode(), add_bos=False, special=False))

    prompts = {p.stem: tokens(p.read_text()) for p in PROMPTS.glob("*.txt")}
    generated = calls = accepted = programs = 0
    for file in args.records:
        for line in file.read_text().splitlines():
            for prog in json.loads(line).get("programs") or []:
                if prog.get("lmp") not in prompts or not prog.get("code"):
                    continue
                gen = tokens(prog["code"])
                c, a = decode_calls(prompts[prog["lmp"]] + tokens(prog["query"] + "\n"), gen,
                                    args.draft, args.match)
                generated += len(gen)
                calls += c
                accepted += a
                programs += 1
    if not generated:
        raise SystemExit("no recorded program with a known prompt in these records")
    console.print(f"{programs} programs, {generated} generated tokens: a draft of {args.draft} "
                  f"would have supplied {accepted} ({accepted / generated:.0%}); "
                  f"{calls} decode calls, {generated / calls:.2f} tokens per call")
    print(f"programs={programs} tokens={generated} accepted_share={accepted / generated:.3f} "
          f"tokens_per_call={generated / calls:.2f} draft={args.draft} match={args.match}")


if __name__ == "__main__":
    main()
