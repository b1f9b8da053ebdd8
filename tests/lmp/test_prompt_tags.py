"""Task tags on few-shot examples and the leave-one-task-out ("unseen instruction") folds."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from voxposer.errors import ConfigError
from voxposer.lmp.prompt import (
    API_MARKER,
    Example,
    check_fold,
    load_prompt,
    parse_prompt,
    prompt_names,
)
from voxposer.lmp.prompt_tags import TASK_NAMES, fold_prefix_id, lmp_of
from voxposer.lmp.registry import LMP_SPECS, LMPConfig

PROMPTS = Path(__file__).resolve().parents[2] / "src" / "voxposer" / "lmp" / "prompts"
ALL_PROMPTS = prompt_names()
TEXT = """### system
header
### user [tasks: push_to_pos, drop_to_pos]
# Query: a
### assistant
A
### user [tasks: none]
# Query: b
### assistant
B
### user [tasks: push_to_pos]
# Query: c
### assistant
C
"""


def test_task_names_are_the_benchmark_registry() -> None:
    from voxposer.bench.tasks import TASKS

    assert TASK_NAMES == tuple(TASKS)


def test_packaged_prompts_are_the_lmps_and_the_baseline() -> None:
    assert set(ALL_PROMPTS) == {*LMP_SPECS, "llm_primitives"}


def test_tags_are_kept_per_example() -> None:
    prompt = parse_prompt("p", TEXT)
    assert prompt.examples == (
        Example("# Query: a", "A", frozenset({"push_to_pos", "drop_to_pos"})),
        Example("# Query: b", "B", frozenset()),
        Example("# Query: c", "C", frozenset({"push_to_pos"})),
    )
    assert prompt.tasks == {"push_to_pos", "drop_to_pos"}


@pytest.mark.parametrize("marker, match", [
    ("### user [tasks: push_to_po]", r"unknown task 'push_to_po'.*tasks are: move_to_preposition, "
                                     r"move_to_pos_staying_on_preposition, .*, push_to_pos$"),
    ("### user", r"every example must say which benchmark tasks"),
    ("### user [tasks push_to_pos]", r"malformed section marker"),
    ("### user [tasks: push_to_pos", r"malformed section marker"),
    ("### user [tasks: push_to_pos] extra", r"malformed section marker"),
    ("###user [tasks: none]", r"malformed section marker"),
    ("### user [tasks: ]", r"empty task name"),
    ("### user [tasks: push_to_pos,]", r"empty task name"),
    ("### user [tasks: none, push_to_pos]", r"mixes 'none'"),
    ("### user [tasks: push_to_pos, push_to_pos]", r"names a task twice"),
    ("### assistant [tasks: none]", r"only '### user' lines carry"),
])
def test_bad_tag_lines_are_rejected_with_their_line(marker: str, match: str) -> None:
    text = TEXT.replace("### user [tasks: none]", marker)
    with pytest.raises(ConfigError, match=match) as info:
        parse_prompt("p", text)
    assert "prompt 'p' line 7" in str(info.value)


def test_without_task_removes_exactly_the_tagged_examples() -> None:
    prompt = parse_prompt("p", TEXT)
    fold = prompt.without_task("push_to_pos")
    assert fold.examples == (prompt.examples[1],)
    assert fold.system == prompt.system and fold.held_out == "push_to_pos"
    assert prompt.without_task("drop_to_pos").examples == prompt.examples[1:]
    assert prompt.without_task("close_drawer") is prompt  # nothing tagged: the default prompt
    with pytest.raises(ConfigError, match="unknown task 'nope'; tasks are: move_to_preposition"):
        prompt.without_task("nope")


@pytest.mark.parametrize("name", ALL_PROMPTS)
def test_without_task_on_every_packaged_prompt(name: str) -> None:
    prompt = load_prompt(name)
    for task in TASK_NAMES:
        fold = load_prompt(name, held_out_task=task)
        assert fold.examples == tuple(e for e in prompt.examples if task not in e.tasks)
        assert not any(task in e.tasks for e in fold.examples)
        assert fold.system == prompt.system
        removed = len(prompt.examples) - len(fold.examples)
        assert fold.prefix_id == (f"{name}~{task}" if removed else name)
        user_turns = {m.content for m in fold.messages("# Query: x") if m.role == "user"}
        for example in prompt.examples:
            assert (example.user in user_turns) == (task not in example.tasks), (task, example)


@pytest.mark.parametrize("name", ALL_PROMPTS)
def test_every_example_is_tagged_and_tags_stay_out_of_the_messages(name: str) -> None:
    text = (PROMPTS / f"{name}.txt").read_text(encoding="utf-8")
    users = re.findall(r"^### user.*$", text, re.MULTILINE)
    assert users and all(re.fullmatch(r"### user \[tasks: [a-z_, ]+\]", u) for u in users)
    # An independent reference rendering: split on marker lines, drop them, strip the turns.
    api = (PROMPTS / "api_reference.txt").read_text(encoding="utf-8").strip()
    parts = re.split(r"^### (?:system|user|assistant).*\n", text.replace(API_MARKER, api),
                     flags=re.MULTILINE)[1:]
    expected = [p.strip() for p in parts] + ["# Query: x"]
    messages = load_prompt(name).messages("# Query: x")
    assert [m.content for m in messages] == expected
    assert [m.role for m in messages] == ["system"] + ["user", "assistant"] * len(users) + ["user"]
    assert not any("[tasks:" in m.content or "### " in m.content for m in messages)


def test_tagged_examples_are_the_reviewed_ones() -> None:
    """A few tags the fold design rests on (see prompt_tags' rule), so a re-tag is deliberate."""
    def tags(name: str, query: str) -> frozenset[str]:
        (example,) = [e for e in load_prompt(name).examples if e.user.endswith(query)]
        return example.tasks

    assert tags("planner", "close the topmost drawer by pushing.") == {"close_drawer"}
    assert tags("composer", "back to default pose.") == set()
    assert tags("get_affordance_map", "a point at the center of the brown block.") == \
        {"grasp_at_velocity", "drop_to_pos"}
    assert tags("get_avoidance_map", "5cm around the pink block.") == \
        {"push_to_pos_avoid_obstacle"}
    assert tags("get_velocity_map", "half speed near the yellow block.") == \
        {"move_to_pos_velocity_near_obj"}
    assert tags("parse_query_obj", "blue block.") == set()
    assert tags("llm_primitives", "put the green block on the back side of the table.") == \
        {"drop_to_pos"}


@pytest.mark.parametrize("task", TASK_NAMES)
def test_every_packaged_fold_is_valid(task: str) -> None:
    folds = check_fold(task)
    assert set(folds) == set(ALL_PROMPTS)
    assert all(f.examples and task not in f.tasks for f in folds.values())


def write_prompts(directory: Path, planner_tags: str) -> None:
    directory.mkdir()
    (directory / "planner.txt").write_text(
        f"### system\nplan\n### user [tasks: {planner_tags}]\n# Query: push it\n### assistant\n"
        "composer('push it')\n", encoding="utf-8")
    (directory / "composer.txt").write_text(
        "### system\ncompose\n### user [tasks: none]\n# Query: q\n### assistant\nx = 1\n",
        encoding="utf-8")


def test_a_fold_that_empties_a_prompt_names_the_lmp_and_task(tmp_path: Path) -> None:
    write_prompts(tmp_path / "p", "push_to_pos")
    assert prompt_names(tmp_path / "p") == ("composer", "planner")
    with pytest.raises(ConfigError, match=r"'push_to_pos' leaves the prompt of LMP\(s\) planner "
                                          r"with no few-shot example"):
        check_fold("push_to_pos", tmp_path / "p")
    with pytest.raises(ConfigError, match=r"'push_to_pos' leaves the prompt of LMP 'planner'"):
        load_prompt("planner", tmp_path / "p", held_out_task="push_to_pos")
    assert set(check_fold("drop_to_pos", tmp_path / "p")) == {"composer", "planner"}
    with pytest.raises(ConfigError, match="unknown task 'x'; tasks are: "):
        check_fold("x", tmp_path / "p")


def test_lmp_config_validates_held_out_task() -> None:
    assert LMPConfig(held_out_task="push_to_pos").held_out_task == "push_to_pos"
    assert LMPConfig().held_out_task is None
    with pytest.raises(ConfigError, match=r"held_out_task .* got 'push'; tasks are: "
                                          r"move_to_preposition, .*, push_to_pos$"):
        LMPConfig(held_out_task="push")


def test_fold_prefix_ids_map_back_to_their_lmp() -> None:
    assert fold_prefix_id("composer", None) == "composer"
    assert fold_prefix_id("composer", "push_to_pos") == "composer~push_to_pos"
    assert lmp_of("composer~push_to_pos") == lmp_of("composer") == "composer"
    assert lmp_of(None) == ""
