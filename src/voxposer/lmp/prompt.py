"""Prompt files: a system header and few-shot examples, rendered as chat messages.

A prompt file (``prompts/<lmp>.txt``) is split by marker lines ``### system``, ``### user [tasks:
...]`` and ``### assistant``. The marker text ``<<API_REFERENCE>>`` is replaced by
``prompts/api_reference.txt`` (the shared Python-style API reference with the axis convention and
direction table). Each ``user``/``assistant`` pair is one example; the query is appended as the
last user message. Every ``### user`` line says which benchmark tasks its example demonstrates
(see :mod:`voxposer.lmp.prompt_tags`); :meth:`Prompt.without_task` removes them for an "unseen
instruction" fold. Tags live on the marker lines, so the rendered messages do not contain them.

An LMP may also have an example *bank*, ``prompts/banks/<lmp>.txt`` (the same markers and tags,
no system section): :meth:`Prompt.messages` places the bank examples nearest to the query after
the fixed ones (:mod:`voxposer.lmp.retrieval`), and a fold leaves out the bank's examples of its
task too.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from importlib import resources
from pathlib import Path
from typing import Final

from voxposer.errors import ConfigError
from voxposer.lmp.backends.base import ChatMessage
from voxposer.lmp.example import Example
from voxposer.lmp.prompt_tags import MARKER_LIKE, check_task, fold_prefix_id, parse_marker
from voxposer.lmp.retrieval import ExampleBank, query_text

API_MARKER: Final = "<<API_REFERENCE>>"
API_FILE: Final = "api_reference.txt"
#: Sub-folder of a prompt directory with the example banks (``banks/<lmp>.txt``).
BANK_DIR: Final = "banks"
#: The bank of a prompt without one.
NO_BANK: Final = ExampleBank(())
#: First line of the user message that feeds an error back to the model (self-correction).
RETRY_PREFIX: Final = "Running your code failed:"
QUERY_PREFIX: Final = "# Query: "


@dataclass(frozen=True)
class Prompt:
    """A parsed prompt.

    Attributes:
        name: the LMP it belongs to.
        system: the system message (API reference and instructions).
        examples: the few-shot examples, in file order.
        held_out: the task whose examples :meth:`without_task` removed (None: the default
            prompt, or a fold that removed nothing from it).
        bank: more examples, chosen per query (:mod:`voxposer.lmp.retrieval`); empty: none.
    """

    name: str
    system: str
    examples: tuple[Example, ...]
    held_out: str | None = None
    bank: ExampleBank = NO_BANK

    @property
    def n_prefix_messages(self) -> int:
        """How many leading messages of :meth:`messages` are the same for every query (the
        system message and the fixed examples): the prefix a backend may keep evaluated."""
        return 1 + 2 * len(self.examples)

    def messages(self, query_message: str, retrieved: int = 0) -> tuple[ChatMessage, ...]:
        """System, the fixed examples, the ``retrieved`` bank examples nearest to the query
        (nearest last), each as a user and an assistant turn, then ``query_message`` as the
        last user turn."""
        chosen = self.bank.nearest(query_text(query_message), retrieved)
        out = [ChatMessage("system", self.system)]
        for example in self.examples + chosen:
            out += [ChatMessage("user", example.user), ChatMessage("assistant", example.assistant)]
        out.append(ChatMessage("user", query_message))
        return tuple(out)

    @property
    def tasks(self) -> frozenset[str]:
        """Every task some example demonstrates."""
        return frozenset().union(*(e.tasks for e in self.examples))

    @property
    def prefix_id(self) -> str:
        """The id backends keep this prompt's evaluated prefix under: the LMP name, or
        ``"<lmp>~<task>"`` for a fold that removed examples (its prefix text differs)."""
        return fold_prefix_id(self.name, self.held_out)

    def without_task(self, task: str) -> Prompt:
        """This prompt minus exactly the examples tagged with ``task``, fixed and banked (the
        "unseen instruction" fold of ``task``); ``self`` when none is tagged with it.

        Raises:
            ConfigError: ``task`` is not a benchmark task (the message lists them), or every
                example is tagged with it (the fold would leave no example).
        """
        check_task(task)
        kept = tuple(e for e in self.examples if task not in e.tasks)
        bank = self.bank.without_task(task)
        if len(kept) == len(self.examples) and bank is self.bank:
            return self
        if not kept:
            raise ConfigError(f"holding out task {task!r} leaves the prompt of LMP "
                              f"{self.name!r} with no few-shot example: all "
                              f"{len(self.examples)} are tagged with it; add an example that "
                              f"does not demonstrate {task!r}")
        if len(kept) == len(self.examples):  # only the bank lost examples: same prefix
            return replace(self, bank=bank)
        held = task if self.held_out is None else f"{self.held_out}+{task}"
        return replace(self, examples=kept, held_out=held, bank=bank)


def _sections(name: str, text: str, api: str) -> list[tuple[str, frozenset[str], str]]:
    """(role, tasks, body) of each marked section of ``text``."""
    markers = list(MARKER_LIKE.finditer(text))
    sections: list[tuple[str, frozenset[str], str]] = []
    for i, m in enumerate(markers):
        where = f"prompt {name!r} line {text.count(chr(10), 0, m.start()) + 1}"
        role, tasks = parse_marker(m.group(0), where)
        end = markers[i + 1].start() if i + 1 < len(markers) else len(text)
        sections.append((role, tasks, text[m.end():end].replace(API_MARKER, api).strip()))
    return sections


def _examples(name: str, turns: list[tuple[str, frozenset[str], str]]) -> tuple[Example, ...]:
    roles = [role for role, _, _ in turns]
    if roles != ["user", "assistant"] * (len(turns) // 2) or len(turns) % 2:
        raise ConfigError(f"prompt {name!r}: examples must alternate '### user' and "
                          f"'### assistant'; got {roles}")
    return tuple(Example(turns[i][2], turns[i + 1][2], turns[i][1])
                 for i in range(0, len(turns), 2))


def parse_prompt(name: str, text: str, api_reference: str = "") -> Prompt:
    """Parse prompt ``text`` (see module doc).

    Raises:
        ConfigError: no system section, user/assistant turns that do not pair up, or a
            malformed marker line or task tag (:func:`~voxposer.lmp.prompt_tags.parse_marker`).
    """
    sections = _sections(name, text, api_reference.strip())
    if not sections or sections[0][0] != "system":
        raise ConfigError(f"prompt {name!r} must start with a '### system' section")
    return Prompt(name, sections[0][2], _examples(name, sections[1:]))


def parse_bank(name: str, text: str) -> ExampleBank:
    """Parse the example bank ``text`` of LMP ``name``: tagged user/assistant examples only.

    Raises:
        ConfigError: a system section, turns that do not pair up, or a malformed marker line.
    """
    sections = _sections(f"{name} bank", text, "")
    if any(role == "system" for role, _, _ in sections):
        raise ConfigError(f"the example bank of LMP {name!r} has a '### system' section; a bank "
                          "holds only '### user' / '### assistant' examples")
    return ExampleBank(_examples(f"{name} bank", sections))


def load_prompt(name: str, directory: str | Path | None = None,
                held_out_task: str | None = None) -> Prompt:
    """Load ``<name>.txt`` from ``directory`` (default: the packaged ``voxposer/lmp/prompts``).

    Args:
        held_out_task: a benchmark task whose examples are removed (its "unseen instruction"
            fold, :meth:`Prompt.without_task`); None keeps every example.
    """
    if held_out_task is not None:
        check_task(held_out_task)
    root = resources.files("voxposer.lmp") / "prompts" if directory is None else Path(directory)
    if not (root / f"{name}.txt").is_file():
        raise ConfigError(f"no prompt file {name}.txt in {root}")
    text = (root / f"{name}.txt").read_text(encoding="utf-8")
    api_file = root / API_FILE
    api = api_file.read_text(encoding="utf-8") if api_file.is_file() else ""
    prompt = parse_prompt(name, text, api)
    bank_file = root / BANK_DIR / f"{name}.txt"
    if bank_file.is_file():
        prompt = replace(prompt, bank=parse_bank(name, bank_file.read_text(encoding="utf-8")))
    return prompt if held_out_task is None else prompt.without_task(held_out_task)


def prompt_names(directory: str | Path | None = None) -> tuple[str, ...]:
    """The LMP prompts in ``directory`` (default: the packaged ones), sorted: every ``*.txt``
    except the shared API reference."""
    root = resources.files("voxposer.lmp") / "prompts" if directory is None else Path(directory)
    return tuple(sorted(p.name[:-4] for p in root.iterdir()
                        if p.name.endswith(".txt") and p.name != API_FILE))


def check_fold(task: str, prompt_dir: str | Path | None = None) -> dict[str, Prompt]:
    """Load every prompt of ``prompt_dir`` (:func:`prompt_names`) for the fold holding out
    ``task``; call before running the fold so a broken one fails before any episode.

    Returns:
        LMP name → its prompt in the fold.

    Raises:
        ConfigError: ``task`` is unknown (lists the tasks), or the fold leaves some prompt with
            no example (names every such LMP and the task).
    """
    check_task(task)
    out: dict[str, Prompt] = {}
    empty: list[str] = []
    for name in prompt_names(prompt_dir):
        prompt = load_prompt(name, prompt_dir)
        if prompt.examples and all(task in e.tasks for e in prompt.examples):
            empty.append(name)
        else:
            out[name] = prompt.without_task(task)
    if empty:
        raise ConfigError(f"the fold holding out task {task!r} leaves the prompt of LMP(s) "
                          f"{', '.join(empty)} with no few-shot example; every example there "
                          f"is tagged with {task!r}")
    return out


def request_query(messages: Sequence[ChatMessage]) -> tuple[str, int]:
    """(query, attempt) of a request built by the LMP runtime.

    ``attempt`` is 1 plus the number of self-correction turns at the end of the conversation;
    the query is the text after the last ``# Query:`` of the user message that asked it.
    """
    attempt, i = 1, len(messages) - 1
    while (i >= 2 and messages[i].role == "user" and messages[i].content.startswith(RETRY_PREFIX)
           and messages[i - 1].role == "assistant"):
        attempt += 1
        i -= 2
    text = messages[i].content if messages else ""
    lines = [ln for ln in text.splitlines() if ln.startswith(QUERY_PREFIX)]
    query = lines[-1][len(QUERY_PREFIX):].strip() if lines else text.strip()
    return query, attempt
