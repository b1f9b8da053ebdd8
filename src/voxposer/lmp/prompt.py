"""Prompt files: a system header and few-shot examples, rendered as chat messages.

A prompt file (``prompts/<lmp>.txt``) is split by marker lines ``### system``, ``### user`` and
``### assistant``. The marker text ``<<API_REFERENCE>>`` is replaced by ``prompts/api_reference.txt``
(the shared Python-style API reference with the axis convention and direction table). Each
``user``/``assistant`` pair is one example; the query is appended as the last user message.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Final

from voxposer.errors import ConfigError
from voxposer.lmp.backends.base import ChatMessage

API_MARKER: Final = "<<API_REFERENCE>>"
#: First line of the user message that feeds an error back to the model (self-correction).
RETRY_PREFIX: Final = "Running your code failed:"
QUERY_PREFIX: Final = "# Query: "
_SECTION: Final = re.compile(r"^### (system|user|assistant)\s*$", re.MULTILINE)


@dataclass(frozen=True)
class Prompt:
    """A parsed prompt.

    Attributes:
        name: the LMP it belongs to.
        system: the system message (API reference and instructions).
        examples: (user, assistant) pairs, in file order.
    """

    name: str
    system: str
    examples: tuple[tuple[str, str], ...]

    def messages(self, query_message: str) -> tuple[ChatMessage, ...]:
        """System, the examples as alternating turns, then ``query_message`` as the last user turn."""
        out = [ChatMessage("system", self.system)]
        for user, assistant in self.examples:
            out += [ChatMessage("user", user), ChatMessage("assistant", assistant)]
        out.append(ChatMessage("user", query_message))
        return tuple(out)


def parse_prompt(name: str, text: str, api_reference: str = "") -> Prompt:
    """Parse prompt ``text`` (see module doc).

    Raises:
        ConfigError: no system section, or user/assistant turns that do not pair up.
    """
    text = text.replace(API_MARKER, api_reference.strip())
    parts = _SECTION.split(text)
    sections = [(parts[i], parts[i + 1].strip("\n")) for i in range(1, len(parts) - 1, 2)]
    if not sections or sections[0][0] != "system":
        raise ConfigError(f"prompt {name!r} must start with a '### system' section")
    turns = sections[1:]
    roles = [role for role, _ in turns]
    if roles != ["user", "assistant"] * (len(turns) // 2) or len(turns) % 2:
        raise ConfigError(f"prompt {name!r}: examples must alternate '### user' and "
                          f"'### assistant'; got {roles}")
    examples = tuple((turns[i][1].strip(), turns[i + 1][1].strip()) for i in range(0, len(turns), 2))
    return Prompt(name, sections[0][1].strip(), examples)


def load_prompt(name: str, directory: str | Path | None = None) -> Prompt:
    """Load ``<name>.txt`` from ``directory`` (default: the packaged ``voxposer/lmp/prompts``)."""
    if directory is None:
        root = resources.files("voxposer.lmp") / "prompts"
        text = (root / f"{name}.txt").read_text(encoding="utf-8")
        api = (root / "api_reference.txt").read_text(encoding="utf-8")
    else:
        d = Path(directory)
        if not (d / f"{name}.txt").is_file():
            raise ConfigError(f"no prompt file {name}.txt in {d}")
        text = (d / f"{name}.txt").read_text(encoding="utf-8")
        api_file = d / "api_reference.txt"
        api = api_file.read_text(encoding="utf-8") if api_file.is_file() else ""
    return parse_prompt(name, text, api)


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
