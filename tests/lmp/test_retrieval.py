"""Few-shot examples chosen per query from an LMP's example bank."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from voxposer.bench.paraphrases import PARAPHRASES
from voxposer.errors import ConfigError
from voxposer.lmp import LMP_SPECS, LMPConfig, LMPRuntime, RecordingHandler, make_tabletop_scene
from voxposer.lmp.backends.base import LLMRequest
from voxposer.lmp.backends.replay import ReplayBackend
from voxposer.lmp.prompt import BANK_DIR, Example, load_prompt, parse_bank
from voxposer.lmp.prompt_tags import TASK_NAMES
from voxposer.lmp.retrieval import ExampleBank, query_text, query_words

from .test_replay_and_prompts import UNSEEN
from .test_runtime_folds import Spy

RECORDINGS = Path(__file__).parent / "recordings"
PACKAGED = Path(__file__).parents[2] / "src" / "voxposer" / "lmp" / "prompts" / BANK_DIR
BANKED = sorted(p.stem for p in PACKAGED.glob("*.txt"))


def ex(query: str, *tasks: str) -> Example:
    return Example(f"# Query: {query}", f"answer to {query}", frozenset(tasks))


BANK = ExampleBank((
    ex("while keeping to the left of the blue block, go to the back side", "move_to_pos_staying_on_preposition"),
    ex("push the pink block to the right side", "push_to_pos"),
    ex("grab the green block at faster speed", "grasp_at_velocity"),
    ex("go to the right side and keep at least 9cm from the brown block", "move_to_pos_min_distance"),
))


def test_words_fold_colours_and_numbers_only() -> None:
    assert query_words("Push the RED block 10cm, to the left!") == \
        ["push", "<colour>", "block", "<n>", "cm", "to", "left"]


def test_the_nearest_examples_come_last_in_order_of_nearness() -> None:
    query = "while keeping to the left of the red block, head to the front side"
    chosen = BANK.nearest(query, 2)
    assert len(chosen) == 2
    assert chosen[-1] == BANK.examples[0]  # the same wording with another colour and place
    assert BANK.nearest("snatch the orange block at faster speed", 1) == (BANK.examples[2],)
    assert BANK.nearest(query, 0) == ()
    assert BANK.nearest("xyzzy", 3) == ()  # shares no word: nothing is chosen


def test_a_held_out_task_is_left_out_of_the_bank() -> None:
    fold = BANK.without_task("move_to_pos_staying_on_preposition")
    assert BANK.examples[0] not in fold.examples and len(fold.examples) == 3
    query = "while keeping to the left of the red block, head to the front side"
    assert BANK.examples[0] not in fold.nearest(query, 3)
    assert BANK.without_task("close_drawer") is BANK


def test_prompt_messages_put_the_chosen_examples_between_the_fixed_ones_and_the_query(
        tmp_path: Path) -> None:
    (tmp_path / BANK_DIR).mkdir()
    (tmp_path / "planner.txt").write_text(
        "### system\nplan\n### user [tasks: push_to_pos]\n# Query: push it\n### assistant\n"
        "composer('push it')\n", encoding="utf-8")
    (tmp_path / BANK_DIR / "planner.txt").write_text(
        "### user [tasks: grasp_at_velocity]\n# Query: grab the pink block quickly\n"
        "### assistant\ncomposer('grasp the pink block at faster speed')\n"
        "### user [tasks: none]\n# Query: wave hello\n### assistant\ncomposer('wave')\n",
        encoding="utf-8")
    prompt = load_prompt("planner", tmp_path)
    assert prompt.n_prefix_messages == 3
    plain = prompt.messages("# Query: grab the blue block quickly")
    chosen = prompt.messages("# Query: grab the blue block quickly", retrieved=1)
    assert chosen[:3] == plain[:3] and chosen[-1] == plain[-1]
    assert [m.content for m in chosen[3:5]] == ["# Query: grab the pink block quickly",
                                               "composer('grasp the pink block at faster speed')"]
    fold = load_prompt("planner", tmp_path, held_out_task="grasp_at_velocity")
    assert fold.prefix_id == "planner"  # only the bank lost an example: the same prefix
    assert fold.messages("# Query: grab the blue block quickly", retrieved=1) == plain


def test_a_bank_with_a_system_section_is_refused() -> None:
    with pytest.raises(ConfigError, match=r"bank of LMP 'planner' has a '### system' section"):
        parse_bank("planner", "### system\nx\n### user [tasks: none]\n# Query: q\n### assistant\na\n")


@pytest.mark.parametrize("name", BANKED)
def test_packaged_banks_parse_for_known_lmps_and_hold_no_unseen_attributes(name: str) -> None:
    assert name in LMP_SPECS
    bank = load_prompt(name).bank
    assert len(bank.examples) >= 3 and bank.tasks <= set(TASK_NAMES)
    text = "\n".join(e.user + "\n" + e.assistant for e in bank.examples).lower()
    for word in UNSEEN:  # "back side of the table" is a seen place, "back side of" a block not
        assert not re.search(rf"\b{re.escape(word)}\b(?! the table)", text), (name, word)
    fixed = {e.user for e in load_prompt(name).examples}
    assert not fixed & {e.user for e in bank.examples}  # a bank adds, never repeats


def test_no_planner_bank_example_is_a_paraphrase_of_the_benchmark() -> None:
    """The paraphrase split measures wordings the prompts have not seen: no instruction of the
    planner's bank is one of its phrasings with any attribute values."""
    patterns = [re.compile(re.sub(r"\\\[\w+\\\]", ".+", re.escape(p)) + r"\.?", re.IGNORECASE)
                for phrasings in PARAPHRASES.values() for p in phrasings]
    assert patterns[0].fullmatch("go to the left of the blue block.")  # the patterns match
    for example in load_prompt("planner").bank.examples:
        query = query_text(example.user)
        assert not any(p.fullmatch(query) for p in patterns), query


def planner_request(config: LMPConfig) -> LLMRequest:
    spy = Spy(ReplayBackend(RECORDINGS / "closed_loop.jsonl"))
    rt = LMPRuntime(make_tabletop_scene(), spy, handler=RecordingHandler(), config=config)
    rt.run("move to the left of the blue block while staying away from the green block")
    return next(r for r in spy.requests if r.prefix_id and r.prefix_id.startswith("planner"))


def test_the_runtime_sends_the_nearest_bank_examples_after_the_reusable_prefix() -> None:
    request = planner_request(LMPConfig(retrieved_examples=2))
    prompt = load_prompt("planner")
    assert request.prefix_messages == prompt.n_prefix_messages
    added = request.messages[prompt.n_prefix_messages:-1]
    banked = {e.user for e in prompt.bank.examples}
    assert len(added) == 4 and {m.content for m in added[::2]} <= banked
    assert request.context_messages == len(request.messages) - 1  # prefix + the chosen examples
    none = planner_request(LMPConfig(retrieved_examples=0))
    assert none.prefix_messages is None and len(none.messages) == prompt.n_prefix_messages + 1
    assert none.context_messages is None  # nothing beyond the prefix to keep


def test_retrieved_examples_is_validated() -> None:
    with pytest.raises(ConfigError, match=r"retrieved_examples must be an int in \[0, 8\]; got -1"):
        LMPConfig(retrieved_examples=-1)
